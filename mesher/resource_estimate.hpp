#pragma once
// What a grid will cost, known before meshing: particles, bonds, memory and
// particle-file size. pd-mesh refuses a grid that does not fit in memory (a
// spacing of 1 um on a 20 mm plate is 4e8 particles) instead of running for
// hours and ending in std::bad_alloc.
#include <cstdint>
#include <string>
#include <vector>

#include "particle_file.hpp"

namespace pd {

struct ResourceEstimate {
  double particles = 0;     // area / dx^2
  double bonds = 0;         // particles x the interior family size
  double memory_bytes = 0;  // peak of pd-mesh
  double file_bytes = 0;    // particle file
};

// For a plate of `area` [m^2], spacing dx and horizon [m]. The memory model
// (bytes per particle and per bond of pd-mesh's arrays at their peak, while
// the families are built) is checked against measured runs in docs/mesher.md.
// `extra_bond_area` [m^2]: bonds beyond one interior family per particle, as
// the area whose particles would hold them (smoothed horizons' larger families).
ResourceEstimate estimate_resources(double area, double spacing, double horizon, Quadrature quadrature,
                                    double extra_bond_area = 0);

// The same memory and file model for counts known once the grid is meshed:
// its particles and the directed bonds estimated from their positions
// (family_size_estimate.hpp), at most N (N - 1).
ResourceEstimate resources_of(double particles, double bonds);

// Memory this process may use now [bytes]: MemAvailable of /proc/meminfo, or
// the cgroup's remaining limit if that is smaller; 0 if unknown.
double available_memory_bytes();

// Throws pd::Error naming the file and the estimate if the grid cannot be
// written (more particles than 32-bit indices reach, or counts beyond the
// range of numbers) or does not fit in `budget_bytes` (0: unknown, not
// checked; `budget_option` names the option that sets it).
struct ResourceAdvice {
  std::string grid = "this grid";  // how the message names the grid ("once meshed, this grid")
  std::string cause;               // why so many bonds, said after their count in parentheses
  std::vector<std::string> remedies{"a larger spacing"};  // besides a larger budget
};
void check_resources(const std::string& file, const ResourceEstimate& estimate, double budget_bytes,
                     const std::string& budget_option, const ResourceAdvice& advice = {});

// "A", "A or B", "A, B or C".
std::string alternatives(const std::vector<std::string>& items);

// "64GB", "500MB", "1.5GiB", "2e9B" -> bytes; pd::Error naming `what` otherwise.
double parse_byte_size(const std::string& text, const std::string& what);

}  // namespace pd
