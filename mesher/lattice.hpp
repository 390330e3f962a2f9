#pragma once
// The uniform square lattice: cells [x0 + i dx, x0 + (i+1) dx] x [y0 + j dx, ...].
// Used for the squares of NB-NUG grids and for uniform grids.
#include <functional>

#include "particle_file.hpp"

namespace pd {

// Appends one particle per lattice cell (i, j) with i0 <= i < i1, j0 <= j < j1
// for which keep(i, j) is true, rows first (j outer), with exact square cells.
// Horizon and material are set later by the caller.
void append_lattice_squares(ParticleSet& particles, double x0, double y0, double spacing, long i0, long i1,
                            long j0, long j1, const std::function<bool(long, long)>& keep, Region region);

// The boundary sets left/right/bottom/top of the plate [0, width] x [0, height]:
// the particles within `horizon` of each edge.
void add_rectangle_edge_sets(ParticleSet& p, double width, double height, double horizon);

// A plain rectangular plate [0, width] x [0, height] of dx squares with
// families for `horizon` and boundary sets left/right/bottom/top (particles
// within one horizon of each edge). Width and height must be multiples of dx.
// For tests and examples; pd-mesh builds the same through its .geo path.
ParticleSet make_rectangle_lattice(double width, double height, double spacing, double horizon,
                                   Quadrature quadrature);

}  // namespace pd
