// Crafted particle files (docs/robustness.md): seeded mutants of small real
// particle files, made here by the mesher's own library, with their checksums
// recomputed as any buggy writer could. Each mutant must either be refused by
// both readers with a pd::Error that names the file, or be accepted by both
// and then run through pd-solve's set-up and a step without crashing: exit 0,
// or exit 1 with one "pd-solve: error: ..." line that is not a bare standard
// library exception. The solver runs as its own process, so a crash, an abort
// or a sanitizer report (docs/robustness.md, scripts/sanitize.sh) is seen as
// such instead of taking the test down.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "checksum.hpp"
#include "error.hpp"
#include "families.hpp"
#include "../c1_plate.hpp"
#include "gmsh_session.hpp"
#include "grids.hpp"
#include "lattice.hpp"
#include "particle_file.hpp"
#include "plate_geometry.hpp"
#include "../test_folder.hpp"

namespace fs = std::filesystem;

namespace {

std::string fresh_folder(const std::string& name) { return pd::test_support::fresh_folder_under(PD_TEST_TMPDIR, name); }

std::vector<char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

void dump(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---- The file layout (docs/formats.md) ---------------------------------------

constexpr std::size_t header_size = 128;
constexpr std::size_t count_offsets[] = {16, 24, 32};  // particles, bonds, cell vertices (u64)
constexpr std::size_t set_count_offset = 40, grid_offset = 44, double_offsets[] = {56, 64, 72, 80, 88, 96};
constexpr std::size_t payload_size_offset = 104, payload_checksum_offset = 112, header_checksum_offset = 120;

template <class T>
T get(const std::vector<char>& bytes, std::size_t offset) {
  T value{};
  if (offset + sizeof value <= bytes.size()) std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}
template <class T>
void put(std::vector<char>& bytes, std::size_t offset, T value) {
  if (offset + sizeof value <= bytes.size()) std::memcpy(bytes.data() + offset, &value, sizeof value);
}

// Recomputes the payload size, the payload checksum and the header checksum.
void reseal(std::vector<char>& bytes) {
  const std::uint64_t size = bytes.size() - header_size;
  put(bytes, payload_size_offset, size);
  put(bytes, payload_checksum_offset, pd::checksum_of(bytes.data() + header_size, size));
  put(bytes, header_checksum_offset, pd::checksum_of(bytes.data(), header_checksum_offset));
}

// Where each section of an unmutated file starts, and its element size.
struct Section {
  const char* name;
  std::size_t begin, count, element;
};
std::vector<Section> sections_of(const std::vector<char>& bytes) {
  const auto n = get<std::uint64_t>(bytes, 16), b = get<std::uint64_t>(bytes, 24), c = get<std::uint64_t>(bytes, 32);
  std::vector<Section> s;
  std::size_t at = header_size;
  const auto add = [&](const char* name, std::size_t count, std::size_t element) {
    s.push_back({name, at, count, element});
    at += count * element;
  };
  for (const char* name : {"x", "y", "volume", "cell_size", "horizon"}) add(name, n, 8);
  add("region", n, 1);
  add("material", n, 2);
  add("cell_offsets", n + 1, 8);
  add("cell_vx", c, 8);
  add("cell_vy", c, 8);
  add("family_offsets", n + 1, 8);
  add("neighbors", b, 4);
  add("partial_volume", b, 8);
  add("sets and provenance", (bytes.size() - at), 1);
  return s;
}

// ---- Mutations ---------------------------------------------------------------

class Mutator {
public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  // One to three mutations of `good`, resealed; `what` describes them.
  std::vector<char> mutant(const std::vector<char>& good, std::string& what) {
    auto bytes = good;
    const auto sections = sections_of(good);
    std::ostringstream log;
    const int count = 1 + static_cast<int>(pick(3));
    for (int m = 0; m < count && mutate(bytes, sections, log); ++m) {
    }
    // Mostly resealed: an unsealed file only tests the checksum.
    if (pick(10) != 0) reseal(bytes);
    what = log.str();
    return bytes;
  }

private:
  std::size_t pick(std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); }

  double interesting_double(double current) {
    const double values[] = {0.0,
                             -0.0,
                             1e-300,
                             std::numeric_limits<double>::denorm_min(),
                             1e-12,
                             1e-6,
                             1.0,
                             -1.0,
                             1e204,
                             1e300,
                             std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN(),
                             current * (1 + 1e-12),
                             current * (1 + 1e-6),
                             current * 2,
                             current * 0.5,
                             current * 1e6,
                             current * 1e-6,
                             -current,
                             current + 1e-3};
    return values[pick(std::size(values))];
  }

  std::uint64_t interesting_integer(std::uint64_t current, std::uint64_t limit) {
    const std::uint64_t values[] = {0,
                                    1,
                                    current + 1,
                                    current - 1,
                                    current * 2,
                                    current / 2,
                                    limit,
                                    limit - 1,
                                    limit + 1,
                                    0xffffffffull,
                                    0x100000000ull,
                                    std::uint64_t{1} << 62,
                                    ~std::uint64_t{0},
                                    pick(limit + 1)};
    return values[pick(std::size(values))];
  }

  // Returns false once the sections have moved (bytes removed or added), after
  // which the layout no longer locates them.
  bool mutate(std::vector<char>& b, const std::vector<Section>& sections, std::ostringstream& log) {
    const auto n = get<std::uint64_t>(b, 16);
    const auto& s = sections[pick(sections.size())];
    switch (pick(13)) {
      case 0: {  // flip a few bits anywhere
        for (std::size_t k = 0, bits = 1 + pick(3); k < bits; ++k) {
          const std::size_t at = pick(b.size());
          b[at] = static_cast<char>(b[at] ^ (1 << pick(8)));
          log << "bit flip at " << at << "; ";
        }
        break;
      }
      case 1: {  // a header double (dx, delta, bbox)
        const std::size_t at = double_offsets[pick(std::size(double_offsets))];
        const double value = interesting_double(get<double>(b, at));
        put(b, at, value);
        log << "header double at " << at << " = " << value << "; ";
        break;
      }
      case 2: {  // a header count or code
        if (pick(2)) {
          const std::size_t at = count_offsets[pick(std::size(count_offsets))];
          const auto value = interesting_integer(get<std::uint64_t>(b, at), n);
          put(b, at, value);
          log << "header count at " << at << " = " << value << "; ";
        } else {
          const std::size_t at = pick(2) ? set_count_offset : grid_offset + pick(4);
          const auto value = static_cast<std::uint32_t>(interesting_integer(get<std::uint8_t>(b, at), 4));
          if (at == set_count_offset) put(b, at, value);
          else put(b, at, static_cast<std::uint8_t>(value));
          log << "header field at " << at << " = " << value << "; ";
        }
        break;
      }
      case 3: {  // an element of a section, by its type
        if (s.count == 0) break;
        const std::size_t k = pick(s.count), at = s.begin + k * s.element;
        if (s.element == 8 && (std::strcmp(s.name, "cell_offsets") == 0 || std::strcmp(s.name, "family_offsets") == 0)) {
          const auto value = interesting_integer(get<std::uint64_t>(b, at), get<std::uint64_t>(b, s.begin + (s.count - 1) * 8));
          put(b, at, value);
          log << s.name << "[" << k << "] = " << value << "; ";
        } else if (s.element == 8) {
          const double value = interesting_double(get<double>(b, at));
          put(b, at, value);
          log << s.name << "[" << k << "] = " << value << "; ";
        } else if (s.element == 4) {
          const auto value = static_cast<std::uint32_t>(interesting_integer(get<std::uint32_t>(b, at), n));
          put(b, at, value);
          log << s.name << "[" << k << "] = " << value << "; ";
        } else {
          const auto value = static_cast<std::uint8_t>(pick(256));
          b[at] = static_cast<char>(value);
          log << s.name << " byte " << k << " = " << int(value) << "; ";
        }
        break;
      }
      case 4: {  // the same value for a whole per-particle section (e.g. every horizon 1e-12)
        const auto& t = sections[pick(5)];
        const double value = interesting_double(get<double>(b, t.begin));
        for (std::size_t k = 0; k < t.count; ++k) put(b, t.begin + 8 * k, value);
        log << "every " << t.name << " = " << value << "; ";
        break;
      }
      case 5: {  // a particle and its cell moved together (the cell checks still hold)
        if (n == 0) break;
        const std::size_t i = pick(n);
        const double shift_x = interesting_double(1e-3) * (pick(2) ? 1 : -1), shift_y = pick(2) ? shift_x : 0.0;
        const auto first = get<std::uint64_t>(b, sections[7].begin + 8 * i);
        const auto last = get<std::uint64_t>(b, sections[7].begin + 8 * (i + 1));
        put(b, sections[0].begin + 8 * i, get<double>(b, sections[0].begin + 8 * i) + shift_x);
        put(b, sections[1].begin + 8 * i, get<double>(b, sections[1].begin + 8 * i) + shift_y);
        for (auto v = first; v < last && v < sections[8].count; ++v) {
          put(b, sections[8].begin + 8 * v, get<double>(b, sections[8].begin + 8 * v) + shift_x);
          put(b, sections[9].begin + 8 * v, get<double>(b, sections[9].begin + 8 * v) + shift_y);
        }
        log << "particle " << i << " and its cell moved by (" << shift_x << ", " << shift_y << "); ";
        break;
      }
      case 6: {  // two neighbours of a family swapped, or one repeated
        const auto& nb = sections[11];
        if (nb.count < 2) break;
        const std::size_t k = pick(nb.count - 1), at = nb.begin + 4 * k;
        const auto first = get<std::uint32_t>(b, at), second = get<std::uint32_t>(b, at + 4);
        put(b, at, second);
        if (pick(2)) put(b, at + 4, first);
        log << "neighbors[" << k << "] and [" << k + 1 << "] swapped or repeated; ";
        break;
      }
      case 7: {  // payload cut short or grown (the header follows: resealed)
        const std::size_t payload = b.size() - header_size;
        if (pick(2) && payload > 0) {
          b.resize(header_size + pick(payload));
          log << "payload cut to " << b.size() - header_size << " bytes; ";
        } else {
          b.insert(b.begin() + static_cast<std::ptrdiff_t>(header_size + pick(payload + 1)), 1 + pick(16), '\0');
          log << "payload grown to " << b.size() - header_size << " bytes; ";
        }
        return false;
      }
      // Gentler mutations, which keep most invariants, so that many mutants
      // reach the solver with something unusual.
      case 8: {  // a partial-volume factor anywhere in (0, 1]
        const auto& phi = sections[12];
        if (phi.count == 0) break;
        const std::size_t k = pick(phi.count);
        const double values[] = {1.0, 1e-300, 1e-12, 0.5, std::uniform_real_distribution<double>(1e-9, 1.0)(rng_)};
        put(b, phi.begin + 8 * k, values[pick(std::size(values))]);
        log << "partial_volume[" << k << "] changed; ";
        break;
      }
      case 9: {  // a horizon within [dx, delta], a region or a material code changed
        if (n == 0) break;
        const std::size_t i = pick(n);
        const double dx = get<double>(b, 56), delta = get<double>(b, 64);
        if (pick(2)) {
          put(b, sections[4].begin + 8 * i, dx + (delta - dx) * std::uniform_real_distribution<double>(0, 1)(rng_));
          log << "horizon[" << i << "] changed; ";
        } else if (pick(2)) {
          b[sections[5].begin + i] = static_cast<char>(pick(3));
          log << "region[" << i << "] changed; ";
        } else {
          put(b, sections[6].begin + 2 * i, static_cast<std::uint16_t>(pick(65536)));
          log << "material[" << i << "] changed; ";
        }
        break;
      }
      case 10: {  // a bond removed (its partner stays: a one-way bond)
        const auto& nb = sections[11];
        const auto& phi = sections[12];
        const auto& offsets = sections[10];
        if (nb.count == 0) break;
        const std::size_t k = pick(nb.count);
        for (std::size_t i = 0; i < offsets.count; ++i) {
          const auto o = get<std::uint64_t>(b, offsets.begin + 8 * i);
          if (o > k) put(b, offsets.begin + 8 * i, o - 1);
        }
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(phi.begin + 8 * k),
                b.begin() + static_cast<std::ptrdiff_t>(phi.begin + 8 * k + 8));
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(nb.begin + 4 * k),
                b.begin() + static_cast<std::ptrdiff_t>(nb.begin + 4 * k + 4));
        put(b, 24, get<std::uint64_t>(b, 24) - 1);
        log << "bond " << k << " removed; ";
        return false;
      }
      case 11: {  // a particle nudged off its lattice position, within its cell
        if (n == 0) break;
        const std::size_t i = pick(n);
        const double dx = get<double>(b, 56), shift = 0.005 * dx * std::uniform_real_distribution<double>(-1, 1)(rng_);
        const std::size_t at = sections[pick(2)].begin + 8 * i;
        put(b, at, get<double>(b, at) + shift);
        log << "particle " << i << " nudged by " << shift << " m; ";
        break;
      }
      case 12: {  // every horizon and the nominal one set to another valid value
        const double dx = get<double>(b, 56), delta = dx * (1 + 7 * std::uniform_real_distribution<double>(0, 1)(rng_));
        put(b, 64, delta);
        for (std::size_t i = 0; i < n; ++i) put(b, sections[4].begin + 8 * i, delta);
        log << "every horizon = " << delta << " m; ";
        break;
      }
    }
    return true;
  }

  std::mt19937_64 rng_;
};

