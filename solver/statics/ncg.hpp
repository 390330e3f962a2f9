#pragma once
// Energy minimisation by nonlinear conjugate gradients (theory.md Sec. 4;
// [Peng, Chen, Bobaru 2023, Sec. 2] use NCG for their quasi-static runs).
//
// Method: Polak-Ribiere conjugate directions with the non-negativity reset
// ("PR+", Nocedal & Wright 2006, Sec. 5.2), preconditioned by the diagonal of
// the Hessian (Jacobi), and a Newton line search along each direction,
//   alpha = (r . d) / (d . H d),
// with the exact Hessian-vector product of the bond energies. The PD energy is
// almost quadratic at the strains of interest (the geometric nonlinearity is
// of the order of the strain), so this step lands on the line minimum to that
// order; a direction of non-positive curvature or one that does not descend
// restarts along the preconditioned steepest descent.
//
// Convergence: |r| <= tolerance * max(|F|, force_floor), with r the residual
// (out-of-balance) forces on the free components and |F| the norm of the
// forces the body carries (support reactions and applied tractions) at the
// same state (EnergyProblem::reaction_norm). The floor keeps the test
// meaningful once a sample has separated and carries almost nothing.
#include <exception>
#include <functional>
#include <vector>

#include "communicator.hpp"
#include "energy_problem.hpp"

namespace pd::solver {

// Where a running minimisation stands (progress lines).
struct NcgProgress {
  long iteration = 0;
  double relative_residual = 0;  // |r| / max(|F|, force_floor) at that iteration
  double seconds = 0;            // since the minimisation started
};

struct NcgSettings {
  double tolerance = 1e-6;
  long max_iterations = 20000;
  double force_floor = 0;  // [N]
  long restart_interval = 0;  // steepest-descent restart every N iterations; 0 = only when needed
  // Called after an iteration once at least `progress_interval` seconds have
  // passed since the start or the last call (0: after every iteration). A
  // minimisation at a fine resolution can run for minutes: the user sees that it moves.
  std::function<void(const NcgProgress&)> progress;
  double progress_interval = 10;  // [s]
  // Stalled (0: never looked for): the relative residual has not gone below
  // the least it reached, at iteration b, in the iterations since, and they
  // are at least max(stall_iterations, b) (on the lattice kernels a new least
  // energy of the damped rounds counts as progress too). At the round-off
  // floor of a state (a tolerance just above double's round-off that the
  // plate cannot reach) more iterations only wander about it; the
  // minimisation then stops, unconverged, with `stalled` set. A minimisation
  // that converges never meets it.
  long stall_iterations = 0;
  // Asked after every iteration (when given): true abandons the minimisation
  // with MinimisationAbandoned (Ctrl-C: a minimisation at a fine resolution
  // can run for minutes, and its caller goes back to its last equilibrium).
  std::function<bool()> abandon;
};

// Thrown when NcgSettings::abandon said so: u is left where the last
// iteration put it, no equilibrium.
struct MinimisationAbandoned : std::exception {
  const char* what() const noexcept override { return "minimisation abandoned"; }
};

struct NcgResult {
  bool converged = false;
  long iterations = 0;
  double residual_norm = 0;       // |r| [N]
  double reference_norm = 0;      // max(|F|, force_floor) [N]
  // Stopped before max_iterations: no direction left that descends with
  // positive curvature (more iterations would not help).
  bool no_descent = false;
  // Stopped before max_iterations on NcgSettings::stall_iterations's rule:
  // the least relative residual reached, and the iterations at the end
  // without progress.
  bool stalled = false;
  double least_relative_residual = 0;
  long stalled_iterations = 0;
  double relative_residual() const { return reference_norm > 0 ? residual_norm / reference_norm : residual_norm; }
};

// Minimises the problem's energy over its free components, starting from u
// (constrained components already set); u holds the result. Dot products
// are reduced through `communicator`.
NcgResult minimise_energy(EnergyProblem& problem, std::vector<double>& u, const NcgSettings& settings,
                          const Communicator& communicator = serial_communicator());

}  // namespace pd::solver
