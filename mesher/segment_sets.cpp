#include "segment_sets.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include "geometry.hpp"
#include "material_boundary.hpp"
#include "neighbor_search.hpp"

namespace pd {

std::vector<std::uint32_t> particles_near_segments(const ParticleSet& p, const NeighborSearch& search,
                                                   const std::vector<double>& ax, const std::vector<double>& ay,
                                                   const std::vector<double>& bx, const std::vector<double>& by,
                                                   double distance, const MaterialBoundary* material) {
  // Each particle within reach, with its nearest point of the segments (on
  // a tie, the first segment's): the particle less that point, and the point.
  struct Nearest {
    Vec2 offset, foot;
  };
  std::unordered_map<std::uint32_t, Nearest> nearest;
  std::vector<std::uint32_t> candidates;
  const double step = std::max(distance, 1e-300);
  // The boxes of a run's segments in groups of consecutive ones: a particle
  // passes over a group whose box lies farther than its nearest point so far
  // (by a margin far above round-off, so no segment it skips would have won).
  constexpr std::size_t group = 16;
  struct Box {
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  // The particles found within `radius` of `centre` against the segments
  // begin .. end - 1, which lie within radius - distance of it.
  const auto search_near = [&](std::size_t begin, std::size_t end, Vec2 centre, double radius) {
    boxes.clear();
    for (std::size_t g = begin; g < end; g += group) {
      Box box{ax[g], ay[g], ax[g], ay[g]};
      for (std::size_t k = g; k < std::min(end, g + group); ++k)
        box = {std::min({box.x0, ax[k], bx[k]}), std::min({box.y0, ay[k], by[k]}), std::max({box.x1, ax[k], bx[k]}),
               std::max({box.y1, ay[k], by[k]})};
      boxes.push_back(box);
    }
    search.within(centre.x, centre.y, radius + 1e-12 * step, candidates);
    for (auto i : candidates) {
      const Vec2 q{p.x[i], p.y[i]};
      Nearest best{};
      bool found = false;
      double beyond_best2 = 0;  // squared distance beyond which no segment can be nearer
      for (std::size_t g = 0; g < boxes.size(); ++g) {
        const Box& box = boxes[g];
        const double ox = std::max({box.x0 - q.x, 0.0, q.x - box.x1}), oy = std::max({box.y0 - q.y, 0.0, q.y - box.y1});
        if (found && ox * ox + oy * oy > beyond_best2) continue;
        for (std::size_t k = begin + g * group; k < std::min(end, begin + (g + 1) * group); ++k) {
          const Vec2 a{ax[k], ay[k]}, b{bx[k], by[k]}, d = b - a;
          const double t = dot(d, d) > 0 ? std::clamp(dot(q - a, d) / dot(d, d), 0.0, 1.0) : 0.0;
          const Vec2 foot = a + t * d;
          const Vec2 offset{q.x - foot.x, q.y - foot.y};
          if (found && !hypot_less(offset, best.offset)) continue;
          best = {offset, foot};
          found = true;
          const double beyond = std::sqrt(dot(offset, offset)) * (1 + 1e-9) + 1e-12 * step;
          beyond_best2 = beyond * beyond;
        }
      }
      if (!hypot_at_most(best.offset.x, best.offset.y, distance)) continue;
      auto [it, inserted] = nearest.try_emplace(i, best);
      if (!inserted && hypot_less(best.offset, it->second.offset)) it->second = best;
    }
  };
  // One search per run of consecutive segments whose box is at most the
  // distance across (a hole's polyline has a thousand chords within a few
  // spacings: a search per chord took seconds), about the box's centre; a
  // longer segment is covered by disks about the middles of pieces at most
  // the distance long.
  for (std::size_t k = 0; k < ax.size();) {
    const Vec2 a{ax[k], ay[k]}, b{bx[k], by[k]}, d = b - a;
    const double length = std::hypot(d.x, d.y);
    if (length > step) {
      const long pieces = static_cast<long>(std::ceil(length / step));
      for (long s = 0; s < pieces; ++s)
        search_near(k, k + 1, a + ((static_cast<double>(s) + 0.5) / pieces) * d, distance + 0.5 * length / pieces);
      ++k;
      continue;
    }
    double x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x), y0 = std::min(a.y, b.y), y1 = std::max(a.y, b.y);
    std::size_t end = k + 1;
    for (; end < ax.size(); ++end) {
      const double nx0 = std::min({x0, ax[end], bx[end]}), nx1 = std::max({x1, ax[end], bx[end]});
      const double ny0 = std::min({y0, ay[end], by[end]}), ny1 = std::max({y1, ay[end], by[end]});
      if (std::hypot(nx1 - nx0, ny1 - ny0) > step) break;
      x0 = nx0, x1 = nx1, y0 = ny0, y1 = ny1;
    }
    search_near(k, end, {0.5 * (x0 + x1), 0.5 * (y0 + y1)}, distance + 0.5 * std::hypot(x1 - x0, y1 - y0));
    k = end;
  }
  std::vector<std::uint32_t> result;
  for (const auto& [i, found] : nearest)
    if (!material || !material->segment_leaves_material({p.x[i], p.y[i]}, found.foot)) result.push_back(i);
  std::sort(result.begin(), result.end());
  return result;
}

}  // namespace pd