// ---- What a mutant does --------------------------------------------------------

struct ReadOutcome {
  bool accepted = false;
  std::string message;  // pd::Error text when refused
};

// Reads `path` with one of the readers; any exception other than pd::Error fails the test.
template <class Read>
ReadOutcome read_with(const Read& read) {
  ReadOutcome r;
  try {
    read();
    r.accepted = true;
  } catch (const pd::Error& e) {
    r.message = e.what();
  } catch (const std::exception& e) {
    FAIL("not a pd::Error: " << e.what());
  }
  return r;
}

void ignore_family(const pd::ParticleSet&, std::uint32_t, const std::uint32_t*, const double*, std::size_t) {}

struct SolverOutcome {
  int exit_status = -1;  // -1: killed by a signal or timed out
  std::string log;
};

SolverOutcome run_solver(const std::string& folder) {
  const std::string log = folder + "/solve.log";
  fs::remove_all(folder + "/out");
  // A hung solver (it must not hang) fails the test after 120 s instead of blocking it.
  const std::string command = "timeout -s KILL 120 " + std::string(PD_SOLVE_EXECUTABLE) + " " + folder +
                              "/scene.toml -q --threads 1 -o " + folder + "/out > " + log + " 2>&1";
  const int raw = std::system(command.c_str());
  SolverOutcome r;
  r.exit_status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  if (r.exit_status == 137) r.exit_status = -1;  // SIGKILL from timeout
  r.log = text_of(log);
  return r;
}

