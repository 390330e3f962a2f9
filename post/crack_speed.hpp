#pragma once
// Crack speed over a moving window, v(t) = |tip(t + w) - tip(t)| / w
// [Peng, Chen, Bobaru 2023, App. 2], reported at the window's start time t.
// The window w: speed_window.hpp.
#include <vector>

#include "crack_branches.hpp"
#include "tip_tracking.hpp"

namespace pd::post {

struct SpeedSample {
  double time = 0;   // window start [s]
  int branch = 0;
  double tip_x = 0;  // tip x at the window's start [m]
  double speed = 0;  // [m/s]
  bool across_pore = false;  // the window contains a jump to the far side of a pore
  // The window contains a tip move longer than `jump_length` in one time step:
  // a crack front grows at most c_R dt per step (a few hundredths of a horizon),
  // so such a move is a jump onto a separate damage group (over a gap in the
  // band), not growth.
  bool tip_jump = false;
  bool is_growth() const { return !across_pore && !tip_jump; }
};

// Samples at every time step k with k + window_steps inside the branch's tip
// path. `jump_length` [m]: see SpeedSample::tip_jump (pd-post uses one horizon).
std::vector<SpeedSample> crack_speeds(const TipPath& path, const CrackBranch& branch, int window_steps,
                                      double jump_length);

struct SpeedStats {
  double max = 0, mean = 0;  // [m/s], over growth samples (no pore crossing, no tip jump)
  int samples = 0;
};
SpeedStats speed_stats(const std::vector<SpeedSample>& samples, int branch = -1);

}  // namespace pd::post
