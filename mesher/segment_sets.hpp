#pragma once
// Boundary sets: the particles near line segments (plate edges, hole outlines).
#include <cstdint>
#include <vector>

#include "particle_file.hpp"

namespace pd {

class MaterialBoundary;
class NeighborSearch;

// The particles within `distance` of any of the segments (ax[k], ay[k]) ->
// (bx[k], by[k]), sorted. `search` must be built on the particles' positions.
// With `material`, a particle counts only if the straight line to its
// nearest point of the segment stays in the material: a particle across a
// notch from the segment's end is not near it.
std::vector<std::uint32_t> particles_near_segments(const ParticleSet& particles, const NeighborSearch& search,
                                                   const std::vector<double>& ax, const std::vector<double>& ay,
                                                   const std::vector<double>& bx, const std::vector<double>& by,
                                                   double distance, const MaterialBoundary* material = nullptr);

}  // namespace pd
