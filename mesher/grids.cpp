#include "grids.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "error.hpp"
#include "families.hpp"
#include "segment_sets.hpp"
#include "lattice.hpp"
#include "neighbor_search.hpp"
#include "units.hpp"

namespace pd {

void lattice_cells(const PlateGeometry& g, double dx, long& nx, long& ny) {
  const double width = g.xmax - g.xmin, height = g.ymax - g.ymin;
  const auto fits = [](double length, double d, long& n) {
    n = std::lround(length / d);
    return n >= 1 && std::fabs(n * d - length) <= 1e-9 * length;
  };
  if (fits(width, dx, nx) && fits(height, dx, ny)) return;
  // Nearest spacing that divides both sides: dx = width / n for n near width / dx.
  double best = 0;
  const long n0 = std::max(1L, std::lround(width / dx));
  for (long d = 0; d < 100000 && best == 0; ++d)
    for (long n : {n0 - d, n0 + d}) {
      long m;
      if (n >= 1 && fits(height, width / n, m)) {
        best = width / n;
        break;
      }
    }
  char buf[256];
  std::snprintf(buf, sizeof buf, "the plate (%s x %s) is not an integer number of spacings %s",
                format_mm(width).c_str(), format_mm(height).c_str(), format_mm(dx).c_str());
  std::string message = buf;
  if (best > 0) message += "; the nearest spacing that fits both sides is " + format_mm(best) + " (--spacing " +
                           [&] { char b[64]; std::snprintf(b, sizeof b, "%.10gmm", best * 1e3); return std::string(b); }() + ")";
  throw file_error(g.file, message);
}

std::vector<LatticeBox> nbnug_boxes(const PlateGeometry& g, double dx, double padding, long nx, long ny) {
  std::vector<LatticeBox> boxes;
  // A tiny tolerance keeps a bound that lies exactly on a lattice line there.
  const double eps = 1e-9;
  for (std::size_t h = 0; h < g.holes.size(); ++h) {
    const auto& hole = g.holes[h];
    LatticeBox b;
    b.i0 = std::max(0L, static_cast<long>(std::floor((hole.xmin - padding - g.xmin) / dx + eps)));
    b.i1 = std::min(nx, static_cast<long>(std::ceil((hole.xmax + padding - g.xmin) / dx - eps)));
    b.j0 = std::max(0L, static_cast<long>(std::floor((hole.ymin - padding - g.ymin) / dx + eps)));
    b.j1 = std::min(ny, static_cast<long>(std::ceil((hole.ymax + padding - g.ymin) / dx - eps)));
    b.holes = {h};
    boxes.push_back(b);
  }
  // Merge until no two boxes overlap or touch (gap < one cell).
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < boxes.size() && !merged; ++a)
      for (std::size_t b = a + 1; b < boxes.size() && !merged; ++b) {
        auto& A = boxes[a];
        const auto& B = boxes[b];
        if (A.i0 <= B.i1 && B.i0 <= A.i1 && A.j0 <= B.j1 && B.j0 <= A.j1) {
          A.i0 = std::min(A.i0, B.i0), A.i1 = std::max(A.i1, B.i1);
          A.j0 = std::min(A.j0, B.j0), A.j1 = std::max(A.j1, B.j1);
          A.holes.insert(A.holes.end(), B.holes.begin(), B.holes.end());
          std::sort(A.holes.begin(), A.holes.end());
          boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(b));
          merged = true;
        }
      }
  }
  return boxes;
}

namespace {

bool inside_hole(const HoleLoop& hole, Vec2 p) {
  if (p.x < hole.xmin || p.x > hole.xmax || p.y < hole.ymin || p.y > hole.ymax) return false;
  // The samples at about dx decide unless p is close to a chord, where the
  // chord and the curve may disagree; then the fine samples decide.
  double near = 1e300;
  for (std::size_t k = 0; k < hole.points.size(); ++k)
    near = std::min(near, point_segment_distance(p, hole.points[k], hole.points[(k + 1) % hole.points.size()]));
  double longest = 0;
  for (std::size_t k = 0; k < hole.points.size(); ++k) {
    const auto& a = hole.points[k];
    const auto& b = hole.points[(k + 1) % hole.points.size()];
    longest = std::max(longest, std::hypot(b.x - a.x, b.y - a.y));
  }
  return near < longest ? point_in_polygon(p, hole.fine) : point_in_polygon(p, hole.points);
}

// min(cutoff, distance from p to the nearest hole curve).
double distance_to_curves(const PlateGeometry& g, Vec2 p, double cutoff) {
  double best = cutoff;
  for (const auto& hole : g.holes) {
    const double dxb = std::max({hole.xmin - p.x, 0.0, p.x - hole.xmax});
    const double dyb = std::max({hole.ymin - p.y, 0.0, p.y - hole.ymax});
    if (std::hypot(dxb, dyb) > best) continue;
    // Chords at about dx bound the distance from below up to their sagitta
    // (< chord length); only near holes do the fine samples decide.
    double coarse = 1e300, longest = 0;
    for (std::size_t k = 0; k < hole.points.size(); ++k) {
      const auto& a = hole.points[k];
      const auto& b = hole.points[(k + 1) % hole.points.size()];
      coarse = std::min(coarse, point_segment_distance(p, a, b));
      longest = std::max(longest, std::hypot(b.x - a.x, b.y - a.y));
    }
    if (coarse - longest > best) continue;
    for (std::size_t k = 0; k < hole.fine.size(); ++k)
      best = std::min(best, point_segment_distance(p, hole.fine[k], hole.fine[(k + 1) % hole.fine.size()]));
  }
  return best;
}

}  // namespace

