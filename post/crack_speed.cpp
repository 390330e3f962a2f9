#include "crack_speed.hpp"

#include <algorithm>
#include <cmath>

namespace pd::post {

std::vector<SpeedSample> crack_speeds(const TipPath& path, const CrackBranch& branch, int window_steps,
                                      double jump_length) {
  std::vector<SpeedSample> out;
  const std::size_t n = path.time.size();
  const std::size_t w = static_cast<std::size_t>(std::max(1, window_steps));
  // jumps_before[k]: one-step tip moves longer than jump_length among steps 1..k.
  std::vector<int> jumps_before(n, 0);
  for (std::size_t k = 1; k < n; ++k)
    jumps_before[k] = jumps_before[k - 1] +
                      (std::hypot(path.x[k] - path.x[k - 1], path.y[k] - path.y[k - 1]) > jump_length ? 1 : 0);
  for (std::size_t k = 0; k + w < n; ++k) {
    SpeedSample s;
    s.time = path.time[k];
    s.branch = path.branch;
    s.tip_x = path.x[k];
    const double dt = path.time[k + w] - path.time[k];
    s.speed = std::hypot(path.x[k + w] - path.x[k], path.y[k + w] - path.y[k]) / dt;
    const double half_step = 0.5 * dt / w;
    for (double restart : branch.pore_restart_times)
      s.across_pore |= restart > path.time[k] + half_step && restart <= path.time[k + w] + half_step;
    s.tip_jump = jumps_before[k + w] > jumps_before[k];
    out.push_back(s);
  }
  return out;
}

SpeedStats speed_stats(const std::vector<SpeedSample>& samples, int branch) {
  SpeedStats st;
  double sum = 0;
  for (const auto& s : samples) {
    if (!s.is_growth() || (branch >= 0 && s.branch != branch)) continue;
    st.max = std::max(st.max, s.speed);
    sum += s.speed;
    ++st.samples;
  }
  st.mean = st.samples ? sum / st.samples : 0;
  return st;
}

}  // namespace pd::post
