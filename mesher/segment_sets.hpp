#pragma once
// Boundary sets: the particles near line segments (plate edges, hole outlines).
#include <cstdint>
#include <vector>

#include "particle_file.hpp"

namespace pd {

class NeighborSearch;

// The particles within `distance` of any of the segments (ax[k], ay[k]) ->
// (bx[k], by[k]), sorted. `search` must be built on the particles' positions.
std::vector<std::uint32_t> particles_near_segments(const ParticleSet& particles, const NeighborSearch& search,
                                                   const std::vector<double>& ax, const std::vector<double>& ay,
                                                   const std::vector<double>& bx, const std::vector<double>& by,
                                                   double distance);

}  // namespace pd
