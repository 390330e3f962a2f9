#include "free_mesh.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <map>

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

struct HoleNode {
  std::size_t hole, sample;
};

}  // namespace

void append_free_mesh(GmshSession& session, const PlateGeometry& g, double x0, double y0, double x1, double y1,
                      long nx, long ny, const std::vector<std::size_t>& holes, double spacing, Region region,
                      ParticleSet& particles, FreeMeshStats& stats) {
  // The gmsh model is built in the geometry file's units (usually mm): gmsh's
  // internal tolerances are absolute and tuned for such numbers, not for 1e-5.
  const double u = g.unit;
  const double size = spacing / u;
  gmsh::model::add("free_region");
  namespace geo = gmsh::model::geo;
  const int c0 = geo::addPoint(x0 / u, y0 / u, 0, size);
  const int c1 = geo::addPoint(x1 / u, y0 / u, 0, size);
  const int c2 = geo::addPoint(x1 / u, y1 / u, 0, size);
  const int c3 = geo::addPoint(x0 / u, y1 / u, 0, size);
  const int bottom = geo::addLine(c0, c1), right = geo::addLine(c1, c2);
  const int top = geo::addLine(c2, c3), left = geo::addLine(c3, c0);
  std::vector<int> loops{geo::addCurveLoop({bottom, right, top, left})};

  std::map<int, HoleNode> point_to_sample;  // gmsh point tag -> hole sample
  std::vector<int> hole_lines;
  for (const auto h : holes) {
    const auto& hole = g.holes[h];
    std::vector<int> pts, lines;
    for (std::size_t k = 0; k < hole.points.size(); ++k) {
      pts.push_back(geo::addPoint(hole.points[k].x / u, hole.points[k].y / u, 0, size));
      point_to_sample[pts.back()] = {h, k};
    }
    for (std::size_t k = 0; k < pts.size(); ++k) lines.push_back(geo::addLine(pts[k], pts[(k + 1) % pts.size()]));
    hole_lines.insert(hole_lines.end(), lines.begin(), lines.end());
    loops.push_back(geo::addCurveLoop(lines));
  }
  const int surface = geo::addPlaneSurface(loops);
  // Sides: exactly the lattice segments. Hole chords: one segment each, so the
  // mesh nodes on a hole are exactly the samples on the true curve.
  geo::mesh::setTransfiniteCurve(bottom, static_cast<int>(nx + 1));
  geo::mesh::setTransfiniteCurve(top, static_cast<int>(nx + 1));
  geo::mesh::setTransfiniteCurve(left, static_cast<int>(ny + 1));
  geo::mesh::setTransfiniteCurve(right, static_cast<int>(ny + 1));
  for (int line : hole_lines) geo::mesh::setTransfiniteCurve(line, 2);
  geo::mesh::setRecombine(2, surface);
  geo::synchronize();

  // Frontal-Delaunay for quads; without CrossFieldClosestPoint = 0 it crashes
  // in gmsh 4.8 (docs/mesher.md).
  gmsh::option::setNumber("Mesh.Algorithm", 8);
  gmsh::option::setNumber("Mesh.CrossFieldClosestPoint", 0);
  gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1);
  gmsh::option::setNumber("Mesh.MeshSizeMin", size);
  gmsh::option::setNumber("Mesh.MeshSizeMax", size);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  gmsh::model::mesh::generate(2);
  session.throw_on_logged_errors(g.file, "meshing a free region");

  // Node coordinates by tag.
  std::vector<std::size_t> node_tags;
  std::vector<double> coords, params;
  gmsh::model::mesh::getNodes(node_tags, coords, params, -1, -1, true, false);
  std::size_t max_tag = 0;
  for (auto t : node_tags) max_tag = std::max(max_tag, t);
  // gmsh's smoothing leaves run-to-run differences in the last bits of
  // interior node coordinates. Rounding them to a binary quantum of 2^-20
  // file units (about 1 nm for mm) makes the particle file byte-identical
  // across runs; a conforming mesh's total area does not depend on interior
  // node positions, so no area is lost.
  const double quantum = std::ldexp(1.0, -20);
  const auto snap = [&](double v) { return std::round(v / quantum) * quantum * u; };
  std::vector<Vec2> node_xy(max_tag + 1);
  for (std::size_t k = 0; k < node_tags.size(); ++k) node_xy[node_tags[k]] = {snap(coords[3 * k]), snap(coords[3 * k + 1])};
  std::map<std::size_t, HoleNode> node_to_sample;
  for (const auto& [point, sample] : point_to_sample) {
    std::vector<std::size_t> tags;
    std::vector<double> c, p;
    gmsh::model::mesh::getNodes(tags, c, p, 0, point, false, false);
    if (tags.size() != 1) continue;
    node_to_sample[tags[0]] = sample;
    // Nodes on a hole are the samples on the true curve, exactly.
    node_xy[tags[0]] = g.holes[sample.hole].points[sample.sample];
  }
  // Nodes on the rectangle's sides sit on the lattice, exactly.
  for (int side : {bottom, right, top, left}) {
    std::vector<std::size_t> tags;
    std::vector<double> c, p;
    gmsh::model::mesh::getNodes(tags, c, p, 1, side, true, false);
    for (std::size_t k = 0; k < tags.size(); ++k) {
      auto& xy = node_xy[tags[k]];
      if (side == bottom || side == top) {
        xy.x = x0 + std::round((c[3 * k] * u - x0) / (x1 - x0) * nx) * ((x1 - x0) / nx);
        xy.y = side == bottom ? y0 : y1;
      } else {
        xy.y = y0 + std::round((c[3 * k + 1] * u - y0) / (y1 - y0) * ny) * ((y1 - y0) / ny);
        xy.x = side == left ? x0 : x1;
      }
    }
  }

  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, element_nodes;
  gmsh::model::mesh::getElements(types, element_tags, element_nodes, 2, surface);
  if (particles.cell_offsets.empty()) particles.cell_offsets.push_back(0);
  std::size_t elements = 0;
  for (std::size_t t = 0; t < types.size(); ++t) {
    const std::size_t n = types[t] == 2 ? 3 : types[t] == 3 ? 4 : 0;
    if (n == 0) throw file_error(g.file, "gmsh produced an element of unexpected type " + std::to_string(types[t]));
    const auto& nodes = element_nodes[t];
    for (std::size_t e = 0; e * n < nodes.size(); ++e) {
      std::size_t ids[4];
      double vx[4], vy[4];
      for (std::size_t v = 0; v < n; ++v) {
        ids[v] = nodes[e * n + v];
        vx[v] = node_xy[ids[v]].x;
        vy[v] = node_xy[ids[v]].y;
      }
      double area = polygon_signed_area(vx, vy, n);
      if (area < 0) {  // make counter-clockwise
        std::reverse(ids, ids + n);
        std::reverse(vx, vx + n);
        std::reverse(vy, vy + n);
        area = -area;
      }
      // The cell polygon: the element's corners, plus the arc points of every
      // edge that lies on a hole (both end nodes consecutive samples of one
      // hole). The volume is the straight element's area plus the exact bulges.
      std::vector<Vec2> polygon;
      double correction = 0;
      for (std::size_t v = 0; v < n; ++v) {
        polygon.push_back({vx[v], vy[v]});
        const auto a = node_to_sample.find(ids[v]), b = node_to_sample.find(ids[(v + 1) % n]);
        if (a == node_to_sample.end() || b == node_to_sample.end() || a->second.hole != b->second.hole) continue;
        const auto& hole = g.holes[a->second.hole];
        const std::size_t count = hole.points.size(), ka = a->second.sample, kb = b->second.sample;
        if ((ka + 1) % count == kb) {
          correction += hole.bulge[ka];
          polygon.insert(polygon.end(), hole.arc[ka].begin(), hole.arc[ka].end());
          ++stats.curved_edges;
        } else if ((kb + 1) % count == ka) {
          correction -= hole.bulge[kb];
          polygon.insert(polygon.end(), hole.arc[kb].rbegin(), hole.arc[kb].rend());
          ++stats.curved_edges;
        }
      }
      const double volume = area + correction;
      if (!(volume > 0))
        throw file_error(g.file, "an element next to a hole has no positive area after the curved-edge "
                                 "correction; use a smaller spacing");
      std::vector<double> px(polygon.size()), py(polygon.size());
      for (std::size_t v = 0; v < polygon.size(); ++v) px[v] = polygon[v].x, py[v] = polygon[v].y;
      const Vec2 centroid = polygon_centroid(px.data(), py.data(), px.size());
      particles.x.push_back(centroid.x);
      particles.y.push_back(centroid.y);
      particles.volume.push_back(volume);
      particles.cell_size.push_back(std::sqrt(volume));
      particles.horizon.push_back(0);
      particles.region.push_back(static_cast<std::uint8_t>(region));
      particles.material.push_back(0);
      particles.cell_vx.insert(particles.cell_vx.end(), px.begin(), px.end());
      particles.cell_vy.insert(particles.cell_vy.end(), py.begin(), py.end());
      particles.cell_offsets.push_back(particles.cell_vx.size());
      (n == 3 ? stats.triangles : stats.quads)++;
      stats.min_area = std::min(stats.min_area, volume);
      stats.max_area = std::max(stats.max_area, volume);
      stats.sum_area += volume;
      stats.worst_quality = std::min(stats.worst_quality, angle_quality(vx, vy, n));
      ++elements;
    }
  }
  gmsh::model::remove();
  if (elements == 0) throw file_error(g.file, "gmsh produced no elements for a free region");
}

}  // namespace pd
