#include "material_boundary.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"

namespace pd {

namespace {

double angle_in_0_2pi(double a) {
  const double two_pi = 2 * M_PI;
  a = std::fmod(a, two_pi);
  return a < 0 ? a + two_pi : a;
}

bool lexicographically_less(Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

}  // namespace

MaterialBoundary::MaterialBoundary(const std::vector<std::vector<Vec2>>& loops, double tolerance,
                                   double typical_segment_length)
    : tolerance_(tolerance) {
  if (!(tolerance >= 0) || !(typical_segment_length > 0))
    throw Error("MaterialBoundary: the tolerance must be >= 0 and the segment length positive");
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  for (const auto& loop : loops)
    for (const auto& p : loop) {
      xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
      ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
    }
  if (!(xmax >= xmin)) return;  // no boundary: nothing ever leaves the material
  // Buckets of about half a segment; at most 2048 along the larger side.
  const double extent = std::max(xmax - xmin, ymax - ymin);
  bucket_ = std::max(0.5 * typical_segment_length, extent / 2048);
  x0_ = xmin - tolerance - bucket_, y0_ = ymin - tolerance - bucket_;
  nx_ = static_cast<long>((xmax - x0_ + tolerance) / bucket_) + 2;
  ny_ = static_cast<long>((ymax - y0_ + tolerance) / bucket_) + 2;

  // Long edges (straight boundaries) are split into collinear pieces no longer
  // than half a bucket, so that every edge sits in a few buckets. A split point
  // is a straight vertex: a segment through it crosses the edge, one along the
  // edge touches it, exactly as for the edge itself.
  const double longest = 0.5 * bucket_;
  for (const auto& loop : loops) {
    if (loop.size() < 3) continue;
    const auto first = static_cast<std::uint32_t>(points_.size());
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Vec2 a = loop[k], b = loop[(k + 1) % loop.size()];
      const long pieces = std::max(1L, static_cast<long>(std::ceil(std::hypot(b.x - a.x, b.y - a.y) / longest)));
      for (long s = 0; s < pieces; ++s) {
        const double t = static_cast<double>(s) / pieces;
        points_.push_back(s == 0 ? a : Vec2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
      }
    }
    const auto last = static_cast<std::uint32_t>(points_.size() - 1);
    for (auto k = first; k <= last; ++k) {
      prev_.push_back(k == first ? last : k - 1);
      next_.push_back(k == last ? first : k + 1);
    }
  }

  // Groups of up to 16 consecutive edges of one loop, each with its box grown
  // by the tolerance: a segment that misses the box misses its edges.
  for (std::uint32_t k = 0; k < points_.size();) {
    Group g{k, k, INFINITY, INFINITY, -INFINITY, -INFINITY};
    do {
      const Vec2 a = points_[g.end], b = points_[next_[g.end]];
      g.x0 = std::min({g.x0, a.x - tolerance_, b.x - tolerance_}), g.x1 = std::max({g.x1, a.x + tolerance_, b.x + tolerance_});
      g.y0 = std::min({g.y0, a.y - tolerance_, b.y - tolerance_}), g.y1 = std::max({g.y1, a.y + tolerance_, b.y + tolerance_});
      ++g.end;
    } while (g.end < points_.size() && g.end - g.begin < 16 && next_[g.end - 1] == g.end);
    groups_.push_back(g);
    k = g.end;
  }

  // Bucket lists of groups (CSR), two passes: count, then fill.
  const auto bucket_range = [&](const Group& g, long& i0, long& j0, long& i1, long& j1) {
    i0 = static_cast<long>((g.x0 - x0_) / bucket_), i1 = static_cast<long>((g.x1 - x0_) / bucket_);
    j0 = static_cast<long>((g.y0 - y0_) / bucket_), j1 = static_cast<long>((g.y1 - y0_) / bucket_);
  };
  bucket_offsets_.assign(static_cast<std::size_t>(nx_ * ny_) + 1, 0);
  for (const auto& g : groups_) {
    long i0, j0, i1, j1;
    bucket_range(g, i0, j0, i1, j1);
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i) ++bucket_offsets_[static_cast<std::size_t>(j * nx_ + i) + 1];
  }
  for (std::size_t b = 1; b < bucket_offsets_.size(); ++b) bucket_offsets_[b] += bucket_offsets_[b - 1];
  bucket_groups_.resize(bucket_offsets_.back());
  std::vector<std::uint64_t> fill(bucket_offsets_.begin(), bucket_offsets_.end() - 1);
  for (std::uint32_t g = 0; g < groups_.size(); ++g) {
    long i0, j0, i1, j1;
    bucket_range(groups_[g], i0, j0, i1, j1);
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i) bucket_groups_[fill[static_cast<std::size_t>(j * nx_ + i)]++] = g;
  }
}

template <class GroupFilter, class F>
bool MaterialBoundary::any_edge_in_box(double x0, double y0, double x1, double y1, GroupFilter&& keep, F&& f) const {
  if (nx_ == 0) return false;
  const long i0 = std::max(0L, static_cast<long>(std::floor((x0 - x0_) / bucket_)));
  const long i1 = std::min(nx_ - 1, static_cast<long>(std::floor((x1 - x0_) / bucket_)));
  const long j0 = std::max(0L, static_cast<long>(std::floor((y0 - y0_) / bucket_)));
  const long j1 = std::min(ny_ - 1, static_cast<long>(std::floor((y1 - y0_) / bucket_)));
  for (long j = j0; j <= j1; ++j)
    for (long i = i0; i <= i1; ++i) {
      const auto b = static_cast<std::size_t>(j * nx_ + i);
      for (auto e = bucket_offsets_[b]; e < bucket_offsets_[b + 1]; ++e) {
        const Group& g = groups_[bucket_groups_[e]];
        if (g.x1 < x0 || g.x0 > x1 || g.y1 < y0 || g.y0 > y1 || !keep(g)) continue;
        for (auto k = g.begin; k < g.end; ++k)
          if (f(k)) return true;
      }
    }
  return false;
}

