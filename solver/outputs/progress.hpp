#pragma once
// Progress on stderr: a line rewritten in place on a terminal, or a quiet
// line every 10 % (and at least every 60 s) when stderr is a file or pipe.
#include <chrono>
#include <cstddef>

namespace pd::solver {

class Progress {
public:
  Progress(long first_step, long last_step, std::size_t bonds_per_step, bool enabled);
  void update(long step, double time_s);
  // The last line: at the run's end (finish), or where it stopped before it
  // (stopped: an interrupt or an instability; the line then says so, no ETA).
  void finish(long step, double time_s);
  void stopped(long step, double time_s);
  // From `step` on, the run ends at `last_step` and a step evaluates
  // `bonds_per_step` bonds (a refinement event changes both, and the time step).
  void replan(long step, long last_step, std::size_t bonds_per_step);
  double elapsed_seconds() const;

private:
  enum class Line { running, finished, stopped };
  void print(long step, double time_s, Line line);
  using Clock = std::chrono::steady_clock;
  long first_step_, last_step_;
  std::size_t bonds_per_step_;
  long plan_first_step_;             // the step from which bonds_per_step_ holds
  double bonds_before_plan_ = 0;     // bond evaluations of the steps before it
  bool enabled_, terminal_;
  Clock::time_point start_, last_print_;
  long next_quiet_step_ = 0;
};

}  // namespace pd::solver
