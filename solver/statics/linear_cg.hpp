#pragma once
// Linear preconditioned conjugate gradients for the correction of a
// minimisation round (mixed_precision.cpp, theory.md Sec. 4.12): w with
// H w = r, H the problem's Hessian product at a fixed state. Source: Nocedal &
// Wright 2006, Algorithm 5.3 (preconditioned CG), with the stop at a
// direction of non-positive curvature of their Algorithm 7.2 (CG-Steihaug):
// after bonds break, the tangent Hessian need not be positive definite.
//
// Unlike minimise_energy on the quadratic 1/2 w.H w - r.w, the residual
// r - H w is updated from the product the step needs (r_k+1 = r_k - alpha H d):
// one product per iteration instead of two.
#include <vector>

#include "energy_problem.hpp"
#include "ncg.hpp"

namespace pd::solver {

struct LinearSolveResult {
  long iterations = 0;
  double residual_norm = 0;         // |r - H w| [N] (the recurrence's)
  bool converged = false;           // |r - H w| <= tolerance |r|
  bool negative_curvature = false;  // stopped at a direction d with d.H d <= 0 (w is the last iterate)
  bool diverged = false;            // stopped when |r - H w| grew past 1e3 |r| (w is then 0)
  bool stagnated = false;           // stopped when |r - H w| had not halved for stagnation_window iterations (w kept)
};

// CG that has not halved its residual for this many iterations has stalled
// (a tangent that is nearly singular or indefinite on directions it has not
// met yet, after bonds broke): its correction so far goes to the caller's
// test instead of running on to the iteration limit. Healthy rounds halve
// it every 10 to 150 iterations (docs/performance.md, "Quasi-static on the
// fast kernels").
constexpr long stagnation_window = 500;

// a . b summed serially in index order: the solvers' results must not depend
// on the thread count.
double dot(const std::vector<double>& a, const std::vector<double>& b);

// From w = 0: CG on H w = r with the problem's preconditioner (precondition()) and
// Hessian products at `state`. `settings.tolerance` is relative to |r| here
// (force_floor is not used); progress lines give |r - H w| / |r|; `settings.abandon`
// is asked after every iteration (MinimisationAbandoned).
LinearSolveResult solve_linear(const EnergyProblem& problem, const std::vector<double>& state,
                               const std::vector<double>& r, std::vector<double>& w, const NcgSettings& settings);

}  // namespace pd::solver
