#include "geometry.hpp"

#include <algorithm>
#include <cmath>

namespace pd {

double polygon_signed_area(const double* vx, const double* vy, std::size_t n) {
  if (n < 3) return 0;
  // About the first vertex, as in polygon_centroid: a small cell far from the
  // origin keeps its digits (products of absolute coordinates would cancel).
  const double ox = vx[0], oy = vy[0];
  double twice = 0;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
    twice += (vx[j] - ox) * (vy[i] - oy) - (vx[i] - ox) * (vy[j] - oy);
  return 0.5 * twice;
}

Vec2 polygon_centroid(const double* vx, const double* vy, std::size_t n) {
  if (n == 0) return {0, 0};
  // Moments about the first vertex keep the sums well conditioned for small
  // cells far from the origin.
  const double ox = vx[0], oy = vy[0];
  double twice_area = 0, mx = 0, my = 0;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xj = vx[j] - ox, yj = vy[j] - oy, xi = vx[i] - ox, yi = vy[i] - oy;
    const double c = xj * yi - xi * yj;
    twice_area += c;
    mx += (xj + xi) * c;
    my += (yj + yi) * c;
  }
  return {ox + mx / (3.0 * twice_area), oy + my / (3.0 * twice_area)};
}

namespace {

// Signed area of triangle(O, a, b) ∩ disk(O, r); a and b relative to O.
//
// The edge's line a + t d (d = b - a) meets the circle where
// (d.d) t^2 + 2 (a.d) t + (a.a - r^2) = 0. Its discriminant is written as
// (d.d) r^2 - (a x d)^2, i.e. (d.d) (r^2 - h^2) with h the distance of the line
// from O: no cancellation between (a.d)^2 and (d.d)(a.a), and the sign says
// directly whether the line passes inside the circle. The part of the line
// inside the disk is the parameter interval [t1, t2] between the roots; each
// piece of the edge is classified by where its parameters lie, never by
// comparing a point's distance with r. At a tangency (h = r, and within
// round-off of it: the discriminant may come out as -1e-30 or +1e-30) the
// inside interval is empty or a few ulps long, so the straight piece is nil
// and the sectors make up the edge, as they must: a circle tangent to the
// edge leaves it outside the disk but for one point. The area is continuous
// in the discriminant, so which side of zero it rounds to does not matter.
double triangle_disk_signed_area(Vec2 a, Vec2 b, double r) {
  const double r2 = r * r;
  const Vec2 d = b - a;
  const double qa = dot(d, d);
  if (qa == 0) return 0;
  const double qb = dot(a, d);
  const double qc = dot(a, a) - r2;
  const double distance_term = cross(a, d);
  const double disc = qa * r2 - distance_term * distance_term;  // = qb^2 - qa qc
  const auto sector = [&](Vec2 p, Vec2 q) { return 0.5 * r2 * std::atan2(cross(p, q), dot(p, q)); };
  if (!(disc > 0)) return sector(a, b);  // the line misses the open disk
  const double s = std::sqrt(disc);
  // Stable roots of the quadratic (no difference of nearly equal numbers).
  const double q = -(qb + std::copysign(s, qb));
  double t1 = q / qa, t2 = (q != 0) ? qc / q : t1;
  if (t1 > t2) std::swap(t1, t2);
  // The edge's parameter range [0, 1] cut by [t1, t2]: outside, inside, outside.
  const double enter = std::clamp(t1, 0.0, 1.0), leave = std::clamp(t2, 0.0, 1.0);
  const Vec2 p_enter = enter == 0 ? a : a + enter * d, p_leave = leave == 1 ? b : a + leave * d;
  double area = 0;
  if (enter > 0) area += sector(a, p_enter);
  if (leave > enter) area += 0.5 * cross(p_enter, p_leave);  // straight piece inside the disk
  if (leave < 1) area += sector(p_leave, b);
  return area;
}

}  // namespace

