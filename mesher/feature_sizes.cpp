#include "feature_sizes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <queue>
#include <utility>

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

Vec2 closest_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double length2 = dot(d, d);
  const double t = length2 > 0 ? std::clamp(dot(p - a, d) / length2, 0.0, 1.0) : 0.0;
  return a + t * d;
}

// Lattice cells whose centre lies inside `loop`: the even-odd rule on this
// loop's polyline alone, with the crossings of a row's centre line counted
// half-open as classify_cells counts them, so that a removed cell is found
// in exactly the void it was removed for.
std::vector<std::pair<long, long>> cells_inside_loop(const BoundaryLoop& loop, const Lattice& l) {
  const long j0 = std::max(0L, static_cast<long>(std::floor((loop.ymin - l.y0) / l.dx - 0.5)));
  const long j1 = std::min(l.ny - 1, static_cast<long>(std::ceil((loop.ymax - l.y0) / l.dx - 0.5)));
  const long i0 = std::max(0L, static_cast<long>(std::floor((loop.xmin - l.x0) / l.dx - 0.5)));
  const long i1 = std::min(l.nx - 1, static_cast<long>(std::ceil((loop.xmax - l.x0) / l.dx - 0.5)));
  std::vector<std::pair<long, long>> inside;
  if (j1 < j0 || i1 < i0) return inside;
  std::vector<std::vector<double>> crossings(static_cast<std::size_t>(j1 - j0 + 1));
  const auto pts = loop.polyline();
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Vec2 p = pts[k], q = pts[(k + 1) % pts.size()];
    if (p.y == q.y) continue;
    const double lo = std::min(p.y, q.y), hi = std::max(p.y, q.y);
    for (long j = j0; j <= j1; ++j) {
      const double y = l.y0 + (j + 0.5) * l.dx;
      if (y >= lo && y < hi)
        crossings[static_cast<std::size_t>(j - j0)].push_back(p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y));
    }
  }
  for (long j = j0; j <= j1; ++j) {
    auto& xs = crossings[static_cast<std::size_t>(j - j0)];
    std::sort(xs.begin(), xs.end());
    for (long i = i0; i <= i1; ++i) {
      const double x = l.x0 + (i + 0.5) * l.dx;
      if ((std::lower_bound(xs.begin(), xs.end(), x) - xs.begin()) % 2 == 1) inside.push_back({i, j});
    }
  }
  return inside;
}

// The narrowest place between two closed polylines among their segments
// within `radius` of `around`: the distance and its two end points.
struct Narrowest {
  double distance = INFINITY;
  Vec2 a, b;
};
Narrowest narrowest_between(const std::vector<Vec2>& first, const std::vector<Vec2>& second, Vec2 around,
                            double radius) {
  const auto near_segments = [&](const std::vector<Vec2>& poly) {
    std::vector<std::pair<Vec2, Vec2>> out;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Vec2 a = poly[k], b = poly[(k + 1) % poly.size()];
      if (point_segment_distance(around, a, b) <= radius) out.push_back({a, b});
    }
    return out;
  };
  Narrowest best;
  const auto consider = [&](Vec2 a, Vec2 b) {
    const double d = std::hypot(b.x - a.x, b.y - a.y);
    if (d < best.distance) best = {d, a, b};
  };
  // Boundaries do not cross (sample_plate refuses that), so the distance of
  // two segments is that of an end point of one to the other.
  const auto near_second = near_segments(second);
  for (const auto& [p, q] : near_segments(first))
    for (const auto& [r, s] : near_second) {
      consider(p, closest_on_segment(p, r, s));
      consider(q, closest_on_segment(q, r, s));
      consider(closest_on_segment(r, p, q), r);
      consider(closest_on_segment(s, p, q), s);
    }
  return best;
}

}  // namespace

