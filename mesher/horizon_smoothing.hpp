#pragma once
// The smoothed variable horizon (theory.md Sec. 7; Imachi et al. 2021,
// Sec. 4): instead of jumping from m x fine side to m x dx at the edge of a
// refinement region, the horizon of the fine squares grows linearly towards
// that edge over the smoothing length L_s,
//
//   delta_i = delta_f + (delta_c - delta_f) max(0, 1 - d_i / L_s)
//
// with d_i the distance of x_i from the region's edges that face coarse
// squares (edges on the plate's bounding box face no other resolution),
// delta_f = m x the square's side and delta_c = the nominal horizon m dx.
// The spacing stays abrupt: only the horizon varies, as in the paper's
// smoothing-length model (their "step by step" grading of the spacing is a
// separate device). The coarse side keeps m dx: a smaller coarse horizon
// would hold fewer than m coarse spacings.
#include <cstddef>
#include <string>

#include "particle_file.hpp"
#include "refinement.hpp"

namespace pd {

// "0.5mm" -> L_s [m]; pd::Error naming `option` and the value if it is not a
// finite length >= 0.
double parse_smoothing_length(const std::string& text, const std::string& option);

// What smooth_horizons did: how many horizons grew, and how deep the region
// is (the largest distance d_i of a refined square from the edges that face
// coarse squares [m]; infinite when no edge faces them). L_s beyond that
// depth leaves no square at the fine horizon delta_f.
struct SmoothingReport {
  std::size_t grown = 0;
  double deepest = 0;            // [m]
  double smallest_horizon = 0;   // of the refined squares after smoothing [m]
  double fine_horizon = 0;       // delta_f of that square [m]
  std::size_t finer_cells = 0;   // the cells the rule applies to
  std::size_t facing_coarse = 0; // those with a square of side dx on some side
  // Smoothing was asked for, but no finer cell has a square of side dx to ramp towards.
  bool nothing_to_ramp_to() const { return finer_cells > 0 && facing_coarse == 0; }
  bool keeps_no_fine_horizon(double smoothing_length) const { return grown > 0 && smoothing_length > deepest; }
};

// Sets the horizons of the refined squares of `region` (those with a side
// below the spacing inside its snapped rectangle) by the rule above, after
// assign_horizons. L_s = 0 leaves every horizon as it is.
SmoothingReport smooth_horizons(ParticleSet& particles, const RefinementRegion& region, double smoothing_length,
                                const std::string& option);

// The same rule for the free cells of NB-NUG boxes meshed finer than dx
// (--box-spacing: delta_f = m x DXB): d_i is the distance of x_i from the
// nearest lattice square of side dx (a cell at the nominal horizon), so the
// ramp runs inward from the box's edges that meet squares, not from its
// hole. Box cells farther than L_s from every such square keep delta_f
// (`deepest` then reports at least L_s). Box cells next to refined squares
// (--refine-region) see no square of side dx there and keep their jump.
SmoothingReport smooth_box_horizons(ParticleSet& particles, double smoothing_length);

// The rule above [m], for a particle at distance d [m] from the coarse side.
double smoothed_horizon(double fine_horizon, double coarse_horizon, double distance, double smoothing_length);

// Area of the band of the region within L_s of its edges that face coarse
// squares [m^2] (for the size estimate: its squares have larger families).
double smoothing_band_area(const SnappedRegion& region, double spacing, long columns, long rows,
                           double smoothing_length);

}  // namespace pd