// A clean refusal by the solver: one error line of its own, not a standard
// library exception that escaped (bad_alloc, length_error, ...) and no report
// of a sanitizer.
bool clean_solver_error(const std::string& log) {
  for (const char* sign : {"Sanitizer", "runtime error", "std::", "vector::", "basic_string", "bad_alloc", "_M_",
                           "terminate called"})
    if (log.find(sign) != std::string::npos) return false;
  return log.find("pd-solve: error: ") != std::string::npos;
}

// The scene every mutant runs: damage, surface correction, a pre-crack,
// loads on named sets, snapshots; one forced step of 1 ns.
std::string scene_text(double plate_height) {
  std::ostringstream s;
  s << "particles = \"mutant.pdp\"\n"
       "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\n"
       "[effects]\ndamage = true\nsurface_correction = true\n"
       "[time]\nstep = 1e-9\nforce = true\nend = 1e-9\n"
       "[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = 0.3\n"
       "[[loads]]\nset = \"bottom\"\ntype = \"fixed\"\n"
       "[[precracks]]\nfrom = [0.0, "
    << 0.5 * plate_height << "]\nto = [" << 0.25 * plate_height << ", " << 0.5 * plate_height
    << "]\n"
       "[output]\nsnapshot_interval = 1\nenergy_interval = 1\n";
  return s.str();
}

