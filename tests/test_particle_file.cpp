// The particle file: round trip, atomic write, every rejection the reader
// promises (docs/formats.md), and the .vtp view opened by VTK's own reader.
#include <unistd.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "checksum.hpp"
#include "error.hpp"
#include "particle_file.hpp"
#include "vtk_output.hpp"

namespace fs = std::filesystem;

namespace {

// One folder per test process: CTest runs the test cases in parallel.
std::string temp_dir() {
  const auto dir = fs::path(PD_TEST_TMPDIR) / std::to_string(::getpid());
  fs::create_directories(dir);
  return dir.string();
}
std::string temp_path(const std::string& name) { return (fs::path(temp_dir()) / name).string(); }

// A 3 x 3 lattice of unit squares (spacing 1 mm) with full families; enough
// structure for every section of the format.
pd::ParticleSet small_lattice() {
  pd::ParticleSet p;
  p.spacing = 1e-3;
  p.horizon_nominal = 1.5e-3;
  p.xmin = 0, p.ymin = 0, p.xmax = 3e-3, p.ymax = 3e-3;
  p.resize(9);
  p.cell_offsets.push_back(0);
  p.family_offsets.push_back(0);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int k = 3 * j + i;
      p.x[k] = (i + 0.5) * 1e-3;
      p.y[k] = (j + 0.5) * 1e-3;
      p.volume[k] = 1e-6;
      p.cell_size[k] = 1e-3;
      p.horizon[k] = 1.5e-3;
      p.region[k] = static_cast<std::uint8_t>(pd::Region::uniform_square);
      p.material[k] = 0;
      const double cx[4] = {i * 1e-3, (i + 1) * 1e-3, (i + 1) * 1e-3, i * 1e-3};
      const double cy[4] = {j * 1e-3, j * 1e-3, (j + 1) * 1e-3, (j + 1) * 1e-3};
      for (int v = 0; v < 4; ++v) {
        p.cell_vx.push_back(cx[v]);
        p.cell_vy.push_back(cy[v]);
      }
      p.cell_offsets.push_back(p.cell_vx.size());
      for (int m = 0; m < 9; ++m)
        if (m != k) {
          p.neighbors.push_back(m);
          p.partial_volume.push_back(m % 2 ? 0.5 : 1.0);
        }
      p.family_offsets.push_back(p.neighbors.size());
    }
  p.sets.push_back({"left", {0, 3, 6}});
  p.sets.push_back({"top", {6, 7, 8}});
  p.provenance = "{\"tool\": \"test\"}";
  return p;
}

std::vector<char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