bool MaterialBoundary::enters_void_at_vertex(std::uint32_t k, Vec2 d, double angle_tolerance) const {
  // Material lies on the left of the boundary, so at vertex v the void is the
  // counter-clockwise sweep from the incoming edge (pointing back, to the
  // previous vertex) to the outgoing edge (to the next vertex).
  const Vec2 v = points_[k];
  const Vec2 back = points_[prev_[k]] - v, ahead = points_[next_[k]] - v;
  const double start = std::atan2(back.y, back.x);
  const double sweep = angle_in_0_2pi(std::atan2(ahead.y, ahead.x) - start);
  if (sweep == 0) return false;  // a zero-width spike: no void to enter
  const double position = angle_in_0_2pi(std::atan2(d.y, d.x) - start);
  return position > angle_tolerance && position < sweep - angle_tolerance;
}

bool MaterialBoundary::segment_leaves_material(Vec2 a, Vec2 b) const {
  // One order for both directions: the floating-point decisions below are then
  // the same for the bond i -> j and the bond j -> i.
  if (lexicographically_less(b, a)) std::swap(a, b);
  const Vec2 d = b - a;
  const double length = std::hypot(d.x, d.y);
  if (length == 0) return false;
  const double eps = tolerance_;
  // Turning by this angle moves the far end of the segment by one tolerance.
  const double angle_tolerance = eps / length;
  const double bx0 = std::min(a.x, b.x) - eps, bx1 = std::max(a.x, b.x) + eps;
  const double by0 = std::min(a.y, b.y) - eps, by1 = std::max(a.y, b.y) + eps;
  // Liang-Barsky: does the segment meet the group's box?
  const auto meets = [&](const Group& g) {
    double t0 = 0, t1 = 1;
    const double dd[2] = {d.x, d.y}, lo[2] = {g.x0 - a.x, g.y0 - a.y}, hi[2] = {g.x1 - a.x, g.y1 - a.y};
    for (int c = 0; c < 2; ++c) {
      if (dd[c] == 0) {
        if (lo[c] > 0 || hi[c] < 0) return false;
        continue;
      }
      double ta = lo[c] / dd[c], tb = hi[c] / dd[c];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    return true;
  };
  return any_edge_in_box(bx0, by0, bx1, by1, meets, [&](std::uint32_t k) {
    const Vec2 p = points_[k], q = points_[next_[k]];
    if (std::max(p.x, q.x) < bx0 || std::min(p.x, q.x) > bx1 || std::max(p.y, q.y) < by0 ||
        std::min(p.y, q.y) > by1)
      return false;
    // Signed distances of the edge's ends from the segment's line.
    const double sp = cross(d, p - a) / length, sq = cross(d, q - a) / length;
    // The segment passes (within the tolerance) through vertex p, the start
    // of this edge (each vertex is the start of exactly one edge): it leaves
    // the material if it heads into the void there, on either side of p; or,
    // where p is one of the segment's ends, on the side of the segment.
    if (std::fabs(sp) <= eps) {
      const double along = dot(p - a, d) / length;
      if (along > eps && along < length - eps) {
        if (enters_void_at_vertex(k, d, angle_tolerance) || enters_void_at_vertex(k, -1.0 * d, angle_tolerance))
          return true;
      } else if (std::fabs(along) <= eps) {
        if (enters_void_at_vertex(k, d, angle_tolerance)) return true;
      } else if (std::fabs(along - length) <= eps) {
        if (enters_void_at_vertex(k, -1.0 * d, angle_tolerance)) return true;
      }
    }
    // Distances of the segment's ends from the edge's line (positive: material side).
    const Vec2 e = q - p;
    const double edge_length = std::hypot(e.x, e.y);
    if (edge_length == 0) return false;
    const double ea = cross(e, a - p) / edge_length, eb = cross(e, b - p) / edge_length;
    // An end of the segment on the edge (a particle on the boundary, as on a
    // uniform grid whose cell centres lie on a straight edge): the segment
    // leaves if it heads to the edge's void side.
    const auto on_edge = [&](Vec2 end, double distance) {
      const double t = dot(end - p, e) / edge_length;
      return std::fabs(distance) <= eps && t > eps && t < edge_length - eps;
    };
    if (on_edge(a, ea) && cross(e, d) < -angle_tolerance * edge_length * length) return true;
    if (on_edge(b, eb) && cross(e, -1.0 * d) < -angle_tolerance * edge_length * length) return true;
    // A proper crossing: the edge's ends clearly on opposite sides of the
    // segment's line, and the segment's ends clearly on opposite sides of the edge's line.
    return ((sp > eps && sq < -eps) || (sp < -eps && sq > eps)) && ((ea > eps && eb < -eps) || (ea < -eps && eb > eps));
  });
}

bool MaterialBoundary::near(Vec2 p, double radius) const {
  const auto within = [&](const Group& g) {
    return std::hypot(std::max({g.x0 - p.x, 0.0, p.x - g.x1}), std::max({g.y0 - p.y, 0.0, p.y - g.y1})) <= radius;
  };
  return any_edge_in_box(p.x - radius, p.y - radius, p.x + radius, p.y + radius, within, [&](std::uint32_t k) {
    return point_segment_distance(p, points_[k], points_[next_[k]]) <= radius;
  });
}

}  // namespace pd
