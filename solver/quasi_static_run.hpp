#pragma once
// pd-solve on a quasi-static scene: set-up, the load steps of quasi_static.hpp,
// the plan and per-step report on the log, and the output directory
// (load_steps.csv, snapshots every output.snapshot_interval load steps,
// final_state.vtp, summary.json; docs/solver.md).
#include "run.hpp"

namespace pd::solver {

RunReport run_quasi_static_scene(const Scene& scene, const RunOptions& options);

}  // namespace pd::solver
