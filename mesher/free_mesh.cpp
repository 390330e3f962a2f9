#include "free_mesh.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "error.hpp"
#include "gmsh_session.hpp"

namespace pd {

namespace {

// Smallest interior angle of a polygon relative to the ideal one (60 degrees
// for triangles, 90 for quads): 1 for perfect elements, -> 0 for slivers.
double angle_quality(const double* vx, const double* vy, std::size_t n) {
  double smallest = M_PI;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t prev = (i + n - 1) % n, next = (i + 1) % n;
    const Vec2 a{vx[prev] - vx[i], vy[prev] - vy[i]}, b{vx[next] - vx[i], vy[next] - vy[i]};
    smallest = std::min(smallest, std::atan2(std::fabs(cross(a, b)), dot(a, b)));
  }
  const double ideal = n == 3 ? M_PI / 3 : M_PI / 2;
  return smallest / ideal;
}

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(a) << 32) | b; }

}  // namespace

RegionShape region_shape(const FreeRegions& regions, std::size_t region_index, double spacing,
                         std::vector<std::uint32_t>& global_vertex) {
  RegionShape shape;
  shape.spacing = spacing;
  global_vertex.clear();
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  for (const auto& loop : regions.regions.at(region_index).loops) {
    std::vector<std::uint32_t> ids;
    std::vector<std::uint8_t> curved;
    for (const auto& edge : loop) {
      curved.push_back(edge.curved ? 1 : 0);
      auto found = local.find(edge.from);
      if (found == local.end()) {
        found = local.emplace(edge.from, static_cast<std::uint32_t>(shape.vertices.size())).first;
        shape.vertices.push_back(regions.vertices[edge.from]);
        global_vertex.push_back(edge.from);
      }
      ids.push_back(found->second);
    }
    shape.loops.push_back(std::move(ids));
    shape.curved.push_back(std::move(curved));
  }
  return shape;
}

