#pragma once
// Families (neighbour lists) and partial-volume factors, docs/theory.md Sec. 2.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle_file.hpp"

namespace pd {

class MaterialBoundary;

struct FamilyReport {
  // Directed bonds left out because their segment leaves the material.
  std::uint64_t bonds_through_voids = 0;
};

// Fills family_offsets, neighbors and partial_volume from the cells and the
// per-particle horizons. Family of i: every j != i whose cell can meet the
// disk(x_i, horizon_i), kept if its factor is positive:
//   analytic: area(cell_j ∩ disk) / area(cell_j)  (exact polygon-disk area)
//   hhb:      [004:(12)] with cell_size_j (dx for squares, sqrt(V_j) otherwise, [004:(13),(14)])
//   full:     1 if |x_j - x_i| <= horizon_i
// With a `boundary`, j is also left out when the segment x_i -> x_j leaves
// the material (MaterialBoundary::segment_leaves_material, symmetric in i
// and j): no bond crosses a hole, a notch or a re-entrant outer boundary.
// Deterministic: families sorted by index whatever the thread count.
FamilyReport build_families(ParticleSet& particles, Quadrature quadrature, const MaterialBoundary* boundary = nullptr);

// Family size of a square far from every boundary on a lattice of spacing
// dx with horizon m dx, counted cell by cell (an upper bound per particle for
// any grid of about dx cells; used to estimate a grid's size before meshing).
std::size_t interior_family_size(double horizon_factor, Quadrature quadrature);

}  // namespace pd