ParticleSet build_grid(GmshSession& session, const PlateGeometry& g, const GridOptions& o, GridReport& report) {
  long nx = 0, ny = 0;
  lattice_cells(g, o.spacing, nx, ny);
  const double dx = o.spacing;
  ParticleSet p;
  p.grid = o.grid;
  p.spacing = dx;
  p.xmin = g.xmin, p.ymin = g.ymin, p.xmax = g.xmax, p.ymax = g.ymax;
  p.cell_offsets.push_back(0);

  switch (o.grid) {
    case GridKind::uniform: {
      append_lattice_squares(
          p, g.xmin, g.ymin, dx, 0, nx, 0, ny,
          [&](long i, long j) {
            const Vec2 c{g.xmin + (i + 0.5) * dx, g.ymin + (j + 0.5) * dx};
            for (const auto& hole : g.holes)
              if (inside_hole(hole, c)) return false;
            return true;
          },
          Region::uniform_square);
      report.squares = p.size();
      break;
    }
    case GridKind::nbnug: {
      report.boxes = nbnug_boxes(g, dx, o.padding, nx, ny);
      // Cell (i, j) -> inside a box? One flag per lattice cell.
      std::vector<std::uint8_t> boxed(static_cast<std::size_t>(nx * ny), 0);
      for (const auto& b : report.boxes)
        for (long j = b.j0; j < b.j1; ++j)
          for (long i = b.i0; i < b.i1; ++i) boxed[static_cast<std::size_t>(j * nx + i)] = 1;
      append_lattice_squares(p, g.xmin, g.ymin, dx, 0, nx, 0, ny,
                             [&](long i, long j) { return !boxed[static_cast<std::size_t>(j * nx + i)]; },
                             Region::uniform_square);
      report.squares = p.size();
      for (const auto& b : report.boxes)
        append_free_mesh(session, g, g.xmin + b.i0 * dx, g.ymin + b.j0 * dx, g.xmin + b.i1 * dx,
                         g.ymin + b.j1 * dx, b.i1 - b.i0, b.j1 - b.j0, b.holes, dx, Region::box_free_mesh, p,
                         report.free);
      break;
    }
    case GridKind::free: {
      std::vector<std::size_t> all(g.holes.size());
      std::iota(all.begin(), all.end(), 0);
      append_free_mesh(session, g, g.xmin, g.ymin, g.xmax, g.ymax, nx, ny, all, dx, Region::other, p, report.free);
      break;
    }
  }
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.region[i] != static_cast<std::uint8_t>(Region::uniform_square) || o.grid == GridKind::uniform)
      report.min_centroid_distance_to_curve =
          distance_to_curves(g, {p.x[i], p.y[i]}, report.min_centroid_distance_to_curve);
  return p;
}

void add_boundary_sets(ParticleSet& p, const PlateGeometry& g, double distance) {
  std::vector<BoundarySet> sets;
  const NeighborSearch search(p.x, p.y);
  const auto edge = [&](const char* name, Vec2 a, Vec2 b) {
    sets.push_back({name, particles_near_segments(p, search, {a.x}, {a.y}, {b.x}, {b.y}, distance)});
  };
  edge("left", {g.xmin, g.ymin}, {g.xmin, g.ymax});
  edge("right", {g.xmax, g.ymin}, {g.xmax, g.ymax});
  edge("bottom", {g.xmin, g.ymin}, {g.xmax, g.ymin});
  edge("top", {g.xmin, g.ymax}, {g.xmax, g.ymax});
  for (const auto& hole : g.holes) {
    std::vector<double> ax, ay, bx, by;
    for (std::size_t k = 0; k < hole.fine.size(); ++k) {
      const auto& a = hole.fine[k];
      const auto& b = hole.fine[(k + 1) % hole.fine.size()];
      ax.push_back(a.x), ay.push_back(a.y), bx.push_back(b.x), by.push_back(b.y);
    }
    sets.push_back({hole.name, particles_near_segments(p, search, ax, ay, bx, by, distance)});
  }
  for (const auto& named : g.physical_curves) {
    std::vector<double> ax, ay, bx, by;
    for (std::size_t k = 0; k < named.a.size(); ++k)
      ax.push_back(named.a[k].x), ay.push_back(named.a[k].y), bx.push_back(named.b[k].x), by.push_back(named.b[k].y);
    BoundarySet s{named.name, particles_near_segments(p, search, ax, ay, bx, by, distance)};
    auto same = std::find_if(sets.begin(), sets.end(), [&](const BoundarySet& t) { return t.name == s.name; });
    if (same != sets.end())
      *same = std::move(s);
    else
      sets.push_back(std::move(s));
  }
  p.sets = std::move(sets);
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
  ParticleSet q;
  q.grid = p.grid, q.quadrature = p.quadrature, q.spacing = p.spacing, q.horizon_nominal = p.horizon_nominal;
  q.xmin = p.xmin, q.ymin = p.ymin, q.xmax = p.xmax, q.ymax = p.ymax;
  q.cell_offsets.push_back(0);
  for (auto i : order) {
    q.x.push_back(p.x[i]);
    q.y.push_back(p.y[i]);
    q.volume.push_back(p.volume[i]);
    q.cell_size.push_back(p.cell_size[i]);
    q.horizon.push_back(p.horizon[i]);
    q.region.push_back(p.region[i]);
    q.material.push_back(p.material[i]);
    for (auto v = p.cell_offsets[i]; v < p.cell_offsets[i + 1]; ++v) {
      q.cell_vx.push_back(p.cell_vx[v]);
      q.cell_vy.push_back(p.cell_vy[v]);
    }
    q.cell_offsets.push_back(q.cell_vx.size());
  }
  q.provenance = std::move(p.provenance);
  p = std::move(q);
}

}  // namespace pd
