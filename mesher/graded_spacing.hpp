#pragma once
// Graded free meshes (docs/mesher.md, "Graded free meshes"; theory.md
// Sec. 7.4): the global free grid's target cell size grows linearly with the
// distance d from the curved boundaries (holes, pores, arcs of the outer
// boundary),
//
//   h(d) = DXF + (dx - DXF) min(1, d / L),
//
// from DXF at the curves to the spacing dx at the grading length L and
// beyond. gmsh meshes with this size field, and every cell gets the horizon
// m h(x_i) at its centroid (m = delta / dx): the smooth field, not the cell's
// own sqrt(area), which scatters about the target.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "geometry.hpp"
#include "neighbor_search.hpp"
#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd {

struct GradedSpacing {
  double fine = 0;    // DXF, the target size at the curved boundaries [m]; 0: no grading
  double coarse = 0;  // dx, the target size at distance L and beyond [m]
  double length = 0;  // L, the grading length [m]
  bool enabled() const { return fine > 0; }
  // h(d) above [m], for the distance d [m] from the nearest curved boundary.
  double size_at(double distance) const;
};

// Default grading length: this many nominal horizons m dx.
inline constexpr double default_grading_horizons = 3;

// "DXF[,L]" (lengths with units, e.g. "0.1mm" or "0.1mm,4mm") -> the grading
// for the spacing dx and the nominal horizon delta [m]. L defaults to
// default_grading_horizons x delta. pd::Error naming `option` and the value
// unless 0 < DXF < dx, dx / DXF <= 64 (the finest size a particle file
// accepts) and L >= 2 (dx - DXF) (the size grows by at most half a cell per
// cell, so that gmsh can follow it with well-shaped quads).
GradedSpacing parse_graded_spacing(const std::string& text, double spacing, double horizon,
                                   const std::string& option);

// Distance from points to the curved boundary curves of a plate (not the
// straight ones): to the chords between the curves' samples and their arc
// points, within a hundredth of DXF of the true curves.
class CurvedBoundaryDistance {
public:
  explicit CurvedBoundaryDistance(const PlateGeometry& geometry);
  ~CurvedBoundaryDistance();
  bool empty() const { return a_.empty(); }
  // min(distance from p [m], cap [m]).
  double distance(Vec2 p, double cap) const;

private:
  std::vector<Vec2> a_, b_;  // segments a_[k] -> b_[k]
  std::vector<double> mid_x_, mid_y_;  // their midpoints (searched)
  double half_longest_ = 0;            // half the longest segment [m]
  std::unique_ptr<NeighborSearch> search_;
};

// Sets every free cell's horizon (the global free grid's Region::other) to
// m h(x_i), m = nominal horizon / dx. Returns how many cells got a horizon
// below the nominal one.
std::size_t assign_graded_horizons(ParticleSet& particles, const PlateGeometry& geometry,
                                   const GradedSpacing& graded);

// For the estimate before meshing: the area [m^2] that, meshed at dx, holds
// as many cells as the graded mesh holds more than the uniform one at dx:
// the integral of (dx / h)^2 - 1 over the band within L of the curved
// boundaries, each curve of length l taken with the band length l + 2 pi d
// at distance d (exact for a lone circle; overlaps of bands counted twice),
// at most the plate's area times (dx / DXF)^2 - 1 (the whole plate at DXF).
double graded_extra_area(const PlateGeometry& geometry, const GradedSpacing& graded);

// Whether any boundary of the plate (outer edge or hole) has a curved piece:
// the cells grade towards those, so a plate of straight edges only has
// nothing to grade towards (pd-mesh refuses --graded-spacing there).
bool has_curved_boundary(const PlateOutline& outline);

}  // namespace pd
