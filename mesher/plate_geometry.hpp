#pragma once
// A plate read from a gmsh geometry file: one plane surface of any shape.
// Its outer boundary may be made of straight and curved curves (notches,
// re-entrant corners, holes cut through the edge); holes inside it are
// bounded by any curves; a hole may touch the outer boundary or another hole
// at a shared point. Everything here is in metres.
#include <string>
#include <utility>
#include <vector>

#include "geometry.hpp"
#include "material_boundary.hpp"

namespace pd {

class GmshSession;

// A curve sampled about one grid spacing apart, for meshing.
struct CurveSamples {
  std::vector<Vec2> points;  // from the curve's start to its end, both included
  // bulge[k]: signed area between the chord points[k] -> points[k+1] and the
  // true curve between them (positive when the curve lies to the right of
  // the chord, i.e. outside a cell that has the chord as a counter-clockwise
  // edge). Replacing a straight cell edge k by the curve changes the cell's
  // area by +bulge[k] (edge traversed k -> k+1) or -bulge[k] (backwards).
  std::vector<double> bulge;
  // arc[k] (curved curves only): arc_points_per_chord points on the true
  // curve strictly between points[k] and points[k+1] (equal parameter
  // steps). Cells with an edge on the curve carry them as extra polygon
  // vertices, so that their polygons follow the curve and cell-disk
  // intersections stay accurate there.
  static constexpr std::size_t arc_points_per_chord = 7;
  std::vector<std::vector<Vec2>> arc;
  std::size_t chords() const { return bulge.size(); }
};

// One gmsh curve of the surface's boundary, oriented along its loop: the
// material lies on its left.
struct BoundaryCurve {
  int tag = 0;
  std::string type;  // gmsh curve type: "Line", "Circle", "Ellipse", "BSpline", ...
  bool straight() const { return type == "Line"; }
  Vec2 start, end;   // shared exactly with the neighbouring curves of the loop
  double length = 0;
  // Points on the curve from start to end (both included); no chord's middle
  // is farther than PlateGeometry::boundary_tolerance from the curve. One
  // chord for a straight line.
  std::vector<Vec2> polyline;
  // Samples about one spacing apart; the second set has one chord more (a
  // free mesh needs an even number of boundary segments to be all quads).
  CurveSamples samples, samples_one_more;
};

// A closed boundary loop: the outer boundary (counter-clockwise) or a hole
// (clockwise), so that the material is always on the left.
struct BoundaryLoop {
  std::string name;  // "outer", or "hole_1", "hole_2", ... (holes ordered by centre x, then y)
  bool outer = false;
  std::vector<BoundaryCurve> curves;  // in loop order
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;  // bounding box of the curves
  double area = 0;                                // exact enclosed area (> 0)
  std::vector<std::string> curve_types;           // distinct gmsh curve types
  // The loop's polyline (the curves' polylines joined), first point not repeated.
  std::vector<Vec2> polyline() const;
};
using HoleLoop = BoundaryLoop;

// A polyline (open or closed) in metres, from a gmsh physical curve group.
struct NamedCurves {
  std::string name;
  std::vector<Vec2> a, b;  // segments a[k] -> b[k]
};

struct PlateGeometry {
  std::string file;
  double unit = 1e-3;                             // metres per geometry-file unit
  double xmin = 0, ymin = 0, xmax = 0, ymax = 0;  // bounding box of the outer boundary [m]
  BoundaryLoop outer;
  std::vector<BoundaryLoop> holes;
  std::vector<NamedCurves> physical_curves;  // user-named boundary groups
  // Largest distance allowed between a polyline chord's middle and its curve [m].
  double boundary_tolerance = 0;

