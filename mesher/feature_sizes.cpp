#include "feature_sizes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <queue>

namespace pd {

namespace {

double distance_to_edges(Vec2 p, const std::vector<Vec2>& poly) {
  double best = INFINITY;
  for (std::size_t k = 0; k < poly.size(); ++k) best = std::min(best, point_segment_distance(p, poly[k], poly[(k + 1) % poly.size()]));
  return best;
}

// Positive inside the polygon, negative outside.
double signed_distance(Vec2 p, const std::vector<Vec2>& poly) {
  const double d = distance_to_edges(p, poly);
  return point_in_polygon(p, poly) ? d : -d;
}

// The curves' polylines joined, first point not repeated. Not the samples
// about dx apart that the cells are built on: those chords cut across a round
// hole (a disk of 0.6 mm sampled at 0.5 mm measured 0.554 mm), whereas the
// polylines lie within 1e-6 dx of the curves, so the width is the true one
// to the precision of the search.
std::vector<Vec2> boundary_polygon(const std::vector<const BoundaryCurve*>& curves) {
  std::vector<Vec2> out;
  for (const auto* c : curves) out.insert(out.end(), c->polyline.begin(), c->polyline.end() - 1);
  return out;
}

std::string mm(Vec2 p) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g) mm", p.x * 1e3, p.y * 1e3);
  return buf;
}

}  // namespace

double largest_inscribed_diameter(const std::vector<Vec2>& poly, double precision, double enough) {
  if (poly.size() < 3) return 0;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const auto& p : poly) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  const double cell = std::min(x1 - x0, y1 - y0);
  if (!(cell > 0)) return 0;
  struct Square {
    Vec2 c;
    double half, d;
    double potential() const { return d + half * std::sqrt(2.0); }
    bool operator<(const Square& o) const { return potential() < o.potential(); }
  };
  std::priority_queue<Square> queue;
  for (double x = x0; x < x1; x += cell)
    for (double y = y0; y < y1; y += cell) {
      const Vec2 c{x + 0.5 * cell, y + 0.5 * cell};
      queue.push({c, 0.5 * cell, signed_distance(c, poly)});
    }
  double best = 0;
  while (!queue.empty()) {
    const Square s = queue.top();
    queue.pop();
    best = std::max(best, s.d);
    if (2 * best >= enough) break;
    if (s.potential() - best <= 0.5 * precision) continue;
    const double h = 0.5 * s.half;
    for (const double dx : {-h, h})
      for (const double dy : {-h, h}) {
        const Vec2 c{s.c.x + dx, s.c.y + dy};
        queue.push({c, h, signed_distance(c, poly)});
      }
  }
  return 2 * best;
}

std::vector<NarrowVoid> narrow_voids(const PlateGeometry& g, double spacing, double narrower_than) {
  std::vector<NarrowVoid> found;
  const auto consider = [&](std::string name, std::vector<Vec2> polygon) {
    const double width = largest_inscribed_diameter(polygon, 1e-3 * spacing, narrower_than);
    if (width < narrower_than) found.push_back({std::move(name), std::move(polygon), width, -1});
  };
  for (const auto& hole : g.holes) {
    std::vector<const BoundaryCurve*> curves;
    for (const auto& c : hole.curves) curves.push_back(&c);
    consider(hole.name, boundary_polygon(curves));
  }
  // Notches: runs of outer curves between curves that lie on a side of the
  // bounding box, closed along the box the short way back.
  const double tol = 1e-9 * std::max(g.xmax - g.xmin, g.ymax - g.ymin);
  const auto side_of = [&](Vec2 p) {
    if (std::fabs(p.y - g.ymin) <= tol) return 0;
    if (std::fabs(p.x - g.xmax) <= tol) return 1;
    if (std::fabs(p.y - g.ymax) <= tol) return 2;
    if (std::fabs(p.x - g.xmin) <= tol) return 3;
    return -1;
  };
  const auto& curves = g.outer.curves;
  const std::size_t n = curves.size();
  // A straight curve along one side of the box (its ends may be corners).
  const auto on_box = [&](const BoundaryCurve& c) {
    if (!c.straight()) return false;
    const auto both = [&](auto on) { return on(c.start) && on(c.end); };
    return both([&](Vec2 p) { return std::fabs(p.y - g.ymin) <= tol; }) ||
           both([&](Vec2 p) { return std::fabs(p.x - g.xmax) <= tol; }) ||
           both([&](Vec2 p) { return std::fabs(p.y - g.ymax) <= tol; }) ||
           both([&](Vec2 p) { return std::fabs(p.x - g.xmin) <= tol; });
  };
  std::size_t first = n;
  for (std::size_t k = 0; k < n; ++k)
    if (on_box(curves[k])) first = k;
  if (first == n) return found;  // no curve on the box (a round plate): no notches
  // Position along the box perimeter, counter-clockwise from (xmin, ymin).
  const double w = g.xmax - g.xmin, h = g.ymax - g.ymin;
  const auto perimeter_position = [&](Vec2 p) {
    switch (side_of(p)) {
      case 0: return p.x - g.xmin;
      case 1: return w + (p.y - g.ymin);
      case 2: return w + h + (g.xmax - p.x);
      default: return 2 * w + h + (g.ymax - p.y);
    }
  };
  const Vec2 corners[4] = {{g.xmin, g.ymin}, {g.xmax, g.ymin}, {g.xmax, g.ymax}, {g.xmin, g.ymax}};
  const double corner_position[4] = {0, w, w + h, 2 * w + h};
  for (std::size_t s = 1; s <= n; ++s) {
    const std::size_t k = (first + s) % n;
    if (on_box(curves[k])) continue;
    std::vector<const BoundaryCurve*> run;
    std::size_t e = k;
    while (!on_box(curves[e])) run.push_back(&curves[e]), e = (e + 1) % n;
    s += run.size() - 1;
    const Vec2 a = run.front()->start, b = run.back()->end;
    if (side_of(a) < 0 || side_of(b) < 0) continue;
    auto polygon = boundary_polygon(run);
    polygon.push_back(b);
    // Back from b to a along the box, clockwise (the way the loop skipped).
    const double pa = perimeter_position(a), total = 2 * (w + h);
    double pb = perimeter_position(b);
    if (pb < pa) pb += total;
    for (int c = 7; c >= 0; --c) {
      const double pc = corner_position[c % 4] + (c >= 4 ? total : 0);
      if (pc > pa && pc < pb) polygon.push_back(corners[c % 4]);
    }
    consider("notch between " + mm(a) + " and " + mm(b), std::move(polygon));
  }
  return found;
}

