#include "hole_cracks.hpp"

#include <algorithm>
#include <cmath>

namespace pd::validation {

std::vector<HoleCrack> cracks_at_hole(const ParticleSet& p, const std::vector<double>& damage,
                                      const std::vector<double>& damage_load_factor, const HoleRing& ring) {
  struct Hit {
    double angle;  // [rad] in (-pi, pi]
    std::size_t particle;
  };
  std::vector<Hit> hits;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double dx = p.x[i] - ring.cx, dy = p.y[i] - ring.cy;
    const double beyond_edge = std::hypot(dx, dy) - ring.radius;
    if (beyond_edge < ring.inner || beyond_edge > ring.outer || damage[i] < ring.damage_threshold) continue;
    hits.push_back({std::atan2(dy, dx), i});
  }
  std::vector<HoleCrack> cracks;
  if (hits.empty()) return cracks;
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.angle < b.angle; });
  const double ring_radius = ring.radius + 0.5 * (ring.inner + ring.outer);
  const double max_gap_angle = ring.max_gap / ring_radius;
  // Start the groups after the largest angular gap, so that no group wraps around.
  std::size_t start = 0;
  double largest_gap = -1;
  for (std::size_t k = 0; k < hits.size(); ++k) {
    const double next = k + 1 < hits.size() ? hits[k + 1].angle : hits[0].angle + 2 * M_PI;
    if (next - hits[k].angle > largest_gap) largest_gap = next - hits[k].angle, start = (k + 1) % hits.size();
  }
  std::vector<std::vector<Hit>> groups;
  for (std::size_t c = 0; c < hits.size(); ++c) {
    const Hit& h = hits[(start + c) % hits.size()];
    if (groups.empty()) {
      groups.push_back({h});
      continue;
    }
    double gap = h.angle - groups.back().back().angle;
    if (gap < 0) gap += 2 * M_PI;
    if (gap > max_gap_angle) groups.push_back({h});
    else groups.back().push_back(h);
  }
  for (const auto& g : groups) {
    HoleCrack crack;
    crack.particles = g.size();
    double sx = 0, sy = 0;
    for (const auto& h : g) sx += std::cos(h.angle), sy += std::sin(h.angle);
    crack.angle_degrees = std::atan2(sy, sx) * 180.0 / M_PI;
    // Initiation: the earliest damage in this crack's angular sector between the hole's edge and the ring's outer radius.
    const double a0 = g.front().angle - max_gap_angle, a1 = g.back().angle + max_gap_angle;
    if (!damage_load_factor.empty())
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (damage_load_factor[i] < 0) continue;
        const double dx = p.x[i] - ring.cx, dy = p.y[i] - ring.cy;
        if (std::hypot(dx, dy) - ring.radius > ring.outer) continue;
        double a = std::atan2(dy, dx);
        while (a < a0) a += 2 * M_PI;
        if (a > a1) continue;
        if (crack.initiation_load_factor < 0 || damage_load_factor[i] < crack.initiation_load_factor)
          crack.initiation_load_factor = damage_load_factor[i];
      }
    cracks.push_back(crack);
  }
  return cracks;
}

}  // namespace pd::validation
