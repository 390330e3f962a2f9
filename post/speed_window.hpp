#pragma once
// The crack-speed window, chosen from the physics rather than as a step count.
//
// The tip moves a particle at a time, so a window in which it crosses n cells
// measures the speed to within about one cell in n. The default window is
// the time a tip running at the Rayleigh speed c_R needs to cross
// `window_cells_at_rayleigh` = 15 cells of the lattice spacing dx,
//   w = ceil(15 dx / (c_R dt)) steps,
// so a one-cell step of the tip changes a window's speed by at most c_R / 15
// (7 % of c_R), whatever the time step. At the paper's dx = 0.04 mm,
// dt = 0.02 us (c_R = 929 m/s) that is 33 steps, about the paper's 30
// [Peng, Chen, Bobaru 2023, App. 2], which cross 14 cells at c_R.
#include <string>
#include <vector>

namespace pd::post {

inline constexpr double window_cells_at_rayleigh = 15.0;

struct SpeedWindow {
  int steps = 0;           // the window used
  double seconds = 0;      // steps x dt
  int rule_steps = 0;      // the default rule's window
  bool requested = false;  // given on the command line (--window, --window-time)
  // Cells of size dx the tip crosses in the window at c_R.
  double cells_at_rayleigh = 0;
};

// The window: `requested_seconds` (> 0, rounded to whole steps) or
// `requested_steps` (> 0), else the rule. A requested window shorter than the
// rule's adds a warning that says by how much speeds may be quantised.
// Throws pd::Error for a requested window below one step, and one naming
// `source` (the arrival.vtp whose field time_step this is) for a rule's
// window beyond an int.
SpeedWindow choose_speed_window(double time_step, double spacing, double rayleigh_speed, int requested_steps,
                                double requested_seconds, std::vector<std::string>& warnings,
                                const std::string& source);

}  // namespace pd::post