void dump(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Header layout offsets (docs/formats.md).
constexpr std::size_t version_offset = 8, particle_count_offset = 16, payload_checksum_offset = 112,
                      header_checksum_offset = 120, header_size = 128;

void reseal_header(std::vector<char>& bytes) {
  const std::uint64_t h = pd::checksum_of(bytes.data(), header_checksum_offset);
  std::memcpy(bytes.data() + header_checksum_offset, &h, 8);
}
void reseal_payload(std::vector<char>& bytes) {
  const std::uint64_t c = pd::checksum_of(bytes.data() + header_size, bytes.size() - header_size);
  std::memcpy(bytes.data() + payload_checksum_offset, &c, 8);
  reseal_header(bytes);
}

std::string read_error(const std::string& path) {
  try {
    pd::read_particle_file(path);
  } catch (const pd::Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("particle file round trip is exact", "[particle-file]") {
  const auto original = small_lattice();
  const auto path = temp_path("roundtrip.pdp");
  pd::write_particle_file(path, original);
  const auto back = pd::read_particle_file(path);
  CHECK(back.size() == 9);
  CHECK(back.x == original.x);
  CHECK(back.y == original.y);
  CHECK(back.volume == original.volume);
  CHECK(back.cell_vx == original.cell_vx);
  CHECK(back.family_offsets == original.family_offsets);
  CHECK(back.neighbors == original.neighbors);
  CHECK(back.partial_volume == original.partial_volume);
  REQUIRE(back.sets.size() == 2);
  CHECK(back.sets[1].name == "top");
  CHECK(back.sets[1].particles == original.sets[1].particles);
  CHECK(back.provenance == original.provenance);
  CHECK(back.spacing == original.spacing);
  CHECK(back.horizon_nominal == original.horizon_nominal);
  // Writing again gives the same bytes (determinism).
  const auto again = temp_path("roundtrip2.pdp");
  pd::write_particle_file(again, back);
  CHECK(slurp(path) == slurp(again));
  // No temporary file left behind.
  for (const auto& entry : fs::directory_iterator(temp_dir()))
    CHECK(entry.path().filename().string().find(".tmp.") == std::string::npos);
}

TEST_CASE("particle file reader rejects damaged files with a clear message", "[particle-file]") {
  const auto path = temp_path("good.pdp");
  pd::write_particle_file(path, small_lattice());
  const auto good = slurp(path);
  const auto bad = temp_path("bad.pdp");

  SECTION("wrong magic") {
    auto b = good;
    b[0] = 'X';
    dump(bad, b);
    CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("wrong magic"));
  }
  SECTION("unknown version") {
    auto b = good;
    const std::uint32_t v = 99;
    std::memcpy(b.data() + version_offset, &v, 4);
    reseal_header(b);
    dump(bad, b);
    CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("unknown format version 99"));
  }
  SECTION("truncated inside the header") {
    dump(bad, std::vector<char>(good.begin(), good.begin() + 50));
    CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("truncated"));
  }
  SECTION("truncated inside the payload") {
    dump(bad, std::vector<char>(good.begin(), good.end() - 100));
    CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("truncated"));
  }
  SECTION("empty file") {
    dump(bad, {});
    CHECK_THAT(read_error(bad), Catch::Contains("truncated"));
  }
  SECTION("bad payload checksum") {
    auto b = good;
    b[header_size + 10] ^= 0x40;
    dump(bad, b);
    CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("checksum mismatch"));
  }
  SECTION("bad header checksum") {
    auto b = good;
    b[60] ^= 0x01;  // inside the spacing value
    dump(bad, b);
    CHECK_THAT(read_error(bad), Catch::Contains("header checksum mismatch"));
  }
  SECTION("inconsistent counts") {
    auto b = good;
    const std::uint64_t n = 10;  // one particle more than the arrays hold
    std::memcpy(b.data() + particle_count_offset, &n, 8);
    reseal_header(b);
    dump(bad, b);
    CHECK_THAT(read_error(bad), Catch::Contains(bad) &&
                                    (Catch::Contains("inconsistent") || Catch::Contains("truncated")));
  }
  SECTION("non-finite value") {
    auto b = good;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(b.data() + header_size + 8 * 4, &nan, 8);  // x[4]
    reseal_payload(b);
    dump(bad, b);
    CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("non-finite value in x[4]"));
  }
  SECTION("trailing garbage") {
    auto b = good;
    b.push_back(0);
    dump(bad, b);
    CHECK_THAT(read_error(bad), Catch::Contains("trailing bytes"));
  }
  SECTION("missing file") {
    CHECK_THAT(read_error(temp_path("does-not-exist.pdp")), Catch::Contains("cannot open"));
  }
}

TEST_CASE("writer refuses an inconsistent particle set", "[particle-file]") {
  auto p = small_lattice();
  p.neighbors[3] = 42;
  CHECK_THROWS_WITH(pd::write_particle_file(temp_path("never.pdp"), p),
                    Catch::Contains("neighbour index out of range"));
  CHECK_FALSE(fs::exists(temp_path("never.pdp")));
}

TEST_CASE("particle .vtp opens in VTK's reader with the documented arrays", "[particle-file][vtk]") {
  const auto p = small_lattice();
  const auto path = temp_path("lattice.vtp");
  pd::write_particles_vtp(path, p);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  REQUIRE(poly->GetNumberOfPoints() == 9);
  for (const char* name : {"volume", "region", "horizon", "neighbors", "neighborhood_area"})
    REQUIRE(poly->GetPointData()->GetArray(name) != nullptr);
  CHECK(poly->GetPointData()->GetArray("neighbors")->GetTuple1(0) == 8);
  // Particle 0's family: 8 squares of 1e-6 m^2, odd indices with factor 0.5
  // (1, 3, 5, 7) -> 4 * 1e-6 + 4 * 0.5e-6 = 6e-6.
  CHECK(poly->GetPointData()->GetArray("neighborhood_area")->GetTuple1(0) == Approx(6e-6));
  double point[3];
  poly->GetPoint(4, point);
  CHECK(point[0] == Approx(1.5e-3));
}
