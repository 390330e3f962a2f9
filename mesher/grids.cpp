#include "grids.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "box_spacing.hpp"
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
