// The particle file: round trip, atomic write, every rejection the reader
// promises (docs/formats.md), and the .vtp view opened by VTK's own reader.
#include <unistd.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
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

// A 3 x 3 lattice of 1 mm squares with full families (a horizon of 2.2 mm
// reaches the far corner's cell); enough structure for every section of the format.
pd::ParticleSet small_lattice() {
  pd::ParticleSet p;
  p.spacing = 1e-3;
  p.horizon_nominal = 2.2e-3;
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
      p.horizon[k] = 2.2e-3;
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
constexpr std::size_t version_offset = 8, particle_count_offset = 16, set_count_offset = 40,
                      payload_checksum_offset = 112, header_checksum_offset = 120, header_size = 128;

void reseal_header(std::vector<char>& bytes) {
  const std::uint64_t h = pd::checksum_of(bytes.data(), header_checksum_offset);
  std::memcpy(bytes.data() + header_checksum_offset, &h, 8);
}
void reseal_payload(std::vector<char>& bytes) {
  const std::uint64_t c = pd::checksum_of(bytes.data() + header_size, bytes.size() - header_size);
  std::memcpy(bytes.data() + payload_checksum_offset, &c, 8);
  reseal_header(bytes);
}

template <class Read>
std::string error_of(const Read& read) {
  try {
    read();
  } catch (const pd::Error& e) {
    return e.what();
  }
  return "no error";
}

void ignore_family(const pd::ParticleSet&, std::uint32_t, const std::uint32_t*, const double*, std::size_t) {}

// The message of the error the reader gives for `path`; the streaming reader
// must give the same one.
std::string read_error(const std::string& path) {
  const auto whole = error_of([&] { pd::read_particle_file(path); });
  const auto streamed = error_of([&] { pd::read_particle_file(path, ignore_family); });
  CHECK(streamed == whole);
  return whole;
}

// `n` thin rectangular cells side by side in a strip 1 mm high (cells of a
// free grid: region "other", cell size sqrt(volume)), all within one horizon
// of each other, with families that cross the streaming reader's chunk
// boundaries: families of 0 to 12 neighbours, and particle n/2 with every
// other particle as neighbour, more than one chunk on its own when
// n > family_read_chunk_bonds.
pd::ParticleSet many_bonds(std::uint32_t n) {
  const double dx = 1e-3, width = dx / 2048;  // n <= 71680 cells fill at most 35 dx
  pd::ParticleSet p;
  p.grid = pd::GridKind::free;
  p.spacing = dx;
  p.horizon_nominal = 40 * dx;
  p.xmin = 0, p.ymin = 0, p.xmax = 35 * dx, p.ymax = dx;
  p.resize(n);
  p.cell_offsets.push_back(0);
  p.family_offsets.push_back(0);
  std::vector<std::uint32_t> family;
  for (std::uint32_t i = 0; i < n; ++i) {
    p.x[i] = (i + 0.5) * width;
    p.y[i] = 0.5 * dx;
    p.volume[i] = width * dx;
    p.cell_size[i] = std::sqrt(p.volume[i]);
    p.horizon[i] = p.horizon_nominal;
    p.region[i] = static_cast<std::uint8_t>(pd::Region::other);
    p.material[i] = 0;
    for (const double vx : {i * width, (i + 1) * width, (i + 1) * width, i * width}) p.cell_vx.push_back(vx);
    for (const double vy : {0.0, 0.0, dx, dx}) p.cell_vy.push_back(vy);
    p.cell_offsets.push_back(p.cell_vx.size());
    family.clear();
    if (i == n / 2) {
      for (std::uint32_t j = 0; j < n; ++j)
        if (j != i) family.push_back(j);
    } else {
      for (std::uint32_t s = 1; s <= i % 13; ++s) family.push_back((i + s * 5) % n);
      std::sort(family.begin(), family.end());
    }
    for (auto j : family) {
      p.neighbors.push_back(j);
      p.partial_volume.push_back((1 + (i * 7919ull + j) % 997) / 997.0);
    }
    p.family_offsets.push_back(p.neighbors.size());
  }
  p.sets.push_back({"left", {0, 1, 2}});
  p.sets.push_back({"right", {n - 1}});
  p.provenance = "{\"tool\": \"test\", \"case\": \"many bonds\"}";
  return p;
}

// Byte offsets of the bond sections in a file of many_bonds(n): the
// per-particle arrays, two offset arrays and 4 cell vertices per particle.
std::size_t neighbors_offset(std::size_t n) {
  return header_size + n * (5 * 8 + 1 + 2) + 2 * (n + 1) * 8 + 2 * (4 * n) * 8;
}
std::size_t partial_volume_offset(std::size_t n, std::size_t bonds) {
  return neighbors_offset(n) + 4 * bonds;
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
  SECTION("another file of the pipeline, named for what it is, whatever its length") {
    // Before 7 December 2026: "wrong magic number", or "truncated" for a
    // file shorter than the header.
    const auto geometry = temp_path("plate.geo");
    const std::string geometry_text = "Point(1) = {0, 0, 0};\n";
    dump(geometry, std::vector<char>(geometry_text.begin(), geometry_text.end()));
    CHECK(read_error(geometry) == geometry + ": a gmsh geometry, not a particle file: pd-mesh meshes it into one "
                                             "(docs/mesher.md)");
    const auto scene = temp_path("scene.toml");
    const std::string scene_text = "particles = \"plate.pdp\"\n" + std::string(4000, '#');
    dump(scene, std::vector<char>(scene_text.begin(), scene_text.end()));
    CHECK_THAT(read_error(scene), Catch::Contains(scene + ": a scene (TOML), not a particle file"));
    // A real particle file cut short is still truncated.
    dump(bad, std::vector<char>(good.begin(), good.begin() + 5));
    CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("truncated: 5 bytes"));
  }
  SECTION("a packed particle file or a Git LFS pointer, named with what to do") {
    // Before 7 December 2026: "not a particle file (wrong magic number;
    // expected 'PDPARTS')", what to do unsaid.
    const auto packed = temp_path("packed.pdp");
    const std::vector<std::pair<std::string, std::string>> heads{
        {std::string("\x1F\x8B\x08\x00\x00\x00\x00\x00", 8), "a gzip-compressed file, not a particle file: unpack it "
                                                             "(gunzip) and give the .pdp it holds"},
        {std::string("\xFD" "7zXZ\0\0\x04", 8), "an xz-compressed file, not a particle file: unpack it (unxz)"},
        {"\x28\xB5\x2F\xFD\x24\x00\x00\x00", "a zstd-compressed file, not a particle file: unpack it (unzstd)"},
        {"BZh91AY&SY", "a bzip2-compressed file, not a particle file: unpack it (bunzip2)"},
        {"PK\x03\x04\x14\x00\x00\x00", "a zip-compressed file, not a particle file: unpack it (unzip)"},
        {"version https://git-lfs.github.com/spec/v1\noid sha256:4d7a\nsize 2850000\n",
         "a text file (a Git LFS pointer?), not a particle file: fetch the file itself (git lfs pull)"}};
    for (const auto& [head, message] : heads) {
      dump(packed, std::vector<char>(head.begin(), head.end()));
      CHECK(read_error(packed).rfind(packed + ": " + message, 0) == 0);
    }
    // Any other bytes: the magic, and what to give.
    const std::string other(300, '\0');
    dump(packed, std::vector<char>(other.begin(), other.end()));
    CHECK(read_error(packed) == packed + ": not a particle file (wrong magic number; expected 'PDPARTS'): give the "
                                         ".pdp file that pd-mesh wrote, or mesh it again (docs/mesher.md)");
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
    // The two readers find this at different sections.
    const auto whole = error_of([&] { pd::read_particle_file(bad); });
    const auto streamed = error_of([&] { pd::read_particle_file(bad, ignore_family); });
    for (const auto& message : {whole, streamed})
      CHECK_THAT(message,
                 Catch::Contains(bad) && (Catch::Contains("inconsistent") || Catch::Contains("truncated")));
  }
  SECTION("set count beyond the payload") {
    auto b = good;
    const std::uint32_t sets = 0x7fffffff;  // checked before any set is allocated
    std::memcpy(b.data() + set_count_offset, &sets, 4);
    reseal_header(b);
    dump(bad, b);
    CHECK_THAT(read_error(bad),
               Catch::Contains(bad) && Catch::Contains("inconsistent counts while reading sets"));
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

TEST_CASE("streaming reader visits the same families as the reader", "[particle-file]") {
  const std::uint32_t n = 70000;
  const auto original = many_bonds(n);
  REQUIRE(original.bond_count() > 4 * pd::family_read_chunk_bonds);
  const auto path = temp_path("many_bonds.pdp");
  pd::write_particle_file(path, original);
  const auto whole = pd::read_particle_file(path);

  std::vector<std::uint64_t> offsets{0};
  std::vector<std::uint32_t> neighbors;
  std::vector<double> factors;
  std::uint32_t next_particle = 0;
  bool in_order = true;
  const auto streamed = pd::read_particle_file(
      path, [&](const pd::ParticleSet&, std::uint32_t particle, const std::uint32_t* nb, const double* phi, std::size_t count) {
        in_order = in_order && particle == next_particle++;
        neighbors.insert(neighbors.end(), nb, nb + count);
        factors.insert(factors.end(), phi, phi + count);
        offsets.push_back(neighbors.size());
      });
  CHECK(in_order);
  CHECK(next_particle == n);
  CHECK(offsets == whole.family_offsets);
  CHECK(neighbors == whole.neighbors);
  REQUIRE(factors.size() == whole.partial_volume.size());
  CHECK(std::memcmp(factors.data(), whole.partial_volume.data(), factors.size() * sizeof(double)) == 0);

  CHECK(streamed.neighbors.empty());
  CHECK(streamed.partial_volume.empty());
  CHECK(streamed.family_offsets == whole.family_offsets);
  CHECK(streamed.x == whole.x);
  CHECK(streamed.y == whole.y);
  CHECK(streamed.volume == whole.volume);
  CHECK(streamed.cell_size == whole.cell_size);
  CHECK(streamed.horizon == whole.horizon);
  CHECK(streamed.region == whole.region);
  CHECK(streamed.material == whole.material);
  CHECK(streamed.cell_offsets == whole.cell_offsets);
  CHECK(streamed.cell_vx == whole.cell_vx);
  CHECK(streamed.cell_vy == whole.cell_vy);
  REQUIRE(streamed.sets.size() == whole.sets.size());
  for (std::size_t s = 0; s < whole.sets.size(); ++s) {
    CHECK(streamed.sets[s].name == whole.sets[s].name);
    CHECK(streamed.sets[s].particles == whole.sets[s].particles);
  }
  CHECK(streamed.provenance == whole.provenance);
  CHECK(streamed.grid == whole.grid);
  CHECK(streamed.quadrature == whole.quadrature);
  CHECK(streamed.spacing == whole.spacing);
  CHECK(streamed.horizon_nominal == whole.horizon_nominal);
  CHECK((streamed.xmin == whole.xmin && streamed.ymin == whole.ymin && streamed.xmax == whole.xmax &&
         streamed.ymax == whole.ymax));

  // The small lattice: fewer bonds than one chunk.
  const auto small_path = temp_path("small_streamed.pdp");
  pd::write_particle_file(small_path, small_lattice());
  std::vector<std::uint32_t> small_neighbors;
  pd::read_particle_file(small_path,
                         [&](const pd::ParticleSet&, std::uint32_t, const std::uint32_t* nb, const double*, std::size_t count) {
                           small_neighbors.insert(small_neighbors.end(), nb, nb + count);
                         });
  CHECK(small_neighbors == small_lattice().neighbors);
}

TEST_CASE("streaming reader rejects damaged families with a clear message", "[particle-file]") {
  const std::uint32_t n = 70000;
  const auto original = many_bonds(n);
  const std::size_t bonds = original.bond_count();
  const auto path = temp_path("many_bonds_good.pdp");
  pd::write_particle_file(path, original);
  const auto good = slurp(path);
  REQUIRE(good.size() > partial_volume_offset(n, bonds) + 8 * bonds);
  const auto bad = temp_path("many_bonds_bad.pdp");

  // A bond in a late chunk, so that families before it are visited first.
  const std::size_t k = bonds - 1000;
  std::uint64_t bonds_visited = 0;
  const auto stream_error = [&](const std::string& file) {
    bonds_visited = 0;
    return error_of([&] {
      pd::read_particle_file(file, [&](const pd::ParticleSet&, std::uint32_t, const std::uint32_t*, const double*,
                                       std::size_t count) { bonds_visited += count; });
    });
  };

  SECTION("corrupted byte in partial_volume") {
    auto b = good;
    b[partial_volume_offset(n, bonds) + 8 * k] ^= 0x01;  // lowest mantissa byte: still a valid factor
    dump(bad, b);
    CHECK_THAT(stream_error(bad), Catch::Contains(bad) && Catch::Contains("checksum mismatch"));
    b[partial_volume_offset(n, bonds) + 8 * k + 7] ^= 0x40;  // exponent: far above 1
    dump(bad, b);
    CHECK_THAT(stream_error(bad),
               Catch::Contains(bad) && Catch::Contains("partial_volume[" + std::to_string(k) + "]"));
    CHECK(bonds_visited <= k);  // the family holding the bad bond was not visited
  }
  SECTION("corrupted byte in neighbors") {
    auto b = good;
    b[neighbors_offset(n) + 4 * k] ^= 0x01;  // lowest byte: still in range
    dump(bad, b);
    CHECK_THAT(stream_error(bad), Catch::Contains(bad) && Catch::Contains("checksum mismatch"));
    b[neighbors_offset(n) + 4 * k + 3] ^= 0x80;  // highest byte: out of range
    dump(bad, b);
    CHECK_THAT(stream_error(bad),
               Catch::Contains(bad) && Catch::Contains("neighbors[" + std::to_string(k) + "]"));
    CHECK(bonds_visited <= k);
  }
  SECTION("truncated file") {
    dump(bad, std::vector<char>(good.begin(), good.begin() + partial_volume_offset(n, bonds) + 8 * k));
    CHECK_THAT(stream_error(bad), Catch::Contains(bad) && Catch::Contains("truncated"));
    CHECK(bonds_visited == 0);  // found from the file size, before any family
  }
  SECTION("out-of-range neighbour in a resealed file") {
    auto b = good;
    std::memcpy(b.data() + neighbors_offset(n) + 4 * k, &n, 4);
    reseal_payload(b);
    dump(bad, b);
    const auto message = stream_error(bad);
    const auto expected = "neighbour index out of range at neighbors[" + std::to_string(k) + "] = " +
                          std::to_string(n);
    CHECK_THAT(message, Catch::Contains(bad) && Catch::Contains(expected));
    CHECK(message == read_error(bad));
    CHECK(bonds_visited <= k);
  }
  SECTION("partial volume above 1 in a resealed file") {
    auto b = good;
    const double phi = 1.5;
    std::memcpy(b.data() + partial_volume_offset(n, bonds) + 8 * k, &phi, 8);
    reseal_payload(b);
    dump(bad, b);
    const auto message = stream_error(bad);
    CHECK_THAT(message,
               Catch::Contains(bad) && Catch::Contains("partial_volume[" + std::to_string(k) + "] = 1.5"));
    CHECK(message == read_error(bad));
  }
  SECTION("defect before the families: nothing visited") {
    auto b = good;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(b.data() + header_size + 8 * 7, &nan, 8);  // x[7]
    reseal_payload(b);
    dump(bad, b);
    CHECK_THAT(stream_error(bad), Catch::Contains(bad) && Catch::Contains("non-finite value in x[7]"));
    CHECK(bonds_visited == 0);
  }
  SECTION("bad set after the families") {
    auto b = good;
    // The last set ("right", one particle) ends just before the provenance.
    const std::size_t provenance_bytes = 8 + original.provenance.size();
    std::memcpy(b.data() + b.size() - provenance_bytes - 4, &n, 4);
    reseal_payload(b);
    dump(bad, b);
    CHECK_THAT(stream_error(bad), Catch::Contains(bad) && Catch::Contains("set 'right' refers to particle"));
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

namespace {

// Byte offsets of the payload sections of a file with n particles, c cell
// vertices and b bonds (docs/formats.md, "Payload").
struct Layout {
  std::size_t x, y, volume, cell_size, horizon, region, material, cell_offsets, cell_vx, cell_vy, family_offsets,
      neighbors, partial_volume, sets;
  Layout(std::size_t n, std::size_t c, std::size_t b) {
    x = header_size;
    y = x + 8 * n;
    volume = y + 8 * n;
    cell_size = volume + 8 * n;
    horizon = cell_size + 8 * n;
    region = horizon + 8 * n;
    material = region + n;
    cell_offsets = material + 2 * n;
    cell_vx = cell_offsets + 8 * (n + 1);
    cell_vy = cell_vx + 8 * c;
    family_offsets = cell_vy + 8 * c;
    neighbors = family_offsets + 8 * (n + 1);
    partial_volume = neighbors + 4 * b;
    sets = partial_volume + 8 * b;
  }
};

template <class T>
void put(std::vector<char>& bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof value);
}
template <class T>
T get(const std::vector<char>& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

// Header offsets of the grid description.
constexpr std::size_t reserved_offset = 46, spacing_offset = 56, horizon_offset = 64, bbox_offset = 72;

}  // namespace

// Files a buggy writer could make: every section is well formed and the
// checksums match, but the values break an invariant of docs/formats.md.
// Each must be refused with the same message by both readers, naming the
// file and the offending value, before the solver sees it.
TEST_CASE("particle file reader refuses resealed files that break the format's invariants", "[particle-file]") {
  const auto original = small_lattice();
  const auto path = temp_path("invariants_good.pdp");
  pd::write_particle_file(path, original);
  const auto good = slurp(path);
  const Layout at(original.size(), original.cell_vx.size(), original.bond_count());
  REQUIRE(good.size() > at.sets);
  REQUIRE(get<double>(good, at.x + 8 * 4) == original.x[4]);
  REQUIRE(get<std::uint32_t>(good, at.neighbors) == original.neighbors[0]);
  const auto bad = temp_path("invariants_bad.pdp");
  // Refused with a message containing `expected` (both readers, same message).
  const auto refused = [&](std::vector<char> bytes, const std::string& expected) {
    reseal_payload(bytes);
    dump(bad, bytes);
    const auto message = read_error(bad);
    CHECK_THAT(message, Catch::Contains(bad) && Catch::Contains(expected));
  };
  auto b = good;

  SECTION("tiny per-particle horizon") {
    put(b, at.horizon + 8 * 3, 1e-12);
    refused(b, "horizon[3] = 1e-12 m, expected between the spacing");
  }
  SECTION("horizon above the nominal one") {
    put(b, at.horizon + 8 * 3, 3e-3);
    refused(b, "horizon[3] = 0.003 m");
  }
  SECTION("a bond longer than the horizon plus the neighbour's cell reach") {
    put(b, at.horizon, 1e-3);  // particle 0 keeps its family up to the far corner 2.83 mm away
    refused(b, "the bond 0 -> 2 (neighbors[1]) is 0.002 m long, more than the horizon 0.001 m plus the "
               "neighbour's cell reach 0.000707106781 m");
  }
  SECTION("absurd spacing in the header") {
    put(b, spacing_offset, 1e-300);
    refused(b, "spacing dx = 1e-300 m, expected 1e-09 to 1000 m");
  }
  SECTION("nominal horizon of millions of spacings") {
    put(b, horizon_offset, 1e3);
    refused(b, "nominal horizon delta = 1000 m, expected 1 to 64 spacings");
  }
  SECTION("bounding box of a huge lattice") {
    put(b, bbox_offset + 16, 1e3);  // xmax: a million spacings for 9 particles
    refused(b, "the bounding box is 1000000 x 3 spacings for 9 particles, more than 64 lattice cells per particle");
  }
  SECTION("bounding box far from the origin") {
    put(b, bbox_offset + 16, 1e300);
    refused(b, "bounding box coordinate 1e+300 m is more than 1e+09 spacings from the origin");
  }
  SECTION("bounding box not a whole number of spacings") {
    put(b, bbox_offset + 16, 3.5e-3);
    refused(b, "bounding box width 0.0035 m is not a whole number of spacings");
  }
  SECTION("empty bounding box") {
    put(b, bbox_offset + 8, 3e-3);  // ymin = ymax
    refused(b, "bounding box height 0 m is not a whole number of spacings");
  }
  SECTION("reserved header field in use") {
    put<std::uint16_t>(b, reserved_offset, 7);
    refused(b, "reserved header field is 7, not 0");
  }
  SECTION("particle far outside the bounding box, its cell with it") {
    put(b, at.x + 8 * 4, 1.0015);
    for (int v = 0; v < 4; ++v) put(b, at.cell_vx + 8 * (16 + v), original.cell_vx[16 + v] + 1.0);
    refused(b, "particle 4 at (1.0015, 0.0015) m lies outside the bounding box [0, 0.003] x [0, 0.003] m");
  }
  SECTION("particle away from its cell") {
    put(b, at.x + 8 * 4, 1.8e-3);
    refused(b, "particle 4 at (0.0018, 0.0015) m is 0.0003 m from its cell's centroid");
  }
  SECTION("vanishing and enormous volumes of lattice squares") {
    put(b, at.volume + 8 * 2, 1e-300);
    refused(b, "volume[2] = 1e-300 m^2 of a lattice square, expected dx^2");
    put(b, at.volume + 8 * 2, 1e204);
    refused(b, "volume[2] = 1e+204 m^2 of a lattice square, expected dx^2");
  }
  SECTION("vanishing volume of a free cell") {
    put<std::uint8_t>(b, at.region + 2, 2);
    put(b, at.volume + 8 * 2, 1e-300);
    put(b, at.cell_size + 8 * 2, 1e-150);
    refused(b, "volume[2] = 1e-300 m^2 does not match its cell's area 1e-06 m^2");
  }
  SECTION("cell size that is neither dx nor sqrt(volume)") {
    put(b, at.cell_size + 8 * 2, 3e-4);
    refused(b, "cell_size[2] = 0.0003 m of a lattice square, expected the spacing 0.001 m or the spacing over a "
               "power of two");
  }
  SECTION("refined square side with the coarse square's volume") {
    put(b, at.cell_size + 8 * 2, 5e-4);
    refused(b, "volume[2] = 1e-06 m^2 of a lattice square, expected its side^2 = 2.5e-07 m^2");
  }
  SECTION("cell with two vertices") {
    put<std::uint64_t>(b, at.cell_offsets + 8, 2);
    refused(b, "cell of particle 0 has 2 vertices, expected at least 3");
  }
  SECTION("clockwise cell") {
    for (int v = 0; v < 4; ++v) {
      put(b, at.cell_vx + 8 * v, original.cell_vx[3 - v]);
      put(b, at.cell_vy + 8 * v, original.cell_vy[3 - v]);
    }
    refused(b, "cell of particle 0 has the signed area -1e-06 m^2; expected a counter-clockwise polygon");
  }
  SECTION("two particles in the same place, bonded") {
    put(b, at.x + 8 * 1, original.x[0]);
    for (int v = 0; v < 4; ++v) put(b, at.cell_vx + 8 * (4 + v), original.cell_vx[v]);
    refused(b, "the bond 0 -> 1 (neighbors[0]) is 0 m long, shorter than 1e-06 spacings");
  }
  SECTION("particle in its own family") {
    put<std::uint32_t>(b, at.neighbors, 0);
    refused(b, "particle 0 is in its own family at neighbors[0]");
  }
  SECTION("repeated neighbour") {
    put<std::uint32_t>(b, at.neighbors + 4, original.neighbors[0]);
    refused(b, "the family of particle 0 is not sorted or repeats a neighbour at neighbors[1] = 1 (after 1)");
  }
  SECTION("unsorted family") {
    put<std::uint32_t>(b, at.neighbors, original.neighbors[1]);
    put<std::uint32_t>(b, at.neighbors + 4, original.neighbors[0]);
    refused(b, "the family of particle 0 is not sorted or repeats a neighbour at neighbors[1] = 1 (after 2)");
  }
  SECTION("repeated and unsorted set indices") {
    // Set "left" = {0, 3, 6}: its name length, name, count, then the indices.
    const std::size_t left = at.sets + 4 + 4 + 8;
    REQUIRE(get<std::uint32_t>(b, left + 4) == 3);
    put<std::uint32_t>(b, left + 8, 3);
    refused(b, "set 'left' is not sorted or repeats particle 3");
    put<std::uint32_t>(b, left, 6);
    put<std::uint32_t>(b, left + 8, 0);
    refused(b, "set 'left' is not sorted or repeats particle 3");
  }
}

TEST_CASE("two boundary sets with one name are refused", "[particle-file]") {
  auto p = small_lattice();
  p.sets.push_back({"left", {1}});
  CHECK_THROWS_WITH(pd::validate(p, "memory"), Catch::Contains("memory: two boundary sets are named 'left'"));
  CHECK_THROWS_WITH(pd::write_particle_file(temp_path("twice_left.pdp"), p),
                    Catch::Contains("two boundary sets are named 'left'"));
}

TEST_CASE("a lattice square off its lattice position is refused", "[particle-file]") {
  // Region 0 promises an exact dx square of the lattice (docs/formats.md):
  // the solver's lattice kernel takes its neighbours' offsets from it.
  const auto original = small_lattice();
  const auto path = temp_path("square_good.pdp");
  pd::write_particle_file(path, original);
  const Layout at(original.size(), original.cell_vx.size(), original.bond_count());
  const auto bad = temp_path("square_bad.pdp");
  auto b = slurp(path);
  SECTION("the particle nudged within its cell") {
    put(b, at.x + 8 * 4, original.x[4] + 3e-6);
  }
  SECTION("the particle and its cell shifted by a tenth of the spacing") {
    put(b, at.x + 8 * 4, original.x[4] + 1e-4);
    for (int v = 0; v < 4; ++v) put(b, at.cell_vx + 8 * (16 + v), original.cell_vx[16 + v] + 1e-4);
  }
  reseal_payload(b);
  dump(bad, b);
  CHECK_THAT(read_error(bad), Catch::Contains(bad) && Catch::Contains("particle 4 at (") &&
                                  Catch::Contains("is a lattice square (region 0) but not the centre of a square of "
                                                  "the lattice with its cell"));
}
