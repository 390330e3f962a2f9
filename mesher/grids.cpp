#include "grids.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "box_spacing.hpp"
#include "error.hpp"
#include "lattice.hpp"
#include "mesh_worker.hpp"
#include "neighbor_search.hpp"

namespace pd {

namespace {

// For every boundary curve off the lattice lines, the smallest distance from
// a particle's centroid to it, split by curved and straight curves.
void nearest_centroid_distances(const ParticleSet& p, const PlateGeometry& g, const Lattice& lattice,
                                GridReport& report) {
  if (p.size() == 0) return;
  const NeighborSearch search(p.x, p.y);
  std::vector<std::uint32_t> near;
  for (const auto* loop : g.loops())
    for (const auto& c : loop->curves) {
      if (on_lattice_line(c, lattice)) continue;
      double& best = c.straight() ? report.min_distance_to_straight_off_lattice : report.min_distance_to_curved;
      for (std::size_t k = 0; k + 1 < c.polyline.size(); ++k) {
        const Vec2 a = c.polyline[k], b = c.polyline[k + 1];
        // Cells touch the boundary: some centroid lies within a spacing.
        const double half = 0.5 * std::hypot(b.x - a.x, b.y - a.y);
        search.within(0.5 * (a.x + b.x), 0.5 * (a.y + b.y), half + std::min(best, lattice.dx), near);
        for (auto i : near) best = std::min(best, point_segment_distance({p.x[i], p.y[i]}, a, b));
      }
    }
}

// A point where two curves of the boundary touch tangentially (two holes,
// or a hole and the edge, meeting at one point with a zero angle between
// them) must be a lattice node for the free cells: elsewhere the lattice
// lines and samples beside it crowd into the two zero-angle corners, where
// gmsh failed ("Unable to recover the edge", "Singular matrix 3x3") or, on
// the free grid, left cells that are not exact (before 7 December 2026).
// pd::Error naming the point, the curves and what to do.
void check_tangent_contacts(const PlateGeometry& g, const Lattice& lattice) {
  struct End {
    Vec2 at, direction;
    int tag;
  };
  std::vector<End> ends;
  for (const auto* loop : g.loops())
    for (const auto& c : loop->curves) {
      const auto& p = c.polyline;
      if (p.size() < 2) continue;
      ends.push_back({p.front(), {p[1].x - p[0].x, p[1].y - p[0].y}, c.tag});
      ends.push_back({p.back(), {p[p.size() - 2].x - p.back().x, p[p.size() - 2].y - p.back().y}, c.tag});
    }
  // Tangent curves' first chords differ by about sqrt(tolerance / radius)
  // (1e-3 rad); a corner the boundary draws is far wider than this.
  const double tangent_angle = 0.02;  // [rad]
  std::map<std::pair<double, double>, std::vector<std::size_t>> at_point;  // (curve ends share points exactly)
  for (std::size_t k = 0; k < ends.size(); ++k) at_point[{ends[k].at.x, ends[k].at.y}].push_back(k);
  for (const auto& [point, meeting] : at_point) {
    if (meeting.size() < 4) continue;  // two curve ends: a vertex of one loop, no contact
    for (std::size_t m = 0; m < meeting.size(); ++m)
    for (std::size_t n = m + 1; n < meeting.size(); ++n) {
      const std::size_t a = meeting[m], b = meeting[n];
      if (ends[b].tag == ends[a].tag) continue;
      const Vec2 u = ends[a].direction, v = ends[b].direction;
      if (!(std::atan2(std::fabs(cross(u, v)), dot(u, v)) < tangent_angle)) continue;
      const double i = (ends[a].at.x - lattice.x0) / lattice.dx, j = (ends[a].at.y - lattice.y0) / lattice.dx;
      if (std::fabs(i - std::round(i)) <= 1e-6 && std::fabs(j - std::round(j)) <= 1e-6) continue;
      char text[700];
      std::snprintf(text, sizeof text,
                    "curves %d and %d touch tangentially at (%.6g, %.6g) mm, between the nodes of the %g mm "
                    "lattice: the free cells cannot follow the zero-angle corners on either side of it; "
                    "place the point of contact on a lattice node (a whole number of spacings from (%.6g, %.6g) "
                    "mm), keep the curves apart or let them overlap, or give --grid uniform",
                    ends[a].tag, ends[b].tag, ends[a].at.x * 1e3, ends[a].at.y * 1e3, lattice.dx * 1e3,
                    lattice.x0 * 1e3, lattice.y0 * 1e3);
      throw file_error(g.file, text);
    }
  }
}

}  // namespace

ParticleSet build_grid(GmshSession& session, const PlateGeometry& g, const GridOptions& given, GridReport& report) {
  const Lattice lattice = plate_lattice(g, given.spacing);
  // The spacing as the lattice has it (the given one to its round-off, or the
  // exact division of the plate that a rounded print of it meant).
  GridOptions o = given;
  o.spacing = lattice.dx;
  report.cells = classify_cells(g, lattice, o.grid, o.padding);
  const CellMap& cells = report.cells;
  ParticleSet p;
  p.grid = o.grid;
  p.spacing = o.spacing;
  p.xmin = g.xmin, p.ymin = g.ymin, p.xmax = g.xmax, p.ymax = g.ymax;
  // A lattice that runs past a side without a straight curve (plate_lattice)
  // is the file's box: the solver lays its lattice over that box.
  const double overhang = 1e-6 * lattice.dx;
  if (lattice.x0 < g.xmin - overhang) p.xmin = lattice.x0;
  if (lattice.y0 < g.ymin - overhang) p.ymin = lattice.y0;
  if (const double end = lattice.x0 + static_cast<double>(lattice.nx) * lattice.dx; end > g.xmax + overhang) p.xmax = end;
  if (const double end = lattice.y0 + static_cast<double>(lattice.ny) * lattice.dx; end > g.ymax + overhang) p.ymax = end;
  p.cell_offsets.push_back(0);
  append_lattice_squares(p, lattice.x0, lattice.y0, lattice.dx, 0, lattice.nx, 0, lattice.ny,
                         [&](long i, long j) { return cells.at(i, j) == CellKind::square; }, Region::uniform_square);
  report.squares = p.size();
  report.graded = o.graded;
  if (o.before_meshing) o.before_meshing(p);
  if (o.grid != GridKind::uniform) {
    check_tangent_contacts(g, lattice);
    const double free_size = o.free_cell_size > 0 ? o.free_cell_size : o.spacing;
    const auto regions = free_regions(g, cells, box_edges_per_lattice_edge(free_size, o.spacing));
    report.free_regions = regions.regions.size();
    const Region kind = o.grid == GridKind::nbnug ? Region::box_free_mesh : Region::other;
    std::vector<RegionShape> shapes(regions.regions.size());
    std::vector<std::vector<std::uint32_t>> global_vertex(shapes.size());
    for (std::size_t r = 0; r < shapes.size(); ++r) {
      shapes[r] = region_shape(regions, r, free_size, global_vertex[r]);
      if (o.graded.enabled()) shapes[r].fine_size = o.graded.fine, shapes[r].grading_length = o.graded.length;
    }
    std::vector<RegionMesh> meshes;
    if (o.worker) {
      meshes = o.worker->mesh(g.file, shapes);
    } else {
      for (const auto& shape : shapes) meshes.push_back(mesh_region(session, g.file, shape));
    }
    for (std::size_t r = 0; r < shapes.size(); ++r)
      append_region_cells(g.file, regions, r, global_vertex[r], meshes[r], kind, p, report.free);
  }
  nearest_centroid_distances(p, g, lattice, report);
  return p;
}

void sort_particles_spatially(ParticleSet& p) {
  const std::size_t n = p.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  const double dx = p.spacing;
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const long ra = static_cast<long>(std::floor((p.y[a] - p.ymin) / dx));
    const long rb = static_cast<long>(std::floor((p.y[b] - p.ymin) / dx));
    if (ra != rb) return ra < rb;
    if (p.x[a] != p.x[b]) return p.x[a] < p.x[b];
    return p.y[a] < p.y[b];
  });
  ParticleSet q = empty_like(p);
  for (auto i : order) append_particle(q, p, i);
  q.provenance = std::move(p.provenance);
  p = std::move(q);
}

}  // namespace pd
