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
  // Each particle within reach, with its nearest point of the segments.
  std::unordered_map<std::uint32_t, std::pair<double, Vec2>> nearest;
  std::vector<std::uint32_t> candidates;
  for (std::size_t k = 0; k < ax.size(); ++k) {
    const Vec2 a{ax[k], ay[k]}, b{bx[k], by[k]}, d = b - a;
    // Cover the segment by disks of radius distance + half a step.
    const double length = std::hypot(d.x, d.y);
    const double step = std::max(distance, 1e-300);
    const long pieces = std::max(1L, static_cast<long>(std::ceil(length / step)));
    for (long s = 0; s <= pieces; ++s) {
      const Vec2 c = a + (static_cast<double>(s) / pieces) * d;
      search.within(c.x, c.y, distance + 0.5 * length / pieces + 1e-12 * step, candidates);
      for (auto i : candidates) {
        const Vec2 q{p.x[i], p.y[i]};
        const double t = dot(d, d) > 0 ? std::clamp(dot(q - a, d) / dot(d, d), 0.0, 1.0) : 0.0;
        const Vec2 foot = a + t * d;
        const double gap = std::hypot(q.x - foot.x, q.y - foot.y);
        if (gap > distance) continue;
        auto [it, inserted] = nearest.try_emplace(i, gap, foot);
        if (!inserted && gap < it->second.first) it->second = {gap, foot};
      }
    }
  }
  std::vector<std::uint32_t> result;
  for (const auto& [i, found] : nearest)
    if (!material || !material->segment_leaves_material({p.x[i], p.y[i]}, found.second)) result.push_back(i);
  std::sort(result.begin(), result.end());
  return result;
}

}  // namespace pd