void measure_resolved_widths(std::vector<NarrowVoid>& voids, const CellMap& cells) {
  const Lattice& l = cells.lattice;
  for (auto& v : voids) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (const auto& p : v.polygon) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    const long i0 = std::max(0L, static_cast<long>(std::floor((x0 - l.x0) / l.dx)));
    const long i1 = std::min(l.nx - 1, static_cast<long>(std::floor((x1 - l.x0) / l.dx)));
    const long j0 = std::max(0L, static_cast<long>(std::floor((y0 - l.y0) / l.dx)));
    const long j1 = std::min(l.ny - 1, static_cast<long>(std::floor((y1 - l.y0) / l.dx)));
    // The cells removed for this void.
    const long nx = i1 - i0 + 1, ny = j1 - j0 + 1;
    if (nx <= 0 || ny <= 0) {
      v.resolved_width = 0;
      continue;
    }
    std::vector<std::uint8_t> removed(static_cast<std::size_t>(nx * ny), 0);
    bool any = false;
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i)
        if (cells.at(i, j) == CellKind::outside && point_in_polygon(l.node(i, j) + Vec2{0.5 * l.dx, 0.5 * l.dx}, v.polygon))
          removed[static_cast<std::size_t>((j - j0) * nx + (i - i0))] = any = true;
    if (!any) {
      v.resolved_width = 0;
      continue;
    }
    // Largest disk in the union of the removed cells: its centre lies on the
    // half-cell lattice; its radius is the distance to the nearest cell that
    // is not removed (or to the edge of the lattice).
    const auto is_removed = [&](long i, long j) {
      return i >= i0 && i <= i1 && j >= j0 && j <= j1 && removed[static_cast<std::size_t>((j - j0) * nx + (i - i0))];
    };
    const long reach = 8;
    double best = 0;
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i) {
        if (!is_removed(i, j)) continue;
        for (int a = 0; a <= 2; ++a)
          for (int b = 0; b <= 2; ++b) {
            const Vec2 p = l.node(i, j) + Vec2{0.5 * a * l.dx, 0.5 * b * l.dx};
            double d = reach * l.dx;
            for (long q = j - reach; q <= j + reach; ++q)
              for (long r = i - reach; r <= i + reach; ++r) {
                if (is_removed(r, q)) continue;
                const Vec2 lo = l.node(r, q);
                const double ddx = std::max({lo.x - p.x, 0.0, p.x - (lo.x + l.dx)});
                const double ddy = std::max({lo.y - p.y, 0.0, p.y - (lo.y + l.dx)});
                d = std::min(d, std::hypot(ddx, ddy));
              }
            best = std::max(best, d);
          }
      }
    v.resolved_width = 2 * best;
  }
}

}  // namespace pd
