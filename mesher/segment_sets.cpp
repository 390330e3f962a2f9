#include "segment_sets.hpp"

#include <algorithm>
#include <cmath>

#include "geometry.hpp"
#include "neighbor_search.hpp"

namespace pd {

std::vector<std::uint32_t> particles_near_segments(const ParticleSet& p, const NeighborSearch& search,
                                                   const std::vector<double>& ax, const std::vector<double>& ay,
                                                   const std::vector<double>& bx, const std::vector<double>& by,
                                                   double distance) {
  std::vector<std::uint32_t> result, candidates;
  for (std::size_t k = 0; k < ax.size(); ++k) {
    // Cover the segment by disks of radius distance + half a step.
    const double length = std::hypot(bx[k] - ax[k], by[k] - ay[k]);
    const double step = std::max(distance, 1e-300);
    const long pieces = std::max(1L, static_cast<long>(std::ceil(length / step)));
    for (long s = 0; s <= pieces; ++s) {
      const double t = static_cast<double>(s) / pieces;
      const double cx = ax[k] + t * (bx[k] - ax[k]), cy = ay[k] + t * (by[k] - ay[k]);
      search.within(cx, cy, distance + 0.5 * length / pieces + 1e-12 * step, candidates);
      for (auto i : candidates)
        if (point_segment_distance({p.x[i], p.y[i]}, {ax[k], ay[k]}, {bx[k], by[k]}) <= distance)
          result.push_back(i);
    }
  }
  std::sort(result.begin(), result.end());
  result.erase(std::unique(result.begin(), result.end()), result.end());
  return result;
}

}  // namespace pd
