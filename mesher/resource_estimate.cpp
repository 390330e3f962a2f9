#include "resource_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "error.hpp"
#include "families.hpp"
#include "units.hpp"

namespace pd {

namespace {

// pd-mesh's arrays while the families are built (mesher/main.cpp): per
// particle its position, volume, size, horizon, codes and CSR offsets (59
// bytes), a square cell's 4 vertices (64), the search tree and the
// per-particle scratch of build_families (about 40); per bond the
// neighbour index and factor (12 bytes), held twice while the blocks of
// rows are joined. Plus about 100 MB for gmsh, OpenCASCADE and the program.
constexpr double bytes_per_particle = 160, bytes_per_bond = 24, base_bytes = 100e6;
// The particle file: per particle 8 doubles and codes (59 bytes) and 4 cell
// vertices (64); per bond 12 bytes (docs/formats.md).
constexpr double file_bytes_per_particle = 123, file_bytes_per_bond = 12;

double read_number_after(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      std::istringstream fields(line.substr(key.size()));
      double value = 0;
      if (fields >> value) return value;
    }
  return -1;
}

double read_single_number(const std::string& path) {
  std::ifstream in(path);
  double value = -1;
  if (!(in >> value)) return -1;  // also "max": no limit
  return value;
}

}  // namespace

ResourceEstimate estimate_resources(double area, double spacing, double horizon, Quadrature quadrature,
                                    double extra_bond_area) {
  ResourceEstimate e;
  e.particles = area / (spacing * spacing);
  e.bonds = (e.particles + extra_bond_area / (spacing * spacing)) *
            static_cast<double>(interior_family_size(horizon / spacing, quadrature));
  // A particle bonds at most with every other one: N (N - 1) directed bonds
  // (a horizon wider than the plate would otherwise count bonds to cells
  // that do not exist).
  return resources_of(e.particles, e.bonds);
}

ResourceEstimate resources_of(double particles, double bonds) {
  ResourceEstimate e;
  e.particles = particles;
  e.bonds = std::min(bonds, particles * std::max(0.0, particles - 1));
  e.memory_bytes = base_bytes + bytes_per_particle * e.particles + bytes_per_bond * e.bonds;
  e.file_bytes = file_bytes_per_particle * e.particles + file_bytes_per_bond * e.bonds;
  return e;
}


double available_memory_bytes() {
  double available = read_number_after("/proc/meminfo", "MemAvailable:");  // kB
  available = available > 0 ? available * 1024 : 0;
  const double limit = read_single_number("/sys/fs/cgroup/memory.max");
  const double used = read_single_number("/sys/fs/cgroup/memory.current");
  if (limit > 0 && used >= 0) available = available > 0 ? std::min(available, limit - used) : limit - used;
  return std::max(0.0, available);
}


std::string alternatives(const std::vector<std::string>& items) {
  std::string text;
  for (std::size_t k = 0; k < items.size(); ++k)
    text += (k == 0 ? "" : k + 1 == items.size() ? " or " : ", ") + items[k];
  return text;
}

void check_resources(const std::string& file, const ResourceEstimate& e, double budget, const std::string& option,
                     const ResourceAdvice& advice) {
  // A plate too large for its spacing to count its cells: no number to print.
  if (!std::isfinite(e.particles) || !std::isfinite(e.bonds))
    throw file_error(file, advice.grid + " would have more particles or bonds than can be counted (beyond 1e308): use "
                           "a larger spacing");
  char counts[96];
  std::snprintf(counts, sizeof counts, "about %.3g particles and %.3g bonds", e.particles, e.bonds);
  const std::string what = counts + (advice.cause.empty() ? "" : " (" + advice.cause + ")") + ", " +
                           format_bytes(e.memory_bytes) +
                           " of memory and a " + format_bytes(e.file_bytes) + " particle file";
  const double most = static_cast<double>(std::numeric_limits<std::uint32_t>::max());
  if (e.particles > most)
    throw file_error(file, advice.grid + " would have " + what +
                               "; the particle file numbers particles with 32 bits (at most 4.29e9): use a larger spacing");
  if (budget > 0 && e.memory_bytes > budget) {
    auto remedies = advice.remedies;
    if (!option.empty()) remedies.push_back("a larger --max-memory");
    throw file_error(file, advice.grid + " needs " + what + ", more than the " + format_bytes(budget) +
                               (option.empty() ? " of memory available: use " + alternatives(remedies) +
                                                     ", or --max-memory SIZE to go ahead with a larger budget"
                                               : " of memory allowed by " + option + ": use " + alternatives(remedies)));
  }
}

double parse_byte_size(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (...) {
    throw Error(what + ": '" + text + "' is not a size (e.g. 64GB, 500MB)");
  }
  std::string unit = text.substr(used);
  unit.erase(std::remove(unit.begin(), unit.end(), ' '), unit.end());
  static const struct {
    const char* name;
    double factor;
  } units[] = {{"B", 1},       {"kB", 1e3},  {"KB", 1e3},  {"MB", 1e6},  {"GB", 1e9},
               {"TB", 1e12},   {"KiB", 1024.0}, {"MiB", 1048576.0}, {"GiB", 1073741824.0}, {"TiB", 1099511627776.0}};
  for (const auto& u : units)
    if (unit == u.name) {
      // (Before 7 December 2026 'infGB' was told to be positive.)
      if (!std::isfinite(value)) throw Error(what + ": '" + text + "' is not a finite size (e.g. 64GB, 500MB)");
      if (!(value > 0)) throw Error(what + ": the size must be positive, got '" + text + "'");
      // No memory is larger than a 64-bit address reaches (about 18.4 EB):
      // a larger budget is a typo, and one beyond a double's range was taken
      // as no limit at all (before 7 December 2026: '1e300GB' passed, and
      // '1e300TB' was an infinite budget).
      const double most = 18446744073709551616.0;  // 2^64 bytes
      if (!(value * u.factor <= most))
        throw Error(what + ": '" + text + "' is more memory than a 64-bit machine can address (2^64 bytes, about 1.8e7 TB): "
                    "give the memory pd-mesh may use, e.g. 64GB");
      return value * u.factor;
    }
  throw Error(what + ": '" + text + "' needs a unit: B, kB, MB, GB, TB, KiB, MiB, GiB or TiB");
}

}  // namespace pd
