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
  const int distance = gmsh::model::mesh::field::add("Distance");
  gmsh::model::mesh::field::setNumbers(distance, "CurvesList", hole_curves);
  if (!clamp_ends.empty()) gmsh::model::mesh::field::setNumbers(distance, "PointsList", clamp_ends);
  gmsh::model::mesh::field::setNumber(distance, "NumPointsPerCurve", 400);
  const int threshold = gmsh::model::mesh::field::add("Threshold");
  gmsh::model::mesh::field::setNumber(threshold, "InField", distance);
  gmsh::model::mesh::field::setNumber(threshold, "SizeMin", options.hole_size * s);
  gmsh::model::mesh::field::setNumber(threshold, "SizeMax", far * s);
  gmsh::model::mesh::field::setNumber(threshold, "DistMin", 0);
  gmsh::model::mesh::field::setNumber(threshold, "DistMax", options.grading_distance * s);
  gmsh::model::mesh::field::setAsBackgroundMesh(threshold);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.Algorithm", 6);
  gmsh::option::setNumber("Mesh.ElementOrder", 2);
  gmsh::option::setNumber("Mesh.SecondOrderLinear", 0);  // mid-side nodes on the true curves

  std::vector<std::pair<int, int>> surfaces;
  gmsh::model::getEntities(surfaces, 2);
  std::vector<int> surface_tags;
  for (const auto& e : surfaces) surface_tags.push_back(e.second);
  const int group = gmsh::model::addPhysicalGroup(2, surface_tags);
  gmsh::model::setPhysicalName(2, group, "PLATE");
  gmsh::model::mesh::generate(2);
  session.throw_on_logged_errors(g.file, "FEM meshing");

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
  if (element_tags.empty()) throw Error(g.file + ": the FEM mesh has no 6-node triangles");
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

}  // namespace pd::validation
