#pragma once
// Families (neighbour lists) and partial-volume factors, docs/theory.md Sec. 2.
#include <vector>

#include "particle_file.hpp"

namespace pd {

// Fills family_offsets, neighbors and partial_volume from the cells and the
// per-particle horizons. Family of i: every j != i whose cell can meet the
// disk(x_i, horizon_i), kept if its factor is positive:
//   analytic: area(cell_j ∩ disk) / area(cell_j)  (exact polygon-disk area)
//   hhb:      [004:(12)] with cell_size_j (dx for squares, sqrt(V_j) otherwise, [004:(13),(14)])
//   full:     1 if |x_j - x_i| <= horizon_i
// Deterministic: families sorted by index whatever the thread count.
void build_families(ParticleSet& particles, Quadrature quadrature);

}  // namespace pd