RegionMesh mesh_region(GmshSession& session, const std::string& file, const RegionShape& shape) {
  // The gmsh model is built in mm (shape.unit) whatever the geometry file's
  // unit: gmsh's internal tolerances are absolute and tuned for such numbers,
  // not for 1e-5, and the nodes' rounding below is 2^-20 mm (about 1 nm).
  // Before 5 December 2026 it was built in the file's unit: a plate written
  // in m was meshed in numbers of 1e-4 and its nodes rounded to 2^-20 m
  // (about 1 um, 0.8 % of a 0.125 mm cell) (docs/mesher.md).
  const double u = shape.unit, size = shape.spacing / u;
  gmsh::model::add("free_region");
  namespace geo = gmsh::model::geo;
  std::vector<int> point_of_vertex(shape.vertices.size(), 0);
  std::unordered_map<int, std::uint32_t> vertex_of_point;
  const auto point = [&](std::uint32_t v) {
    if (point_of_vertex[v] == 0) {
      point_of_vertex[v] = geo::addPoint(shape.vertices[v].x / u, shape.vertices[v].y / u, 0, size);
      vertex_of_point[point_of_vertex[v]] = v;
    }
    return point_of_vertex[v];
  };
  std::vector<int> loops, lines;
  std::vector<double> curved_lines;  // gmsh field options take numbers
  for (std::size_t l = 0; l < shape.loops.size(); ++l) {
    const auto& loop = shape.loops[l];
    std::vector<int> loop_lines;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      loop_lines.push_back(geo::addLine(point(loop[k]), point(loop[(k + 1) % loop.size()])));
      if (l < shape.curved.size() && shape.curved[l][k]) curved_lines.push_back(loop_lines.back());
    }
    lines.insert(lines.end(), loop_lines.begin(), loop_lines.end());
    loops.push_back(geo::addCurveLoop(loop_lines));
  }
  const int surface = geo::addPlaneSurface(loops);
  // One segment per boundary edge: the mesh nodes on the boundary are exactly
  // the region's vertices (lattice nodes and samples on the true curves).
  for (int line : lines) geo::mesh::setTransfiniteCurve(line, 2);
  geo::mesh::setRecombine(2, surface);
  geo::synchronize();

  // Frontal-Delaunay for quads; without CrossFieldClosestPoint = 0 it crashes
  // in gmsh 4.8 (docs/mesher.md).
  gmsh::option::setNumber("Mesh.Algorithm", 8);
  gmsh::option::setNumber("Mesh.CrossFieldClosestPoint", 0);
  gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1);
  const bool graded = shape.fine_size > 0 && !curved_lines.empty();
  if (graded) {
    // theory.md Sec. 7.4: h(d) = DXF + (dx - DXF) min(1, d / L), d the
    // distance from the curved edges (gmsh measures it to points spread along
    // them, 8 per edge, within DXF / 16 of the chords).
    namespace field = gmsh::model::mesh::field;
    const int distance = field::add("Distance");
    field::setNumbers(distance, "CurvesList", curved_lines);
    field::setNumber(distance, "NumPointsPerCurve", 8);
    const int threshold = field::add("Threshold");
    field::setNumber(threshold, "InField", distance);
    field::setNumber(threshold, "SizeMin", shape.fine_size / u);
    field::setNumber(threshold, "SizeMax", size);
    field::setNumber(threshold, "DistMin", 0);
    field::setNumber(threshold, "DistMax", shape.grading_length / u);
    field::setAsBackgroundMesh(threshold);
  }
  gmsh::option::setNumber("Mesh.MeshSizeMin", graded ? shape.fine_size / u : size);
  gmsh::option::setNumber("Mesh.MeshSizeMax", size);
  // Graded: the size field alone (the boundary edges are fixed anyway).
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", graded ? 0 : 1);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", graded ? 0 : 1);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  gmsh::model::mesh::generate(2);
  session.throw_on_logged_errors(file, "meshing a free region");

  RegionMesh mesh;
  std::vector<std::size_t> node_tags;
  std::vector<double> coords, params;
  gmsh::model::mesh::getNodes(node_tags, coords, params, -1, -1, true, false);
  std::size_t max_tag = 0;
  for (auto t : node_tags) max_tag = std::max(max_tag, t);
  std::vector<std::int64_t> index_of_tag(max_tag + 1, -1);
  // Interior node coordinates rounded to a binary quantum of 2^-20 model
  // units (about 1 nm for mm): what is left of gmsh's round-off differences.
  // A conforming mesh's total area does not depend on them.
  const double quantum = std::ldexp(1.0, -20);
  const auto snap = [&](double v) { return std::round(v / quantum) * quantum * u; };
  for (std::size_t k = 0; k < node_tags.size(); ++k) {
    index_of_tag[node_tags[k]] = static_cast<std::int64_t>(mesh.nodes.size());
    mesh.nodes.push_back({snap(coords[3 * k]), snap(coords[3 * k + 1])});
    mesh.vertex_of_node.push_back(-1);
  }
  // Nodes on the shape's vertices take their exact coordinates.
  for (const auto& [tag, v] : vertex_of_point) {
    std::vector<std::size_t> tags;
    std::vector<double> c, p;
    gmsh::model::mesh::getNodes(tags, c, p, 0, tag, false, false);
    if (tags.size() != 1 || index_of_tag[tags[0]] < 0) continue;
    const auto n = static_cast<std::size_t>(index_of_tag[tags[0]]);
    mesh.nodes[n] = shape.vertices[v];
    mesh.vertex_of_node[n] = v;
  }
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, element_nodes;
  gmsh::model::mesh::getElements(types, element_tags, element_nodes, 2, surface);
  for (std::size_t t = 0; t < types.size(); ++t) {
    const std::size_t n = types[t] == 2 ? 3 : types[t] == 3 ? 4 : 0;
    if (n == 0) throw file_error(file, "gmsh produced an element of unexpected type " + std::to_string(types[t]));
    for (std::size_t k = 0; k < element_nodes[t].size(); ++k) {
      mesh.element_nodes.push_back(static_cast<std::uint32_t>(index_of_tag.at(element_nodes[t][k])));
      if ((k + 1) % n == 0) mesh.element_offsets.push_back(static_cast<std::uint32_t>(mesh.element_nodes.size()));
    }
  }
  gmsh::model::remove();
  if (mesh.element_offsets.size() < 2) throw file_error(file, "gmsh produced no elements for a free region");
  return mesh;
}

