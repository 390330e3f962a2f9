#pragma once
// Points, polylines and exact chord areas on gmsh curves of the current gmsh
// model, in the geometry file's units. Used by plate_geometry only.
#include <vector>

#include "geometry.hpp"

namespace pd {

// Points of curve `tag` at the given parameters.
std::vector<Vec2> evaluate_curve(int tag, const std::vector<double>& params);

// A polyline of curve `tag` from parameter t0 to t1 (either order): the
// middle of every chord is within `tolerance` of the curve (chords are
// halved until it is; a straight curve is one chord).
struct CurvePolyline {
  std::vector<double> params;
  std::vector<Vec2> points;
  double length() const;
};
CurvePolyline curve_polyline(int tag, double t0, double t1, bool straight, double tolerance);

// Parameters that split the polyline's curve into `pieces` pieces of equal
// arc length (measured along the polyline), first and last included.
std::vector<double> equal_length_parameters(const CurvePolyline& polyline, int pieces);

// Signed area between the chord p(t0) -> p(t1) and the curve between them:
// positive when the curve lies to the right of the chord. Circles and
// ellipses: Green's formula 1/2 ∫ (X dY - Y dX) with 8-point Gauss-Legendre
// quadrature on the curve's own parametrisation, exact to round-off for the
// short arcs between two samples. Other curves (splines, whose knots may
// fall inside the chord and whose gmsh derivative is a finite difference):
// polygons of ever finer parameter steps, extrapolated, to round-off
// (docs/mesher.md, "Curved boundaries: exact volumes").
double bulge_area(int tag, double t0, double t1);

}  // namespace pd
