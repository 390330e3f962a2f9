#include "boundary_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

namespace pd {

namespace {

struct Edge {
  Vec2 a, b;
  std::size_t loop;
};

bool same_point(Vec2 p, Vec2 q) { return p.x == q.x && p.y == q.y; }

// The closed segments meet somewhere other than at one shared end point.
bool edges_meet(const Edge& s, const Edge& t) {
  const Vec2 s_ends[2] = {s.a, s.b}, t_ends[2] = {t.a, t.b};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      if (!same_point(s_ends[i], t_ends[j])) continue;
      // Shared end point: they meet elsewhere only if they overlap along a line.
      const Vec2 p = s_ends[i], u = s_ends[1 - i] - p, v = t_ends[1 - j] - p;
      return cross(u, v) == 0 && dot(u, v) > 0;
    }
  return segments_intersect(s.a, s.b, t.a, t.b);
}

constexpr std::size_t crowded = 64;

// Brute force over the pairs of a small set; otherwise buckets of about the
// mean edge length over the set's box, each searched the same way.
std::optional<std::pair<std::size_t, std::size_t>> search(const std::vector<Edge>& edges,
                                                          const std::vector<std::uint32_t>& subset, int depth,
                                                          std::size_t& pair_tests) {
  if (subset.size() <= crowded || depth >= 6) {
    for (std::size_t i = 0; i < subset.size(); ++i)
      for (std::size_t j = i + 1; j < subset.size(); ++j) {
        ++pair_tests;
        if (edges_meet(edges[subset[i]], edges[subset[j]])) return std::pair{subset[i], subset[j]};
      }
    return std::nullopt;
  }
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY, total = 0;
  for (auto e : subset) {
    const auto& s = edges[e];
    x0 = std::min({x0, s.a.x, s.b.x}), x1 = std::max({x1, s.a.x, s.b.x});
    y0 = std::min({y0, s.a.y, s.b.y}), y1 = std::max({y1, s.a.y, s.b.y});
    total += std::hypot(s.b.x - s.a.x, s.b.y - s.a.y);
  }
  const double extent = std::max(x1 - x0, y1 - y0);
  if (!(extent > 0)) return search(edges, subset, 6, pair_tests);
  // About one edge per bucket, at most 2^20 buckets along a side.
  const double cell = std::max({total / static_cast<double>(subset.size()), extent * std::ldexp(1.0, -20),
                                extent / std::sqrt(static_cast<double>(subset.size()))});
  const double slack = 1e-9 * cell;  // contacts on a bucket border land in both buckets
  const auto column = [&](double x) { return static_cast<std::int64_t>(std::floor((x - x0) / cell)); };
  std::vector<std::pair<std::int64_t, std::uint32_t>> entries;  // (bucket key, edge)
  const std::int64_t stride = column(x1 + slack) + 2;
  for (auto e : subset) {
    // Every bucket the closed segment touches: column by column, the rows
    // between the segment's lowest and highest point within the column.
    const auto& s = edges[e];
    const Vec2 lo = s.a.x <= s.b.x ? s.a : s.b, hi = s.a.x <= s.b.x ? s.b : s.a;
    const std::int64_t c0 = column(lo.x - slack), c1 = column(hi.x + slack);
    for (std::int64_t c = c0; c <= c1; ++c) {
      const double xa = std::max(lo.x, x0 + c * cell - slack), xb = std::min(hi.x, x0 + (c + 1) * cell + slack);
      const auto y_at = [&](double x) {
        return hi.x > lo.x ? lo.y + (hi.y - lo.y) * std::clamp((x - lo.x) / (hi.x - lo.x), 0.0, 1.0) : lo.y;
      };
      double ya = y_at(xa), yb = y_at(xb);
      if (hi.x == lo.x) ya = std::min(lo.y, hi.y), yb = std::max(lo.y, hi.y);
      const auto r0 = static_cast<std::int64_t>(std::floor((std::min(ya, yb) - slack - y0) / cell));
      const auto r1 = static_cast<std::int64_t>(std::floor((std::max(ya, yb) + slack - y0) / cell));
      for (std::int64_t r = r0; r <= r1; ++r) entries.push_back({(r + 1) * stride + c + 1, e});
    }
  }
  std::sort(entries.begin(), entries.end());
  std::vector<std::uint32_t> bucket;
  for (std::size_t begin = 0; begin < entries.size();) {
    std::size_t end = begin;
    bucket.clear();
    while (end < entries.size() && entries[end].first == entries[begin].first) bucket.push_back(entries[end++].second);
    if (bucket.size() > 1) {
      // A bucket that holds the whole set makes no progress: give up bucketing.
      const int next_depth = bucket.size() == subset.size() ? 6 : depth + 1;
      if (auto found = search(edges, bucket, next_depth, pair_tests)) return found;
    }
    begin = end;
  }
  return std::nullopt;
}

}  // namespace

std::optional<BoundaryContact> find_boundary_contact(const std::vector<std::vector<Vec2>>& loops,
                                                    std::size_t* pair_tests) {
  std::vector<Edge> edges;
  for (std::size_t l = 0; l < loops.size(); ++l)
    for (std::size_t k = 0; k < loops[l].size(); ++k) edges.push_back({loops[l][k], loops[l][(k + 1) % loops[l].size()], l});
  std::vector<std::uint32_t> all(edges.size());
  for (std::uint32_t k = 0; k < all.size(); ++k) all[k] = k;
  std::size_t tests = 0;
  const auto found = search(edges, all, 0, tests);
  if (pair_tests) *pair_tests = tests;
  if (!found) return std::nullopt;
  const auto& s = edges[found->first];
  const auto& t = edges[found->second];
  // Where they cross; if they only touch or overlap, the end of the shorter
  // edge that is nearest to the other edge.
  const Vec2 ds = s.b - s.a, dt = t.b - t.a;
  const double denominator = cross(ds, dt);
  Vec2 where;
  if (denominator != 0) {
    const double u = std::clamp(cross(t.a - s.a, dt) / denominator, 0.0, 1.0);
    where = s.a + u * ds;
  } else {
    const bool s_shorter = dot(ds, ds) <= dot(dt, dt);
    const Edge& shorter = s_shorter ? s : t;
    const Edge& longer = s_shorter ? t : s;
    where = point_segment_distance(shorter.a, longer.a, longer.b) <= point_segment_distance(shorter.b, longer.a, longer.b)
                ? shorter.a
                : shorter.b;
  }
  return BoundaryContact{s.loop, t.loop, where};
}

}  // namespace pd
