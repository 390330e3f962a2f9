#pragma once
// Energy minimisation on the lattice kernels (docs/solver.md, "Fast kernels";
// theory.md Sec. 4): the residual where it decides convergence in double,
// everything else in float. With the energy table (double only) it is
// minimise_energy.
//
// Why not NCG on the float residual: the float sweep rounds the
// displacements to 24 bits (about 6e-8 |u| in every bond's extension of
// ~strain |xi|); at equilibrium that leaves the float residual a floor of a
// few 1e-6 of the reactions on the C1 plate at dx = 0.4 mm and 1e-5 at
// 0.2 mm, above the usual tolerance 1e-6, and NCG on it stalls there.
//
// Method (defect correction, a Newton iteration on the lattice kernels'
// tangent): at u, the residual r(u) in double (one double pass); then the
// correction w with H w = r by linear CG (linear_cg.hpp) with the float
// tangent products H d at u (QuasiStaticProblem::hessian_times, the lattice
// sweep of Model::force_change: deformed directions and the geometric term),
// to `inner_tolerance` of |r|; u += w if that cuts |r| by 10 %; repeat until
// |r(u)| <= tolerance x max(|F|, floor). Each round divides the residual by
// about inner_tolerance plus the Newton step's nonlinear error. After bonds
// break the tangent can be nearly singular or indefinite (a particle left on
// a bond or two): CG stops at non-positive curvature, and a round whose
// correction does not cut the residual is replaced by one with the
// small-strain stiffness K0 (positive definite on whatever holds at rest). If
// that fails too (near separation: pieces hanging by a few bonds), damped
// Newton rounds (Levenberg-Marquardt, theory.md Sec. 4.14) do the rest: CG on
// (H + mu B) w = r, B the preconditioner's blocks, with the same
// preconditioner for the damped matrix; a round is taken if it cuts |r| by
// 10 % or lowers the energy by Armijo's condition; mu grows 3-fold when a
// round is dropped or its CG meets negative curvature (or returns to the
// last mu taken), falls 10-fold when a round cuts the residual and 3-fold
// when one is taken on the energy alone. Only if mu passes its largest value does
// NCG on the double residual with central-difference Hessian products (two
// double passes per product) do the rest of the minimisation.
#include <vector>

#include "ncg.hpp"
#include "quasi_static_problem.hpp"

namespace pd::solver {

struct MixedPrecisionResult {
  NcgResult ncg;     // the whole minimisation: CG iterations of all rounds, the last double residual
  long rounds = 0;   // double residuals evaluated (1 + one per correction tried)
  long exact_iterations = 0;  // of the fallback (NCG in double with the exact Hessian), 0 if not needed
  long rejected_rounds = 0;   // corrections that did not cut the residual by 10 % (not applied)
  long negative_curvature_stops = 0;  // corrections whose CG met non-positive curvature or diverged
  long damped_rounds = 0;     // Levenberg-Marquardt rounds (theory.md Sec. 4.14), taken or not
  long stagnated_rounds = 0;  // corrections whose CG stopped on a stalled residual (linear_cg.hpp), tested as they were
  double largest_damping = 0;  // the largest mu of those rounds
};

// The damping of the Levenberg-Marquardt rounds, relative to the blocks B.
struct DampingSettings {
  bool enabled = true;     // false: no damped round (the central-difference NCG right after K0)
  double first = 1e-2;     // mu of the first damped round (the geometric stiffness's order, k e/|y| ~ 1e-2 k)
  double factor = 10;      // mu / factor after a round that cut the residual by 10 %
  double fine_factor = 3;  // mu / fine_factor after one taken on the energy alone; x fine_factor after a dropped one
  double smallest = 1e-6;  // below this mu is 0 (an undamped tangent round), from which a dropped round goes back here
  double largest = 1e4;    // above this: the central-difference NCG (a step of ~1e-4 of the blocks' own)
};

MixedPrecisionResult minimise_in_mixed_precision(QuasiStaticProblem& problem, std::vector<double>& u,
                                                 const NcgSettings& settings, double inner_tolerance = 1e-2,
                                                 const DampingSettings& damping = {});

}  // namespace pd::solver