double polygon_disk_intersection_area(const double* vx, const double* vy, std::size_t n,
                                      Vec2 center, double radius) {
  double area = 0;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a{vx[j] - center.x, vy[j] - center.y};
    const Vec2 b{vx[i] - center.x, vy[i] - center.y};
    area += triangle_disk_signed_area(a, b, radius);
  }
  return std::fabs(area);
}

double polygon_max_vertex_distance(const double* vx, const double* vy, std::size_t n, Vec2 from) {
  double best = 0;
  for (std::size_t i = 0; i < n; ++i) best = std::max(best, std::hypot(vx[i] - from.x, vy[i] - from.y));
  return best;
}

namespace {
// Where squares alone compare like hypot: d2 = dx^2 + dy^2 and limit^2 carry
// a relative round-off of a few 1e-16 and hypot's value is within an ulp of
// the exact length, so outside this band around limit^2 both comparisons
// agree. Inside it (ties, such as a cell corner exactly on a horizon) the
// caller takes hypot's own values.
constexpr double square_band = 1e-12;
enum class SquareOrder { below, above, undecided };
SquareOrder compare_squares(double d2, double limit) {
  const double l2 = limit * limit;
  if (d2 < l2 * (1 - square_band)) return SquareOrder::below;
  if (d2 > l2 * (1 + square_band)) return SquareOrder::above;
  return SquareOrder::undecided;  // also NaN
}
}  // namespace

bool hypot_at_most(double dx, double dy, double limit) {
  switch (compare_squares(dx * dx + dy * dy, limit)) {
    case SquareOrder::below: return true;
    case SquareOrder::above: return false;
    case SquareOrder::undecided: break;
  }
  return std::hypot(dx, dy) <= limit;
}

bool polygon_within_distance(const double* vx, const double* vy, std::size_t n, Vec2 from, double limit) {
  double farthest2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = vx[i] - from.x, dy = vy[i] - from.y;
    farthest2 = std::max(farthest2, dx * dx + dy * dy);
  }
  switch (compare_squares(farthest2, limit)) {
    case SquareOrder::below: return true;
    case SquareOrder::above: return false;
    case SquareOrder::undecided: break;
  }
  return polygon_max_vertex_distance(vx, vy, n, from) <= limit;
}

bool hypot_less(Vec2 u, Vec2 v) {
  const double u2 = dot(u, u), v2 = dot(v, v);
  // Squares near the bottom of the range lose their relative precision.
  if (std::max(u2, v2) > 1e-280) {
    if (u2 < v2 * (1 - square_band)) return true;
    if (u2 > v2 * (1 + square_band)) return false;
  }
  return std::hypot(u.x, u.y) < std::hypot(v.x, v.y);
}

double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double len2 = dot(d, d);
  double t = len2 > 0 ? dot(p - a, d) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  const Vec2 q = a + t * d;
  return std::sqrt((p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y));
}

namespace {
int orientation(Vec2 a, Vec2 b, Vec2 c) {
  const double v = cross(b - a, c - a);
  return (v > 0) - (v < 0);
}
bool on_segment(Vec2 a, Vec2 b, Vec2 p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}
}  // namespace

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}

bool segments_cross_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  return o1 * o2 < 0 && o3 * o4 < 0;
}

bool point_in_polygon(Vec2 p, const double* vx, const double* vy, std::size_t n) {
  std::vector<Vec2> polygon(n);
  for (std::size_t i = 0; i < n; ++i) polygon[i] = {vx[i], vy[i]};
  return point_in_polygon(p, polygon);
}

bool point_in_polygon(Vec2 p, const std::vector<Vec2>& polygon) {
  int winding = 0;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a = polygon[j], b = polygon[i];
    if (a.y <= p.y) {
      if (b.y > p.y && cross(b - a, p - a) > 0) ++winding;
    } else {
      if (b.y <= p.y && cross(b - a, p - a) < 0) --winding;
    }
  }
  return winding != 0;
}

double hhb_factor(double distance, double horizon, double cell_size) {
  const double half = 0.5 * cell_size;
  if (distance <= horizon - half) return 1.0;
  if (distance >= horizon + half) return 0.0;
  return (horizon + half - distance) / cell_size;
}

}  // namespace pd
