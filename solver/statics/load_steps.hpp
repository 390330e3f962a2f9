#pragma once
// Displacement-controlled quasi-static loading (docs/solver.md, "Quasi-static
// mode"): for each load factor of the scene, minimise the energy (ncg.hpp);
// with damage, break every over-stretched bond and minimise again, until no
// bond breaks at that load (the step is then in equilibrium with its damage).
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "ncg.hpp"
#include "quasi_static_problem.hpp"

namespace pd::solver {

struct LoadStepRecord {
  long step = 0;                 // 1, 2, ...
  double load_factor = 0;
  long minimisations = 0;        // 1 + re-equilibrations after breaking
  long iterations = 0;           // NCG iterations, all minimisations of the step
  double relative_residual = 0;  // of the last minimisation
  bool converged = true;         // every minimisation of the step converged
  double strain_energy = 0;      // [J]
  double potential_energy = 0;   // [J], strain energy minus the work of the tractions
  std::size_t pairs_broken = 0;  // bonds (pairs) broken during this step
  std::size_t broken_bonds = 0;  // directed bonds broken so far, pre-cracks included
  std::vector<LoadResultant> reactions;  // per load [N]
  double max_damage = 0;
};

// The bond sweeps every load step of solve_quasi_static makes at the least,
// counted where they are made: the residual at its start (forces that are no
// numbers refused before any minimisation), its minimisation's first
// residual, and the strain and potential energies of its record. An NCG
// iteration takes 2 more (a residual and a Hessian product). The plan's
// least cost of the load steps (load_step_length) counts them.
constexpr int least_sweeps_per_load_step = 1 + 1 + 2;

// Called after every load step (for outputs and progress).
using LoadStepObserver =
    std::function<void(const QuasiStaticProblem&, const std::vector<double>& u, const LoadStepRecord&)>;

// Where the load steps stand after a step: with the problem's bond states
// (QuasiStaticProblem::bond_states) all that is needed to go on exactly as
// an uninterrupted run would (checkpoints, --restart).
struct LoadStepState {
  std::vector<double> load_factors_done;   // of the steps done, in order
  std::vector<double> u;                   // displacements (x block, then y block) [m]
  std::vector<double> damage_load_factor;  // as in QuasiStaticResult
  double largest_reaction_norm = 0;        // of the converged states so far (the residual floor)
  double largest_axial_reaction = 0;       // peak load cell reading so far (stop_reaction_fraction)
  // The last step's displacement increment u_k - u_k-1 when no bond broke in
  // it (the predictor's tangent, theory.md Sec. 4.11); empty otherwise.
  std::vector<double> last_increment;
  std::string stop_reason;                 // why the steps ended early (empty while they go on)
};
using LoadStepStateObserver = std::function<void(const LoadStepState&)>;

// Where the load steps stood when a request to stop (Ctrl-C, SIGTERM)
// ended them early: the state to go on from, as a checkpoint holds it.
struct InterruptedLoadSteps {
  long step = 0;           // the load step reached (1, 2, ...)
  bool abandoned = false;  // the request came within that step: its work is dropped, and it is done again
  LoadStepState state;     // of the last completed step (the step reached, unless abandoned)
  std::vector<std::uint8_t> bond_states;  // of that step (QuasiStaticProblem::bond_states)
};

struct QuasiStaticResult {
  std::vector<LoadStepRecord> steps;
  std::vector<double> u;                   // final displacements (x block, then y block) [m]
  std::vector<double> damage;              // final damage index
  std::vector<double> damage_load_factor;  // per particle: load factor at which it first had damage, -1 if never
  std::string stop_reason;                 // "last load step", the stop condition or "interrupted"
  std::vector<std::string> warnings;       // this call's (on_nonconvergence = "warn"), as printed
  std::optional<InterruptedLoadSteps> interrupted;  // set when `stop_requested` ended the steps
};

// Runs the scene's load steps. Non-convergence is a pd::Error naming the step,
// the load factor and the residual reached, unless the scene says
// on_nonconvergence = "warn" (then a warning goes to `log`, and to
// `warning_echo` when not null, and the run goes on). `stop_region`: particles of the scene's [stop] region (empty = none).
// `resume`: continue after the steps of this state (the problem's bond
// states restored by the caller); its load factors must be the first of the
// scene's; a state that ended early (stop condition, separation) takes no
// further step. `state_observer` sees the state after every step, its stop
// decision included. `progress` (optional): a line every
// quasi_static.progress_interval seconds (default 10; at the end of the iteration
// that passes it) while a minimisation runs
// (iteration, relative residual, seconds) and while a load step
// re-equilibrates after bonds break (a running crack can take minutes).
// `stop_requested` (optional; Ctrl-C, SIGTERM) is asked after every step,
// after every iteration of its minimisations and between its breaking
// rounds: true ends the steps with the result's `interrupted` set, after the
// step just done, or within a step, which is then abandoned (its work
// dropped; the problem keeps the bonds broken in it, so go on from
// `interrupted`'s state on a new problem, as a restart does).
// The result's `steps` are those of this call.
QuasiStaticResult solve_quasi_static(QuasiStaticProblem& problem, const Scene& scene,
                                     const std::vector<std::uint32_t>& stop_region, std::ostream& log,
                                     const LoadStepObserver& observer = {}, const LoadStepState* resume = nullptr,
                                     const LoadStepStateObserver& state_observer = {},
                                     std::ostream* progress = nullptr, std::ostream* warning_echo = nullptr,
                                     const std::function<bool()>& stop_requested = {});

// Throws unless the saved state `resume` can continue under `scene` on
// `particle_count` particles: its sizes fit, and its load factors are the
// first of the scene's (a restart may only add load steps). solve_quasi_static
// checks it; a restart checks it first, before it changes the folder.
void check_resumable(const Scene& scene, std::size_t particle_count, const LoadStepState& resume);

// Load resultant of a record as one number: the largest |reaction_x| over the
// displacement loads (what a tensile test's load cell reads), or 0 without them.
double axial_reaction(const std::vector<LoadResultant>& reactions, const std::vector<ResolvedLoad>& loads);
inline double axial_reaction(const LoadStepRecord& record, const std::vector<ResolvedLoad>& loads) {
  return axial_reaction(record.reactions, loads);
}

}  // namespace pd::solver
