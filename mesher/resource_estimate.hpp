#pragma once
// What a grid will cost, known before meshing: particles, bonds, memory and
// particle-file size. pd-mesh refuses a grid that does not fit in memory (a
// spacing of 1 um on a 20 mm plate is 4e8 particles) instead of running for
// hours and ending in std::bad_alloc.
#include <cstdint>
#include <string>

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

// Memory this process may use now [bytes]: MemAvailable of /proc/meminfo, or
// the cgroup's remaining limit if that is smaller; 0 if unknown.
double available_memory_bytes();

// Throws pd::Error naming the file and the estimate if the grid cannot be
// written (more particles than 32-bit indices reach) or does not fit in
// `budget_bytes` (`budget_option` names the option that sets it).
void check_resources(const std::string& file, const ResourceEstimate& estimate, double budget_bytes,
                     const std::string& budget_option);

// "64GB", "500MB", "1.5GiB", "2e9B" -> bytes; pd::Error naming `what` otherwise.
double parse_byte_size(const std::string& text, const std::string& what);

}  // namespace pd