void append_region_cells(const std::string& file, const FreeRegions& regions, std::size_t region_index,
                         const std::vector<std::uint32_t>& global_vertex, const RegionMesh& mesh, Region kind,
                         ParticleSet& particles, FreeMeshStats& stats) {
  // Chords of the boundary curves, by their end vertices.
  std::unordered_map<std::uint64_t, const RegionEdge*> chord_of;
  for (const auto& loop : regions.regions.at(region_index).loops)
    for (const auto& edge : loop)
      if (edge.samples) chord_of[pair_key(edge.from, edge.to)] = &edge;
  const auto global = [&](std::uint32_t node) -> std::int64_t {
    const auto v = mesh.vertex_of_node[node];
    return v < 0 ? -1 : static_cast<std::int64_t>(global_vertex[static_cast<std::size_t>(v)]);
  };
  if (particles.cell_offsets.empty()) particles.cell_offsets.push_back(0);
  for (std::size_t e = 0; e + 1 < mesh.element_offsets.size(); ++e) {
    const std::size_t n = mesh.element_offsets[e + 1] - mesh.element_offsets[e];
    std::uint32_t ids[4];
    double vx[4], vy[4];
    for (std::size_t v = 0; v < n; ++v) {
      ids[v] = mesh.element_nodes[mesh.element_offsets[e] + v];
      vx[v] = mesh.nodes[ids[v]].x;
      vy[v] = mesh.nodes[ids[v]].y;
    }
    double area = polygon_signed_area(vx, vy, n);
    if (area < 0) {  // make counter-clockwise
      std::reverse(ids, ids + n);
      std::reverse(vx, vx + n);
      std::reverse(vy, vy + n);
      area = -area;
    }
    // The cell polygon: the element's corners, plus the arc points of every
    // edge that is a chord of a curved boundary. The volume is the straight
    // element's area plus the exact bulges.
    std::vector<Vec2> polygon;
    double correction = 0;
    for (std::size_t v = 0; v < n; ++v) {
      polygon.push_back({vx[v], vy[v]});
      const auto a = global(ids[v]), b = global(ids[(v + 1) % n]);
      if (a < 0 || b < 0) continue;
      const auto ua = static_cast<std::uint32_t>(a), ub = static_cast<std::uint32_t>(b);
      const bool forward = chord_of.count(pair_key(ua, ub)) > 0;
      const auto found = chord_of.find(forward ? pair_key(ua, ub) : pair_key(ub, ua));
      if (found == chord_of.end()) continue;
      const RegionEdge& edge = *found->second;
      correction += (forward ? 1 : -1) * edge.samples->bulge[edge.chord];
      if (!edge.curved) continue;
      const auto& arc = edge.samples->arc[edge.chord];
      if (forward)
        polygon.insert(polygon.end(), arc.begin(), arc.end());
      else
        polygon.insert(polygon.end(), arc.rbegin(), arc.rend());
      ++stats.curved_edges;
    }
    const double volume = area + correction;
    if (!(volume > 0))
      throw file_error(file, "an element next to a curved boundary has no positive area after the curved-edge "
                             "correction; use a smaller spacing");
    std::vector<double> px(polygon.size()), py(polygon.size());
    for (std::size_t v = 0; v < polygon.size(); ++v) px[v] = polygon[v].x, py[v] = polygon[v].y;
    const Vec2 centroid = polygon_centroid(px.data(), py.data(), px.size());
    particles.x.push_back(centroid.x);
    particles.y.push_back(centroid.y);
    particles.volume.push_back(volume);
    particles.cell_size.push_back(std::sqrt(volume));
    particles.horizon.push_back(0);
    particles.region.push_back(static_cast<std::uint8_t>(kind));
    particles.material.push_back(0);
    particles.cell_vx.insert(particles.cell_vx.end(), px.begin(), px.end());
    particles.cell_vy.insert(particles.cell_vy.end(), py.begin(), py.end());
    particles.cell_offsets.push_back(particles.cell_vx.size());
    (n == 3 ? stats.triangles : stats.quads)++;
    stats.min_area = std::min(stats.min_area, volume);
    stats.max_area = std::max(stats.max_area, volume);
    stats.sum_area += volume;
    stats.worst_quality = std::min(stats.worst_quality, angle_quality(vx, vy, n));
  }
}

}  // namespace pd
