#pragma once
// Cracks that start at a hole, counted from the damage field: the damaged
// particles (damage >= threshold) in a ring around the hole, sorted by angle,
// fall into angular groups separated by undamaged arcs; each group is one
// crack crossing the ring. A crack must therefore have grown at least to the
// ring's outer radius to count, and damage confined to the hole's edge (a few
// broken bonds that did not become a crack) does not.
#include <vector>

#include "particle_file.hpp"

namespace pd::validation {

struct HoleRing {
  double cx = 0, cy = 0, radius = 0;  // the hole [m]
  double inner = 0, outer = 0;        // ring radii measured from the hole's edge [m]
  double damage_threshold = 0.3;
  double max_gap = 0;                 // largest arc [m] between damaged particles of one crack
};

struct HoleCrack {
  double angle_degrees = 0;  // mean direction from the hole centre, counter-clockwise from +x
  std::size_t particles = 0; // damaged particles of the ring in this crack
  // Earliest load factor at which a particle of this crack's sector, within the
  // ring's outer radius, had damage (the crack's initiation at the hole); -1 if unknown.
  double initiation_load_factor = -1;
};

// `damage_load_factor`: per particle, the load factor at which it first had
// damage (-1 if never; may be empty).
std::vector<HoleCrack> cracks_at_hole(const ParticleSet& particles, const std::vector<double>& damage,
                                      const std::vector<double>& damage_load_factor, const HoleRing& ring);

}  // namespace pd::validation