  double exact_area() const;  // inside the outer boundary, minus the holes [m^2]
  // The outer loop and the holes' loops, material on the left of each.
  std::vector<const BoundaryLoop*> loops() const;
};

// The side of the bounding box a straight outer curve lies along: 0 left,
// 1 right, 2 bottom, 3 top (the order of the boundary sets' names), or -1
// for a curve that is not straight or not on a side (to 1e-9 of the plate).
int bounding_box_side(const BoundaryCurve& curve, const PlateGeometry& geometry);

// What can be known about a geometry file before choosing a spacing: its
// curves chained into loops, the bounding box and the area (to 1e-6).
// The gmsh model stays open in the session for sample_plate.
struct PlateOutline {
  std::string file;
  std::string gmsh_model;  // the gmsh model holding the geometry
  double unit = 1e-3;
  double xmin = 0, ymin = 0, xmax = 0, ymax = 0;  // [m]
  double area = 0;                                // [m^2]
  struct Curve {
    int tag = 0;
    std::string type;
    double t_start = 0, t_end = 0;  // parameters at the loop-wise start and end
    std::size_t start_vertex = 0, end_vertex = 0;
  };
  std::vector<std::vector<Curve>> loops;  // [0] is the outer loop; material on the left
  std::vector<Vec2> vertices;             // curve end points in file units, shared by the curves that meet there
  std::vector<std::pair<std::string, int>> physical_curve_names;  // as the file names them, with their lines
  std::vector<std::string> warnings;  // what the file draws that it likely did not mean (printed by pd-mesh)
};

// Opens `file` in the gmsh session (after refusing statements that are not
// geometry, see geo_file_check.hpp) and chains the surface's boundary curves
// into loops. Throws pd::Error naming the file for: unreadable or unparsable
// files, not exactly one plane surface, open boundaries.
PlateOutline read_plate_outline(GmshSession& session, const std::string& file, double unit);

struct RefinementRegion;
struct GradedSpacing;

// pd-mesh's lengths that are measured against the plate's outline, as typed
// (an empty text: the option left out) and in metres.
struct PlateSizedLengths {
  bool nbnug = false;                   // --grid nbnug: the only grid with boxes to pad
  std::string padding_text;             // --padding
  double padding = 0, horizon = 0, spacing = 0;
  std::string refine_region_text;       // --refine-region
  const RefinementRegion* refinement = nullptr;  // a region where its factor is above 1
  std::string graded_spacing_text;      // --graded-spacing
  const GradedSpacing* graded = nullptr;         // a graded mesh where enabled()
};

// A plate under 1 mm or over 10 m across is most likely a file in another
// unit: the warning naming --geo-unit ("FILE: ..."), or "" for a plate of
// ordinary size.
std::string plate_unit_warning(const PlateOutline& outline, const std::string& geo_unit);

// Refuses (pd::Error) the lengths that cannot be meant for this plate (a
// --padding of more than ten plates, a --refine-region that misses it,
// --graded-spacing on a plate without curves to grade towards), then
// returns the warnings ("FILE: ...") about lengths larger than the plate or
// most likely in another unit: a refused value gets its error alone.
std::vector<std::string> check_lengths_against_plate(const PlateOutline& outline, const PlateSizedLengths& lengths);

// Samples the outline's curves for a grid of spacing `spacing` [m] (the
// curved ones at `curved_spacing` if that is positive: a graded mesh's fine
// size at its curves) and checks
// that the boundary is simple: no loop crosses itself or another one (they
// may only touch at a shared vertex), no hole lies inside another hole or
// outside the outer boundary. Throws pd::Error naming the file and the place (mm).
PlateGeometry sample_plate(GmshSession& session, const PlateOutline& outline, double spacing,
                           double curved_spacing = 0);

// The boundary that decides which bonds exist (docs/mesher.md, "Bonds
// respect voids"): the loops' polylines, within 1e-6 dx of the curves, with
// contacts closer than 1e-9 dx counting as touching.
MaterialBoundary material_boundary(const PlateGeometry& geometry, double spacing, double horizon);

// read_plate_outline, then sample_plate.
PlateGeometry load_plate_geometry(GmshSession& session, const std::string& file, double unit, double spacing);

}  // namespace pd
