#pragma once
// A scene that switches from quasi-static to dynamic (quasi_static.then =
// "dynamic"; case C3's static-then-dynamic check, [Peng, Chen, Bobaru 2023,
// App. 3]): the load steps of [quasi_static] with the loads of phase
// "quasi_static", then time integration from that equilibrium with [time] and
// the loads of phase "dynamic" (docs/scenes.md, docs/solver.md).
#include "quasi_static_run.hpp"
#include "results_format.hpp"
#include "run.hpp"
#include "scene.hpp"
#include "simulation.hpp"

namespace pd::solver {

// The files of the quasi-static part go to OUTDIR/results::quasi_static_part_folder.
using results::quasi_static_part_folder;

// The parts of a switching scene as scenes of their own, each with its own loads.
// The [stop] table belongs to the dynamic part; with checkpoints on, the
// quasi-static part checkpoints after every load step.
Scene quasi_static_part(const Scene& scene);
Scene dynamic_part(const Scene& scene);

// Puts a simulation at t = 0 into a quasi-static equilibrium: positions =
// reference + u; the broken pairs broken in both directions; velocities as
// the simulation's loads prescribe at t = 0 (else 0); arrival times 0 where the
// damage already reaches a threshold.
void start_from_equilibrium(Simulation& sim, const Equilibrium& equilibrium);

// pd-solve on a switching scene: the quasi-static part writes
// OUTDIR/quasi_static/ (as a quasi-static run), the dynamic part OUTDIR (as a
// dynamic run, with its checkpoints, the first at the switch). --restart
// continues the dynamic part from its checkpoint, which holds the whole
// state, without repeating the quasi-static part; a run stopped before the
// switch continues the quasi-static part from its checkpoint, then switches.
RunReport run_static_then_dynamic(const Scene& scene, const RunOptions& options);

}  // namespace pd::solver