struct Seed {
  std::string name;
  pd::ParticleSet particles;
};

// Small real particle files: a uniform lattice, and NB-NUG grids of the C1
// plate (one hole, free cells with curved edges) with analytic and HHB factors.
std::vector<Seed> seeds() {
  std::vector<Seed> s;
  s.push_back({"uniform lattice", pd::make_rectangle_lattice(12e-3, 10e-3, 1e-3, 3e-3, pd::Quadrature::analytic)});
  for (const auto quadrature : {pd::Quadrature::analytic, pd::Quadrature::hhb}) {
    auto p = pd::test_support::c1_plate_nbnug(1e-3, 3e-3, quadrature, true);
    p.provenance = "{\"test\": \"fuzz seed\"}";
    s.push_back({std::string("C1 NB-NUG ") + pd::to_string(quadrature), std::move(p)});
  }
  return s;
}

}  // namespace

// The crafted files of the issue that motivated the checks, each resealed:
// the byte changes a buggy writer could make, by name.
std::vector<std::pair<std::string, std::vector<char>>> issue_mutants(const std::vector<char>& good) {
  const auto sections = sections_of(good);
  const auto& x = sections[0];
  const auto& volume = sections[2];
  const auto& horizon = sections[4];
  const auto& cell_offsets = sections[7];
  const auto& neighbors = sections[11];
  const auto& sets = sections[13];
  std::vector<std::pair<std::string, std::vector<char>>> mutants;
  const auto add = [&](const std::string& name, const std::function<void(std::vector<char>&)>& change) {
    auto bytes = good;
    change(bytes);
    reseal(bytes);
    mutants.emplace_back(name, std::move(bytes));
  };
  add("every horizon 1e-12 m", [&](auto& b) {
    for (std::size_t i = 0; i < horizon.count; ++i) put(b, horizon.begin + 8 * i, 1e-12);
  });
  add("one horizon 1e-12 m", [&](auto& b) { put(b, horizon.begin + 8 * 7, 1e-12); });
  add("header dx 1e-12 m", [&](auto& b) { put(b, 56, 1e-12); });
  add("header dx 1e-300 m", [&](auto& b) { put(b, 56, 1e-300); });
  add("header dx 1 km", [&](auto& b) { put(b, 56, 1e3); });
  add("header delta 1 m", [&](auto& b) { put(b, 64, 1.0); });
  add("header delta 1e-12 m", [&](auto& b) { put(b, 64, 1e-12); });
  add("bounding box 1 km wide", [&](auto& b) { put(b, 88, 1e3); });
  add("bounding box 1e300 m wide", [&](auto& b) { put(b, 88, 1e300); });
  add("bounding box inverted", [&](auto& b) { put(b, 72, get<double>(b, 88) + 1.0); });
  add("volume 1e-300 m^2", [&](auto& b) { put(b, volume.begin + 8 * 5, 1e-300); });
  add("volume 1e204 m^2", [&](auto& b) { put(b, volume.begin + 8 * 5, 1e204); });
  add("particle 1 km outside the bounding box", [&](auto& b) { put(b, x.begin + 8 * 5, 1e3); });
  add("particle and its cell moved 1 km out", [&](auto& b) {
    put(b, x.begin + 8 * 5, get<double>(b, x.begin + 8 * 5) + 1e3);
    for (auto v = get<std::uint64_t>(b, cell_offsets.begin + 8 * 5); v < get<std::uint64_t>(b, cell_offsets.begin + 8 * 6); ++v)
      put(b, sections[8].begin + 8 * v, get<double>(b, sections[8].begin + 8 * v) + 1e3);
  });
  add("particle and its cell moved 8 horizons within the plate (bonds many horizons long)", [&](auto& b) {
    const double shift = 8 * get<double>(b, 64);
    put(b, x.begin, get<double>(b, x.begin) + shift);
    for (auto v = get<std::uint64_t>(b, cell_offsets.begin); v < get<std::uint64_t>(b, cell_offsets.begin + 8); ++v)
      put(b, sections[8].begin + 8 * v, get<double>(b, sections[8].begin + 8 * v) + shift);
  });
  add("duplicate neighbour", [&](auto& b) { put(b, neighbors.begin + 4, get<std::uint32_t>(b, neighbors.begin)); });
  add("unsorted neighbours", [&](auto& b) {
    const auto first = get<std::uint32_t>(b, neighbors.begin), second = get<std::uint32_t>(b, neighbors.begin + 4);
    put(b, neighbors.begin, second);
    put(b, neighbors.begin + 4, first);
  });
  add("particle in its own family", [&](auto& b) { put<std::uint32_t>(b, neighbors.begin, 0); });
  add("duplicate set index", [&](auto& b) {
    // The first set: name length, name, count, then its indices.
    const auto name_length = get<std::uint32_t>(b, sets.begin);
    const std::size_t indices = sets.begin + 4 + name_length + 8;
    put(b, indices + 4, get<std::uint32_t>(b, indices));
  });
  return mutants;
}

