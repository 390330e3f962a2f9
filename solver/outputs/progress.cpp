#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace pd::solver {

Progress::Progress(long first_step, long last_step, std::size_t bonds_per_step, bool enabled)
    : first_step_(first_step),
      last_step_(last_step),
      bonds_per_step_(bonds_per_step),
      plan_first_step_(first_step),
      enabled_(enabled),
      terminal_(::isatty(STDERR_FILENO) != 0), start_(Clock::now()), last_print_(start_) {
  next_quiet_step_ = first_step_ + (last_step_ - first_step_) / 10;
}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

void Progress::update(long step, double time_s) {
  if (!enabled_ || step >= last_step_) return;  // the last line is finish()'s
  const auto now = Clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (terminal_ ? since < 0.5 : (step < next_quiet_step_ && since < 60)) return;
  last_print_ = now;
  if (!terminal_) next_quiet_step_ = step + std::max(1L, (last_step_ - first_step_) / 10);
  print(step, time_s, Line::running);
}

void Progress::replan(long step, long last_step, std::size_t bonds_per_step) {
  bonds_before_plan_ += static_cast<double>(step - plan_first_step_) * static_cast<double>(bonds_per_step_);
  plan_first_step_ = step;
  last_step_ = last_step;
  bonds_per_step_ = bonds_per_step;
  next_quiet_step_ = std::min(next_quiet_step_, step + std::max(1L, (last_step_ - first_step_) / 10));
}

void Progress::finish(long step, double time_s) {
  if (enabled_) print(step, time_s, Line::finished);
}

void Progress::stopped(long step, double time_s) {
  if (enabled_) print(step, time_s, Line::stopped);
}

void Progress::print(long step, double time_s, Line line) {
  const double elapsed = elapsed_seconds();
  const long done = step - first_step_, total = last_step_ - first_step_;
  const double rate = elapsed > 0 ? done / elapsed : 0;  // steps/s
  const double eta = rate > 0 ? (last_step_ - step) / rate : 0;
  const double bonds_done =
      bonds_before_plan_ + static_cast<double>(step - plan_first_step_) * static_cast<double>(bonds_per_step_);
  const double bonds_per_second = elapsed > 0 ? bonds_done / elapsed : 0;
  char remaining[48];
  if (line == Line::stopped)
    std::snprintf(remaining, sizeof remaining, "stopped");
  else
    std::snprintf(remaining, sizeof remaining, "ETA %.0f s", line == Line::finished ? 0.0 : eta);
  std::fprintf(stderr, "%sstep %ld/%ld (%.1f %%) t = %.4g s, %.1f s elapsed, %s, %.3g bond evaluations/s%s",
               terminal_ ? "\r" : "", step, last_step_, total > 0 ? 100.0 * done / total : 100.0, time_s, elapsed,
               remaining, bonds_per_second, terminal_ && line == Line::running ? "   " : "\n");
  std::fflush(stderr);
}

}  // namespace pd::solver
