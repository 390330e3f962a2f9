#include "lattice.hpp"

#include <cmath>

#include "error.hpp"
#include "families.hpp"
#include "segment_sets.hpp"
#include "neighbor_search.hpp"

namespace pd {

void append_lattice_squares(ParticleSet& p, double x0, double y0, double dx, long i0, long i1, long j0,
                            long j1, const std::function<bool(long, long)>& keep, Region region) {
  if (p.cell_offsets.empty()) p.cell_offsets.push_back(0);
  for (long j = j0; j < j1; ++j)
    for (long i = i0; i < i1; ++i) {
      if (!keep(i, j)) continue;
      const double xa = x0 + i * dx, xb = x0 + (i + 1) * dx;
      const double ya = y0 + j * dx, yb = y0 + (j + 1) * dx;
      p.x.push_back(x0 + (i + 0.5) * dx);
      p.y.push_back(y0 + (j + 0.5) * dx);
      p.volume.push_back(dx * dx);
      p.cell_size.push_back(dx);
      p.horizon.push_back(0);
      p.region.push_back(static_cast<std::uint8_t>(region));
      p.material.push_back(0);
      for (double vx : {xa, xb, xb, xa}) p.cell_vx.push_back(vx);
      for (double vy : {ya, ya, yb, yb}) p.cell_vy.push_back(vy);
      p.cell_offsets.push_back(p.cell_vx.size());
    }
}

void add_rectangle_edge_sets(ParticleSet& p, double width, double height, double horizon) {
  const NeighborSearch search(p.x, p.y);
  const auto edge = [&](double ax, double ay, double bx, double by) {
    return particles_near_segments(p, search, {ax}, {ay}, {bx}, {by}, horizon);
  };
  p.sets.push_back({"left", edge(0, 0, 0, height)});
  p.sets.push_back({"right", edge(width, 0, width, height)});
  p.sets.push_back({"bottom", edge(0, 0, width, 0)});
  p.sets.push_back({"top", edge(0, height, width, height)});
}

ParticleSet make_rectangle_lattice(double width, double height, double dx, double horizon,
                                   Quadrature quadrature) {
  const long nx = std::lround(width / dx), ny = std::lround(height / dx);
  if (nx < 1 || ny < 1 || std::fabs(nx * dx - width) > 1e-9 * width || std::fabs(ny * dx - height) > 1e-9 * height)
    throw Error("make_rectangle_lattice: width and height must be positive multiples of the spacing");
  ParticleSet p;
  p.grid = GridKind::uniform;
  p.quadrature = quadrature;
  p.spacing = dx;
  p.horizon_nominal = horizon;
  p.xmin = 0, p.ymin = 0, p.xmax = width, p.ymax = height;
  append_lattice_squares(p, 0, 0, dx, 0, nx, 0, ny, [](long, long) { return true; }, Region::uniform_square);
  for (auto& h : p.horizon) h = horizon;
  build_families(p, quadrature);
  add_rectangle_edge_sets(p, width, height, horizon);
  p.provenance = "{\"generator\": \"make_rectangle_lattice\"}";
  return p;
}

}  // namespace pd
