#pragma once
// Voids (holes, notches) narrower than a few spacings, and the width a grid
// actually resolves for them: a uniform grid keeps whole cells only, so a
// 1.5 mm slot on a 1 mm lattice becomes 1 or 2 mm wide, and a 0.4 mm slot may
// vanish; the NB-NUG and free grids follow the boundary exactly. pd-mesh
// prints both instead of quantising silently.
#include <string>
#include <vector>

#include "free_region.hpp"
#include "plate_geometry.hpp"

namespace pd {

struct NarrowVoid {
  std::string name;             // "hole_2", or "notch between (x, y) mm and (x, y) mm"
  std::vector<Vec2> polygon;    // the void: a hole, or a notch closed along the bounding box
  double width = 0;             // diameter of the largest disk inside the void [m]
  double resolved_width = -1;   // uniform grids: the same for the union of the removed cells [m]
};

// The holes and notches (runs of outer-boundary curves off the bounding box)
// whose width is less than `narrower_than` [m]. Widths to 1e-3 spacing.
std::vector<NarrowVoid> narrow_voids(const PlateGeometry& geometry, double spacing, double narrower_than);

// Sets resolved_width from the uniform grid's cells: the cells of kind
// outside whose centre lies in the void.
void measure_resolved_widths(std::vector<NarrowVoid>& voids, const CellMap& cells);

// Material narrower than the spacing that a uniform grid leaves without a
// particle, so that two voids the geometry keeps apart are joined in the
// grid: a hole opened to the outer boundary (a notch), or two holes merged.
// Found from the cells: two removed cells that share a side (or a removed
// cell on the lattice's edge and the outside beyond it) whose centres lie in
// different voids have material between them that no cell centre holds.
struct LostLigament {
  std::string between;  // "hole_1 and the outer boundary", "hole_1 and hole_2"
  Vec2 where;           // middle of the ligament's narrowest place found [m]
  double width = 0;     // the boundaries' distance there [m]
  bool to_outer_boundary = false;  // a hole opened to the outside, not two holes joined
};

// The lost ligaments of a uniform grid's cells, one per place (crossings of
// the same two voids within a few spacings of each other are one ligament),
// ordered as found (by lattice row). Voids that touch at a point the
// geometry shares are not reported: no material lies between them.
std::vector<LostLigament> lost_ligaments(const PlateGeometry& geometry, const CellMap& cells);

// Diameter of the largest disk inside a simple polygon, found to `precision`
// [m] (branch and bound over squares around the pole of inaccessibility); stops
// early once a disk of diameter `enough` is found.
double largest_inscribed_diameter(const std::vector<Vec2>& polygon, double precision, double enough);

}  // namespace pd
