#include "fem_mesh.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "error.hpp"
#include "gmsh_session.hpp"

namespace pd::validation {
namespace {

// OpenCASCADE works to a tolerance of about 1e-7 model units: model in mm, not in m.
constexpr double mm_per_m = 1e3;

struct Circle {
  double cx, cy, r;
};

Circle circle_of(const HoleLoop& hole, const std::string& file) {
  for (const auto& type : hole.curve_types)
    if (type != "Circle" && type != "Ellipse")
      throw Error(file + ": " + hole.name + " is bounded by a '" + type +
                  "' curve; the FEM reference handles circular holes only");
  const double wx = hole.xmax - hole.xmin, wy = hole.ymax - hole.ymin;
  if (std::fabs(wx - wy) > 1e-6 * wx)
    throw Error(file + ": " + hole.name + " is not a circle (bounding box " + std::to_string(wx) + " x " +
                std::to_string(wy) + " m)");
  return {0.5 * (hole.xmin + hole.xmax), 0.5 * (hole.ymin + hole.ymax), 0.25 * (wx + wy)};
}

// Size field: h at the given curves and points, growing linearly to `far`
// over `grading` [m]; second-order triangles with mid-side nodes on the curves.
void set_size_field(const std::vector<double>& curves, const std::vector<double>& points, double h, double far,
                    double grading) {
  const double s = mm_per_m;
  const int distance = gmsh::model::mesh::field::add("Distance");
  if (!curves.empty()) gmsh::model::mesh::field::setNumbers(distance, "CurvesList", curves);
  if (!points.empty()) gmsh::model::mesh::field::setNumbers(distance, "PointsList", points);
  gmsh::model::mesh::field::setNumber(distance, "NumPointsPerCurve", 400);
  const int threshold = gmsh::model::mesh::field::add("Threshold");
  gmsh::model::mesh::field::setNumber(threshold, "InField", distance);
  gmsh::model::mesh::field::setNumber(threshold, "SizeMin", h * s);
  gmsh::model::mesh::field::setNumber(threshold, "SizeMax", far * s);
  gmsh::model::mesh::field::setNumber(threshold, "DistMin", 0);
  gmsh::model::mesh::field::setNumber(threshold, "DistMax", grading * s);
  gmsh::model::mesh::field::setAsBackgroundMesh(threshold);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.Algorithm", 6);
  gmsh::option::setNumber("Mesh.ElementOrder", 2);
  gmsh::option::setNumber("Mesh.SecondOrderLinear", 0);  // mid-side nodes on the true curves
}

// Meshes every surface of the model as one physical group "PLATE", reads the
// nodes and 6-node triangles back and writes `inp_path` (in metres).
FemMesh mesh_and_write(GmshSession& session, const std::string& file, const std::string& inp_path) {
  const double s = mm_per_m;
  std::vector<std::pair<int, int>> surfaces;
  gmsh::model::getEntities(surfaces, 2);
  std::vector<int> surface_tags;
  for (const auto& e : surfaces) surface_tags.push_back(e.second);
  const int group = gmsh::model::addPhysicalGroup(2, surface_tags);
  gmsh::model::setPhysicalName(2, group, "PLATE");
  gmsh::model::mesh::generate(2);
  session.throw_on_logged_errors(file, "FEM meshing");

  FemMesh mesh;
  mesh.element_set = "PLATE";
  std::vector<std::size_t> tags;
  std::vector<double> coords, params;
  gmsh::model::mesh::getNodes(tags, coords, params);
  std::map<std::size_t, std::uint32_t> index;
  for (std::size_t k = 0; k < tags.size(); ++k) {
    index[tags[k]] = static_cast<std::uint32_t>(k);
    mesh.node_id.push_back(tags[k]);
    mesh.x.push_back(coords[3 * k] / s);
    mesh.y.push_back(coords[3 * k + 1] / s);
  }
  std::vector<std::size_t> element_tags, element_nodes;
  gmsh::model::mesh::getElementsByType(9, element_tags, element_nodes);  // 9 = 6-node triangle
  if (element_tags.empty()) throw Error(file + ": the FEM mesh has no 6-node triangles");
  for (std::size_t e = 0; e < element_tags.size(); ++e) {
    std::array<std::uint32_t, 6> t{};
    for (int k = 0; k < 6; ++k) t[k] = index.at(element_nodes[6 * e + k]);
    mesh.triangles.push_back(t);
  }
  // gmsh writes the nodes and the elements of the physical group, scaled to metres.
  gmsh::option::setNumber("Mesh.SaveAll", 0);
  gmsh::option::setNumber("Mesh.ScalingFactor", 1.0 / s);
  gmsh::write(inp_path);
  session.throw_on_logged_errors(inp_path, "writing the FEM mesh");
  mesh.inp_mesh_file = inp_path;
  return mesh;
}

}  // namespace

FemMesh write_fem_mesh(const PlateGeometry& g, const FemMeshOptions& options, const std::string& inp_path) {
  if (!(options.hole_size > 0)) throw Error("FEM mesh: the element size at the holes must be positive");
  std::vector<Circle> circles;
  for (const auto& hole : g.holes) circles.push_back(circle_of(hole, g.file));

  GmshSession session;
  gmsh::model::add("fem_reference");
  namespace occ = gmsh::model::occ;
  const double s = mm_per_m;
  const double width = (g.xmax - g.xmin) * s, height = (g.ymax - g.ymin) * s;
  const int plate = occ::addRectangle(g.xmin * s, g.ymin * s, 0, width, height);
  std::vector<std::pair<int, int>> disks, out;
  std::vector<std::vector<std::pair<int, int>>> out_map;
  for (const auto& c : circles) disks.push_back({2, occ::addDisk(c.cx * s, c.cy * s, 0, c.r * s, c.r * s)});
  occ::cut({{2, plate}}, disks, out, out_map);
  if (options.clamp_width > 0) {
    const double cw = options.clamp_width * s;
    const int left = occ::addRectangle(g.xmin * s, g.ymin * s, 0, cw, height);
    const int right = occ::addRectangle(g.xmax * s - cw, g.ymin * s, 0, cw, height);
    std::vector<std::pair<int, int>> fragments;
    occ::fragment(out, {{2, left}, {2, right}}, fragments, out_map);
  }
  occ::synchronize();
  session.throw_on_logged_errors(g.file, "FEM geometry");

  // Size field: h at the hole curves, growing linearly to far_size over grading_distance.
  std::vector<std::pair<int, int>> curves;
  gmsh::model::getEntities(curves, 1);
  std::vector<double> hole_curves;
  for (const auto& [dim, tag] : curves) {
    std::string type;
    gmsh::model::getType(dim, tag, type);
    if (type == "Circle" || type == "Ellipse") hole_curves.push_back(tag);
  }
  // The ends of the clamp lines on the free edges are singular points of the
  // elastic field (a clamped edge meets a free one): refine there as at the holes.
  std::vector<double> clamp_ends;
  if (options.clamp_width > 0) {
    std::vector<std::pair<int, int>> points;
    gmsh::model::getEntities(points, 0);
    for (const auto& [dim, tag] : points) {
      std::vector<double> xyz, parametric;
      gmsh::model::getValue(dim, tag, parametric, xyz);
      const double x = xyz[0] / s;
      if (std::fabs(x - (g.xmin + options.clamp_width)) < 1e-9 || std::fabs(x - (g.xmax - options.clamp_width)) < 1e-9)
        clamp_ends.push_back(tag);
    }
  }
  const double far = options.far_size > 0 ? options.far_size : 4 * options.hole_size;
  set_size_field(hole_curves, clamp_ends, options.hole_size, far, options.grading_distance);
  return mesh_and_write(session, g.file, inp_path);
}

void check_cracked_plate(const PlateGeometry& g, const FemCrack& crack, double strip_width) {
  if (!g.holes.empty())
    throw Error(g.file + ": the cracked-plate FEM reference handles plates without holes (found " + g.holes.front().name +
                ")");
  const double w = strip_width;
  if (!(crack.x1 > g.xmin && crack.x2 < g.xmax && crack.x1 < crack.x2 && crack.y > g.ymin + w && crack.y < g.ymax - w))
    throw Error(g.file + ": the crack must lie inside the plate, between the load strips");
}

FemMesh write_cracked_plate_mesh(const PlateGeometry& g, const FemCrack& crack, const CrackedPlateMeshOptions& options,
                                 const std::string& inp_path) {
  if (!(options.tip_size > 0) || !(options.strip_width > 0))
    throw Error("FEM mesh: the element size at the crack tips and the strip width must be positive");
  check_cracked_plate(g, crack, options.strip_width);
  const double w = options.strip_width;

  GmshSession session;
  gmsh::model::add("fem_cracked_plate");
  // Without coherence the built-in kernel keeps two curves between the same
  // points: the two crack faces.
  gmsh::option::setNumber("Geometry.AutoCoherence", 0);
  namespace geo = gmsh::model::geo;
  const double s = mm_per_m;
  const auto point = [&](double x, double y) { return geo::addPoint(x * s, y * s, 0); };
  const int b0 = point(g.xmin, g.ymin), b1 = point(g.xmax, g.ymin);
  const int sb0 = point(g.xmin, g.ymin + w), sb1 = point(g.xmax, g.ymin + w);
  const int m0 = point(g.xmin, crack.y), tip1 = point(crack.x1, crack.y), tip2 = point(crack.x2, crack.y),
            m1 = point(g.xmax, crack.y);
  const int st0 = point(g.xmin, g.ymax - w), st1 = point(g.xmax, g.ymax - w);
  const int t0 = point(g.xmin, g.ymax), t1 = point(g.xmax, g.ymax);
  const auto line = [](int from, int to) { return geo::addLine(from, to); };
  const int bottom = line(b0, b1), bottom_right = line(b1, sb1), bottom_strip = line(sb1, sb0), bottom_left = line(sb0, b0);
  const int lower_right = line(sb1, m1), ligament_right = line(m1, tip2), lower_face = line(tip2, tip1),
            ligament_left = line(tip1, m0), lower_left = line(m0, sb0);
  const int upper_face = line(tip1, tip2), upper_right = line(m1, st1), top_strip = line(st1, st0),
            upper_left = line(st0, m0);
  const int top_right = line(st1, t1), top = line(t1, t0), top_left = line(t0, st0);
  const auto surface = [](const std::vector<int>& curves) {
    return geo::addPlaneSurface({geo::addCurveLoop(curves)});
  };
  surface({bottom, bottom_right, bottom_strip, bottom_left});
  surface({-bottom_strip, lower_right, ligament_right, lower_face, ligament_left, lower_left});
  surface({-ligament_left, upper_face, -ligament_right, upper_right, top_strip, upper_left});
  surface({-top_strip, top_right, top, top_left});
  geo::synchronize();
  session.throw_on_logged_errors(g.file, "FEM geometry");
  // The tips, and the ends of the strip lines on the free edges (a held edge
  // meeting a free one), are singular points of the elastic field.
  const double far = options.far_size > 0 ? options.far_size : 20 * options.tip_size;
  const double grading = options.grading_distance > 0 ? options.grading_distance : 10 * far;
  set_size_field({}, {double(tip1), double(tip2), double(sb0), double(sb1), double(st0), double(st1)},
                 options.tip_size, far, grading);
  return mesh_and_write(session, g.file, inp_path);
}

}  // namespace pd::validation
