#pragma once
// Refinement regions (docs/mesher.md, "Refinement regions"): a rectangle of
// the plate, snapped outward to the lattice's cells, whose dx squares are
// split into factor x factor squares of side dx / factor, so that one plate
// carries two resolutions. Each square's horizon then follows its own side
// (horizon = m x side), the variable horizon of theory.md Sec. 6.
#include <cstddef>
#include <string>

#include "particle_file.hpp"

namespace pd {

// Largest refinement factor: a refined square's side dx / factor must stay
// a lattice of its own from the bounding box's corner (docs/formats.md).
inline constexpr int max_refinement_factor = 64;

struct RefinementRegion {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // the rectangle as given [m]
  int factor = 1;                         // 2, 4, 8, ... (a power of two)
};

// "X0,Y0,X1,Y1" with units (e.g. "10mm,0mm,20mm,5mm") and the factor, as
// typed for `option` and `factor_option`; pd::Error naming the option and the
// value on a malformed list, an empty rectangle or a factor that is not a
// power of two between 2 and max_refinement_factor.
RefinementRegion parse_refinement_region(const std::string& text, const std::string& factor_text,
                                         const std::string& option, const std::string& factor_option);

// The rectangle snapped outward to the cells of the lattice of `spacing` from
// (xmin, ymin), and clipped to the bounding box [xmin, xmax] x [ymin, ymax]
// (lattice cell columns [i0, i1) and rows [j0, j1)). pd::Error naming `option`
// if nothing of it lies in the box.
struct SnappedRegion {
  long i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  double area(double spacing) const { return static_cast<double>((i1 - i0) * (j1 - j0)) * spacing * spacing; }
};
SnappedRegion snap_to_lattice(const RefinementRegion& region, double spacing, double xmin, double ymin, double xmax,
                              double ymax, const std::string& option);

// The lattice squares (region 0, side dx) whose cell lies in the snapped
// region: those refine_squares would split. pd::Error naming `option` if the
// region misses the particles' bounding box.
std::size_t region_squares(const ParticleSet& particles, const RefinementRegion& region, const std::string& option);

// Replaces every lattice square (region 0, side dx) whose cell lies in the
// snapped region by factor^2 squares of side dx / factor (region 0 too, on the
// lattice of that side from the bounding box's corner). Free cells and cells
// outside the material are left as they are. Returns the squares split.
std::size_t refine_squares(ParticleSet& particles, const RefinementRegion& region, const std::string& option);

// Horizons that follow the cells: a lattice square of side s gets
// nominal_horizon * s / dx (so m = nominal / dx spacings of its own). A free
// cell of an NB-NUG box gets m x the target size of its box's mesh,
// nominal_horizon * box_spacing / dx (box_spacing 0: dx), not m x its own
// sqrt(area): gmsh's cells scatter in size about the target (triangles have
// about half a quad's area), and one horizon per box keeps a box one
// resolution level, like a refinement region. Every other cell gets the
// nominal horizon.
void assign_horizons(ParticleSet& particles, double nominal_horizon, double box_spacing = 0);

// A plain rectangular plate [0, width] x [0, height] of dx squares, refined
// in `region`, with horizons m x own side (m = nominal_horizon / dx), families
// and boundary sets left/right/bottom/top (particles within the nominal
// horizon of each edge). smoothing_length > 0: the horizons of the refined
// squares follow the smoothed rule of horizon_smoothing.hpp. For tests and
// examples, like make_rectangle_lattice; pd-mesh builds the same through its
// .geo path (--grid uniform).
ParticleSet make_refined_rectangle_lattice(double width, double height, double spacing, double nominal_horizon,
                                           const RefinementRegion& region, Quadrature quadrature,
                                           double smoothing_length = 0);

}  // namespace pd
