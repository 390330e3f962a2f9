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
  void finish(long step, double time_s);
  double elapsed_seconds() const;

private:
  void print(long step, double time_s, bool final_line);
  using Clock = std::chrono::steady_clock;
  long first_step_, last_step_;
  std::size_t bonds_per_step_;
  bool enabled_, terminal_;
  Clock::time_point start_, last_print_;
  long next_quiet_step_ = 0;
};

}  // namespace pd::solver
