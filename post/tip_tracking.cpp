#include "tip_tracking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "neighbor_search.hpp"

namespace pd::post {

double tip_start_time(const CrackBranch& branch, const ArrivalData& data, double time_step) {
  if (branch.particles.empty()) return branch.start_time;
  const double first = data.arrival[branch.particles.front()];
  if (first > 0) return first;
  // A pre-crack: its particles seed the tip, which first moves when the
  // first particle beyond them cracks.
  for (auto p : branch.particles)
    if (data.arrival[p] > 0) return std::max(0.0, data.arrival[p] - time_step);
  return 0.0;
}

TipPath track_tip(const CrackBranch& branch, const ArrivalData& data, double time_step) {
  TipPath path;
  path.branch = branch.id;
  std::vector<double> bx, by;
  for (auto p : branch.particles) bx.push_back(data.x[p]), by.push_back(data.y[p]);
  NeighborSearch search(bx, by);
  std::vector<std::uint32_t> near;

  double tip_x = branch.origin_x, tip_y = branch.origin_y, reach = -1;
  std::size_t next = 0, farthest = 0;  // branch.particles are sorted by arrival time
  const double start = tip_start_time(branch, data, time_step);
  // Half a step of tolerance: arrival times are multiples of the time step
  // up to round-off.
  // At least one sample, even for a branch that lives less than a step.
  const auto steps = std::max(0L, static_cast<long>(std::floor((branch.end_time - start) / time_step + 0.5)));
  for (long k = 0; k <= steps; ++k) {
    const double t = start + k * time_step;
    const std::size_t before = next;
    while (next < branch.particles.size() && data.arrival[branch.particles[next]] <= t + 0.5 * time_step) {
      const auto p = branch.particles[next];
      const double r = std::hypot(data.x[p] - branch.origin_x, data.y[p] - branch.origin_y);
      if (r > reach) reach = r, farthest = next;
      ++next;
    }
    if (next != before) {
      // The most advanced particle, averaged with the cracked particles
      // linked to it: the damage band is a few particles wide and the single
      // farthest one hops across it from step to step.
      const auto p = branch.particles[farthest];
      search.within(data.x[p], data.y[p], 1.5 * data.cell_size[p], near);
      double sx = 0, sy = 0;
      int n = 0;
      for (auto m : near)
        if (m < next) sx += bx[m], sy += by[m], ++n;
      tip_x = sx / n, tip_y = sy / n;
    }
    path.time.push_back(t);
    path.x.push_back(tip_x);
    path.y.push_back(tip_y);
  }
  // A child's length counts from its branching point: one whose particles
  // crack only after it branched again (a short link in a cascade of
  // branchings) has a single sample, and measured from that it read 0.
  const bool pre_crack = branch.parent < 0 && !branch.particles.empty() && data.arrival[branch.particles.front()] <= 0;
  path.start_x = pre_crack ? path.x.front() : branch.origin_x;
  path.start_y = pre_crack ? path.y.front() : branch.origin_y;
  return path;
}

std::vector<TipPath> track_tips(const CrackNetwork& network, const ArrivalData& data) {
  std::vector<TipPath> paths;
  for (const auto& b : network.branches) paths.push_back(track_tip(b, data, data.time_step));
  return paths;
}

double tip_path_length(const TipPath& path, double min_step) {
  // A polyline through the tip's positions, each vertex at least min_step
  // from the one before (and the last position): the tip's hops between
  // particles of the band, sideways and back, are no crack length.
  if (path.x.empty()) return 0;
  double length = 0, vx = path.start_x, vy = path.start_y;
  for (std::size_t k = 0; k < path.x.size(); ++k) {
    const double step = std::hypot(path.x[k] - vx, path.y[k] - vy);
    if (step >= min_step || k + 1 == path.x.size()) length += step, vx = path.x[k], vy = path.y[k];
  }
  return length;
}

}  // namespace pd::post
