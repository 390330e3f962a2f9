#pragma once
// pd-solve on a quasi-static scene: the load steps of load_steps.hpp, the
// plan and per-step report on the log, and the output directory
// (load_steps.csv, snapshots every output.snapshot_interval load steps,
// final_state.vtp, summary.json; docs/solver.md).
#include <cstdint>
#include <utility>
#include <vector>

#include "plan_limits.hpp"
#include "run.hpp"
#include "run_context.hpp"

namespace pd::solver {

// The state a quasi-static run ends in, for a dynamic run that starts from it.
struct Equilibrium {
  std::vector<double> u;  // displacements (x block, then y block) [m]
  std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs;  // QuasiStaticProblem::broken_pairs()
  double load_factor = 0;  // of the last load step
};

// `end_state`, if given, receives the final equilibrium.
RunReport run_quasi_static(RunContext run, Equilibrium* end_state = nullptr);

// The scene's load steps after the first `done` (a restart's) as the plan's
// limits count them (check_run_length): least_sweeps_per_load_step
// (load_steps.hpp) sweeps of `bond_count` directed bonds per load step, at
// `sweep_seconds` each (one residual timed at set-up).
RunLength load_step_length(const Scene& scene, double bond_count, std::size_t done, double sweep_seconds);

}  // namespace pd::solver
