#pragma once
// pd-solve on a dynamic scene: builds the Simulation, steps it to the end
// time or the stop condition, and writes energy.csv, snapshots,
// arrival.vtp, checkpoints and summary.json (docs/solver.md).
#include <functional>

#include "run.hpp"
#include "run_context.hpp"
#include "simulation.hpp"

namespace pd::solver {

// `initial_state`, for a run that is not restarted: sets the state at t = 0
// before the first output (a quasi-static equilibrium,
// static_then_dynamic.hpp); with checkpoints on, that state is checkpointed
// at once. Empty = at rest.
using InitialState = std::function<void(Simulation&)>;

RunReport run_dynamic(RunContext run, const InitialState& initial_state = {});

}  // namespace pd::solver
