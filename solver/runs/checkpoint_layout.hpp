#pragma once
// A one-process run's checkpoint restarted on several processes
// (docs/solver.md, "Safety"). One process saves its bond states in its
// kernels' own layout (the lattice sweep's pair bits, then its lists), which
// only a one-process set-up of the whole plate can read; several processes
// place the family-by-family layout (Simulation::State::bond_states_by_family).
// The root turns the one into the other once, at the restart, so that the
// one-process writer stays as it was (a bit per pair, no family walk).
#include <string>

#include "communicator.hpp"
#include "run_context.hpp"
#include "simulation.hpp"

namespace pd::solver {

// `state` (read from `checkpoint_path`) with its bond states family by
// family: unchanged if they are already; else the root makes the whole
// plate's one-process simulation of the run's scene (keeping its families),
// restores the state into it, takes its bond states family by family and
// drops it, and every process gets them from the root (collective). An
// error, agreed by the processes, names the checkpoint.
void take_bond_states_by_family(const RunContext& run, const std::string& checkpoint_path, Simulation::State& state,
                                const Communicator& communicator);

}  // namespace pd::solver