TEST_CASE("crafted particle files: clean errors or a clean solver set-up, never a crash", "[robustness][fuzz]") {
  const int random_mutants_per_seed = 100;
  const auto folder = fresh_folder("fuzz");
  const std::string mutant_path = folder + "/mutant.pdp";
  std::size_t refused = 0, accepted = 0, solver_ran = 0, solver_refused = 0;
  std::uint64_t seed_number = 0;
  for (const auto& seed : seeds()) {
    const double height = seed.particles.ymax - seed.particles.ymin;
    std::ofstream(folder + "/scene.toml") << scene_text(height);
    pd::write_particle_file(mutant_path, seed.particles);
    const auto good = slurp(mutant_path);
    {
      // The unmutated file runs: the scene fits the seed.
      INFO(seed.name);
      const auto baseline = run_solver(folder);
      INFO(baseline.log);
      REQUIRE(baseline.exit_status == 0);
    }
    auto mutants = issue_mutants(good);
    Mutator mutator(0x5eed0000 + seed_number++);
    for (int m = 0; m < random_mutants_per_seed; ++m) {
      std::string what;
      auto bytes = mutator.mutant(good, what);
      mutants.emplace_back("random mutant " + std::to_string(m) + ": " + what, std::move(bytes));
    }
    for (const auto& [what, bytes] : mutants) {
      dump(mutant_path, bytes);
      INFO(seed.name << ", " << what);
      const auto whole = read_with([&] { pd::read_particle_file(mutant_path); });
      const auto streamed = read_with([&] { pd::read_particle_file(mutant_path, ignore_family); });
      INFO("whole-file reader: " << (whole.accepted ? "accepted" : whole.message));
      INFO("streaming reader: " << (streamed.accepted ? "accepted" : streamed.message));
      REQUIRE(whole.accepted == streamed.accepted);
      if (!whole.accepted) {
        ++refused;
        CHECK_THAT(whole.message, Catch::StartsWith(mutant_path + ": "));
        CHECK_THAT(streamed.message, Catch::StartsWith(mutant_path + ": "));
        continue;
      }
      ++accepted;
      const auto solved = run_solver(folder);
      INFO("pd-solve exit status " << solved.exit_status << ", output:\n" << solved.log);
      const bool clean = solved.exit_status == 0 || (solved.exit_status == 1 && clean_solver_error(solved.log));
      CHECK(clean);
      (solved.exit_status == 0 ? solver_ran : solver_refused)++;
    }
  }
  std::cout << "particle-file fuzz: " << refused << " mutants refused by the readers, " << accepted
            << " accepted; of these " << solver_ran << " ran through pd-solve, " << solver_refused
            << " refused by it\n";
  // Both outcomes are exercised: the mutants are neither all trivial nor all fatal.
  CHECK(refused > 30);
  CHECK(accepted > 30);
}
