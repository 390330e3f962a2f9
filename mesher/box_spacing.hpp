#pragma once
// Finer NB-NUG boxes (docs/mesher.md, "Finer boxes"): the free meshes in the
// boxes and bands along boundaries off the lattice get a target size DXB
// below the spacing dx of the squares outside, so that a plate resolves its
// holes finer than the rest. Each free cell's horizon is then m x DXB, the
// variable horizon of theory.md Sec. 6, and the squares next to a box see
// finer neighbours (the dual-horizon solver handles the mismatch).
#include <string>

namespace pd {

struct PlateGeometry;

// "0.025mm" -> DXB [m] for the spacing dx [m]. DXB must be dx / 2^k with
// k = 0 ... 6 (dx / max_refinement_factor at the finest): every lattice edge
// between a box and a square is then cut into exactly 2^k box edges of length
// DXB, and the horizons keep the powers-of-two levels of the refinement
// regions. pd::Error naming `option` and the value otherwise (not a length,
// not finite, not positive, larger than dx, or not dx over a power of two).
double parse_box_spacing(const std::string& text, double spacing, const std::string& option);

// dx / DXB, the number of box edges per lattice edge (1, 2, 4, ... 64).
int box_edges_per_lattice_edge(double box_spacing, double spacing);

// What finer boxes (DXB below dx) add to a grid's size estimate, once the
// holes are known (resource_estimate.hpp's extra areas): each hole's box
// padded by `padding` and snapped out (one dx more on every side), less the
// hole, holds (dx / DXB)^2 times the cells of a box at dx, an upper bound
// (bands along other boundaries off the lattice are not counted); with a
// smoothing length L_s, the boxes' band within L_s of their edges (at most
// all of them) at the horizon ramp's mean factor, as for a refinement
// region. Zeros where DXB is 0 or not below dx. The one rule of pd-mesh and
// of the validation tools' grids.
struct FinerBoxesEstimate {
  double extra_area = 0;             // [m^2] of particles at dx, beyond the plate's
  double smoothed_extra_bond_area = 0;  // [m^2] (estimate_resources's extra_bond_area)
};
FinerBoxesEstimate finer_boxes_estimate(const PlateGeometry& geometry, double spacing, double box_spacing,
                                        double padding, double horizon_smoothing = 0);

}  // namespace pd
