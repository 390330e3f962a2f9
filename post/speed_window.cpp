#include "speed_window.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "error.hpp"

namespace pd::post {

SpeedWindow choose_speed_window(double dt, double spacing, double rayleigh, int requested_steps,
                                double requested_seconds, std::vector<std::string>& warnings,
                                const std::string& source) {
  SpeedWindow w;
  // The small tolerance keeps an exact multiple of dt from rounding up a step.
  const double rule_steps = std::ceil(window_cells_at_rayleigh * spacing / (rayleigh * dt) - 1e-9);
  // read_arrival_data bounds the wave speed, the spacing and the step count
  // to the run's end, not the step itself: a run that ends at its start
  // (end_time 0) may carry any time_step, and 1e-300 s (an edited file)
  // makes the rule a count beyond an int, refused by the file rather than
  // cast (before 7 December 2026 the message named no file).
  if (!(rule_steps < std::numeric_limits<int>::max())) {
    char text[480];
    std::snprintf(text, sizeof text,
                  "field 'time_step' = %.3g s makes the speed window's rule, the time a tip at c_R = %.3g m/s "
                  "takes to cross %.0f cells of %.3g mm, %.3g steps, more than an int counts (an edited or damaged "
                  "file)",
                  dt, rayleigh, window_cells_at_rayleigh, spacing * 1e3, rule_steps);
    throw file_error(source, text);
  }
  w.rule_steps = std::max(1, static_cast<int>(rule_steps));
  if (requested_seconds > 0) {
    // Counted in an int: a window beyond it is a time in another unit (600
    // for 600 ns), which before 7 December 2026 wrapped round and was said
    // to round to 0 steps.
    const double steps = requested_seconds / dt;
    if (!(steps < std::numeric_limits<int>::max())) {
      char text[320];
      std::snprintf(text, sizeof text,
                    "--window-time %.4g s is %.3g solver steps (one step is %.4g s), more than the %d a window can "
                    "span: times are in s, or give the unit (e.g. --window-time 2us)",
                    requested_seconds, steps, dt, std::numeric_limits<int>::max());
      throw Error(text);
    }
    w.steps = static_cast<int>(std::lround(steps));
    if (w.steps < 1) {
      char text[240];
      std::snprintf(text, sizeof text,
                    "--window-time %.4g s rounds to 0 solver steps (one step is %.4g s): give at least one step, "
                    "e.g. --window-time %.4g or --window 1",
                    requested_seconds, dt, dt);
      throw Error(text);
    }
    w.requested = true;
  } else if (requested_steps != 0) {
    if (requested_steps < 1)
      throw Error("--window " + std::to_string(requested_steps) + ": must be at least 1 solver step");
    w.steps = requested_steps;
    w.requested = true;
  } else {
    w.steps = w.rule_steps;
  }
  w.seconds = w.steps * dt;
  w.cells_at_rayleigh = rayleigh * w.seconds / spacing;
  if (w.requested && w.steps < w.rule_steps) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "the speed window of %d steps (%.3g us) is shorter than %d steps (%.3g us), the time a tip at "
                  "c_R needs to cross %.0f cells of %.3g mm: in it a tip at c_R crosses %.1f cells, so a one-cell "
                  "step of the tip changes a window's speed by %.0f %% of c_R",
                  w.steps, w.seconds * 1e6, w.rule_steps, w.rule_steps * dt * 1e6, window_cells_at_rayleigh,
                  spacing * 1e3, w.cells_at_rayleigh, 100.0 / w.cells_at_rayleigh);
    warnings.push_back(text);
  }
  return w;
}

}  // namespace pd::post
