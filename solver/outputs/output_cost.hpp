#pragma once
// What a dynamic run's outputs cost, measured in the run itself, so that the
// share holds whatever the machine's load (both parts are slowed alike):
// the wall time of the output work between steps (energy rows with their
// energy sums and safe state, snapshots, checkpoints, arrival times and the
// files of each), plus what the steps that also sum the strain energy for a
// row take beyond a plain step (the mean plain step's time times their number
// is subtracted from their time). docs/performance.md reports the share.
#include <chrono>

namespace pd::solver {

class OutputCost {
public:
  using Clock = std::chrono::steady_clock;

  // Times one step: `with_energy` when it sums the strain energy for a file.
  template <class Step>
  void time_step(bool with_energy, Step&& step) {
    const auto start = Clock::now();
    step();
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    (with_energy ? energy_step_seconds_ : plain_step_seconds_) += seconds;
    ++(with_energy ? energy_steps_ : plain_steps_);
  }
  // Times output work between steps.
  template <class Work>
  void time_output(Work&& work) {
    const auto start = Clock::now();
    work();
    writing_seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
  }

  // [s] the outputs' part of the time loop.
  double seconds() const {
    const double plain_mean = plain_steps_ > 0 ? plain_step_seconds_ / static_cast<double>(plain_steps_) : 0.0;
    const double energy_extra = energy_step_seconds_ - static_cast<double>(energy_steps_) * plain_mean;
    return writing_seconds_ + (plain_steps_ > 0 && energy_extra > 0 ? energy_extra : 0.0);
  }
  // [s] the steps and the output work together.
  double loop_seconds() const { return plain_step_seconds_ + energy_step_seconds_ + writing_seconds_; }
  // seconds() over the rest of the loop (0 before any step).
  double share() const {
    const double rest = loop_seconds() - seconds();
    return rest > 0 ? seconds() / rest : 0.0;
  }

private:
  double plain_step_seconds_ = 0, energy_step_seconds_ = 0, writing_seconds_ = 0;
  long plain_steps_ = 0, energy_steps_ = 0;
};

}  // namespace pd::solver
