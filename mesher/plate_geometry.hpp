#pragma once
// A plate read from a gmsh geometry file: an axis-aligned rectangle with
// holes bounded by arbitrary curves. Everything here is in metres.
#include <map>
#include <string>
#include <vector>

#include "geometry.hpp"

namespace pd {

class GmshSession;

// A closed hole boundary sampled on the true curve at about the grid spacing.
struct HoleLoop {
  std::string name;                 // "hole_1", "hole_2", ... ordered by centre x, then y
  std::vector<Vec2> points;         // samples on the curve, no repetition of the first
  // bulge[k]: signed area between the chord points[k] -> points[k+1] and the
  // true curve between them (Green's formula; positive when the curve lies to
  // the right of the chord, i.e. outside a cell that has the chord as a
  // counter-clockwise edge). Replacing a straight cell edge k by the curve
  // changes the cell's area by +bulge[k] (edge traversed k -> k+1) or
  // -bulge[k] (traversed backwards).
  std::vector<double> bulge;
  // arc[k]: arc_points_per_segment points on the true curve strictly between
  // points[k] and points[k+1] (equal parameter steps). Cells with an edge on
  // the hole carry them as extra polygon vertices, so that their polygons
  // follow the curve and cell-disk intersections stay accurate there.
  static constexpr std::size_t arc_points_per_segment = 7;
  std::vector<std::vector<Vec2>> arc;
  std::vector<Vec2> fine;           // denser samples, for inside tests and distances
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;  // bounding box of the curve
  double area = 0;                  // exact enclosed area (polygon + bulges)
  std::vector<std::string> curve_types;  // gmsh curve types, e.g. "Circle", "Ellipse", "BSpline"
};

// A polyline (open or closed) in metres, from a gmsh physical curve group.
struct NamedCurves {
  std::string name;
  std::vector<Vec2> a, b;  // segments a[k] -> b[k]
};

struct PlateGeometry {
  std::string file;
  double unit = 1e-3;  // metres per geometry-file unit
  double xmin = 0, ymin = 0, xmax = 0, ymax = 0;  // outer rectangle [m]
  std::vector<HoleLoop> holes;
  std::vector<NamedCurves> physical_curves;  // user-named boundary groups

  double exact_area() const;  // plate minus holes [m^2]
};

// Opens `file` in the gmsh session and extracts the plate. Hole samples are
// spaced about `spacing` metres (an even count per hole: gmsh's quad
// recombination needs it); `fine` samples about spacing / 16.
// Throws pd::Error naming the file for: unreadable or unparsable files, not
// exactly one plane surface, open or self-intersecting boundaries, an outer
// boundary that is not an axis-aligned rectangle, holes touching or crossing
// the plate edge or each other.
PlateGeometry load_plate_geometry(GmshSession& session, const std::string& file, double unit, double spacing);

}  // namespace pd