std::vector<LostLigament> lost_ligaments(const PlateGeometry& g, const CellMap& cells) {
  const Lattice& l = cells.lattice;
  // Which void each removed cell's centre lies in: 0 outside the outer
  // boundary, k for hole k - 1 (-1: a kept square).
  std::vector<int> void_of(cells.kind.size(), 0);
  for (std::size_t c = 0; c < cells.kind.size(); ++c)
    if (cells.kind[c] != CellKind::outside) void_of[c] = -1;
  for (std::size_t h = 0; h < g.holes.size(); ++h)
    for (const auto& [i, j] : cells_inside_loop(g.holes[h], l)) {
      int& v = void_of[static_cast<std::size_t>(j * l.nx + i)];
      if (v == 0) v = static_cast<int>(h) + 1;
    }
  // Beyond the lattice lies the outside of the plate.
  const auto void_at = [&](long i, long j) {
    if (i < 0 || j < 0 || i >= l.nx || j >= l.ny) return 0;
    return void_of[static_cast<std::size_t>(j * l.nx + i)];
  };
  const auto centre = [&](long i, long j) { return l.node(i, j) + Vec2{0.5 * l.dx, 0.5 * l.dx}; };
  std::vector<std::vector<Vec2>> polylines{g.outer.polyline()};
  for (const auto& hole : g.holes) polylines.push_back(hole.polyline());
  const auto name = [&](int v) { return g.holes[static_cast<std::size_t>(v - 1)].name; };

  struct Found {
    int first, second;  // the two voids, first > second
    Vec2 last_crossing;
    LostLigament ligament;
  };
  std::vector<Found> found;
  const auto crossing = [&](long i, long j, long ni, long nj) {
    int a = void_at(i, j), b = void_at(ni, nj);
    if (b < 0 || a == b) return;
    if (a < b) std::swap(a, b);
    const Vec2 from = centre(i, j), to = centre(ni, nj), middle = 0.5 * (from + to);
    // The segment between the two centres leaves one void and enters the
    // other within half a spacing of its middle, so both boundaries pass
    // within a spacing of it there (searched a little wider).
    const auto& void_a = polylines[static_cast<std::size_t>(a)];
    const auto& void_b = polylines[static_cast<std::size_t>(b)];
    Narrowest n = narrowest_between(void_a, void_b, middle, 1.5 * l.dx);
    if (!std::isfinite(n.distance)) n = {l.dx, middle, middle};  // (not expected: the bound and the crossing)
    const Vec2 where = 0.5 * (n.a + n.b);
    // Crossings of the same two voids a few spacings apart are one ligament
    // (a long one is crossed by a run of cell pairs).
    for (auto& f : found)
      if (f.first == a && f.second == b &&
          std::hypot(f.last_crossing.x - middle.x, f.last_crossing.y - middle.y) <= 3 * l.dx) {
        f.last_crossing = middle;
        if (n.distance < f.ligament.width) f.ligament.width = n.distance, f.ligament.where = where;
        return;
      }
    const std::string between = b == 0 ? name(a) + " and the outer boundary" : name(b) + " and " + name(a);
    found.push_back({a, b, middle, {between, where, n.distance, b == 0}});
  };
  for (long j = 0; j < l.ny; ++j)
    for (long i = 0; i < l.nx; ++i) {
      if (void_at(i, j) < 0) continue;
      crossing(i, j, i + 1, j);
      crossing(i, j, i, j + 1);
      if (i == 0) crossing(i, j, i - 1, j);
      if (j == 0) crossing(i, j, i, j - 1);
    }
  std::vector<LostLigament> out;
  for (const auto& f : found)
    if (f.ligament.width > g.boundary_tolerance) out.push_back(f.ligament);  // voids that touch at a shared point
  return out;
}

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
    const double width = largest_inscribed_diameter(polygon, 1e-2 * spacing, narrower_than);
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
    bool cuts_a_corner = false;
    for (int c = 7; c >= 0; --c) {
      const double pc = corner_position[c % 4] + (c >= 4 ? total : 0);
      if (pc > pa && pc < pb) polygon.push_back(corners[c % 4]), cuts_a_corner = true;
    }
    // What a user calls it: a notch cuts into one side; a run from one side
    // to another cuts a corner of the box away (a rounded or chamfered
    // corner), and one from corner to corner of a side is that side curved.
    const auto at_corner = [&](Vec2 p) {
      return (std::fabs(p.x - g.xmin) <= tol || std::fabs(p.x - g.xmax) <= tol) &&
             (std::fabs(p.y - g.ymin) <= tol || std::fabs(p.y - g.ymax) <= tol);
    };
    const std::string name = cuts_a_corner                     ? "corner cut away between " + mm(a) + " and " + mm(b)
                             : at_corner(a) && at_corner(b) ? "space under the curved side from " + mm(a) + " to " + mm(b)
                                                            : "notch between " + mm(a) + " and " + mm(b);
    consider(name, std::move(polygon));
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
