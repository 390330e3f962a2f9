#pragma once
// pd-solve on a dynamic scene: builds the Simulation, steps it to the end
// time or the stop condition, and writes energy.csv, snapshots,
// arrival.vtp, checkpoints and summary.json (docs/solver.md).
#include <functional>
#include <memory>

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

// The refusals of a dynamic run that do not depend on its start state, made
// on its set-up without writing any result: a fixed time step above the
// stable limit, a step count beyond any machine, snapshots beyond the disk
// (pd::Error as run_dynamic raises them). A switching scene checks its
// dynamic part so before its quasi-static part, which may take hours.
// Returns the surface-correction factors its set-up kept back from OUTDIR's
// cache (RunContext::write_deferred_cache), for the run to write once its
// other checks have passed.
std::shared_ptr<DeferredCacheWrite> check_dynamic_plan(RunContext run);

}  // namespace pd::solver
