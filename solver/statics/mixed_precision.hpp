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
// Method (defect correction with the small-strain stiffness K0, a modified
// Newton iteration): at u, the residual r(u) in double (one double pass);
// then the correction w minimising 1/2 w.K0 w - r.w by the same NCG with the
// float products K0 d (QuasiStaticProblem::hessian_times: forces of tiny
// displacements s d from rest, no rounding of a large u), to `inner_tolerance`
// of |r|; u += w; repeat until |r(u)| <= tolerance x max(|F|, floor). Each
// round divides the residual by about max(inner_tolerance, |H - K0| / |K0|),
// the second being of the order of the largest strain (<= s0, a few percent
// at a crack tip): from any start, 1e-6 takes 3 to 7 rounds. A round that
// does not reduce the residual by 10 % (K0 can miss what holds a state: a
// particle left with bonds in one direction only is held sideways by the
// geometric stiffness alone) hands the rest of the minimisation to NCG on the
// double residual with the exact Hessian product (central differences of the
// double force: two double passes per product), which is as robust as the
// energy table's path.
#include <vector>

#include "ncg.hpp"
#include "quasi_static_problem.hpp"

namespace pd::solver {

struct MixedPrecisionResult {
  NcgResult ncg;     // the whole minimisation: float iterations of all rounds, the last double residual
  long rounds = 0;   // double residuals evaluated (corrections + 1 for the final check)
  long exact_iterations = 0;  // of the fallback (NCG in double with the exact Hessian), 0 if not needed
};

MixedPrecisionResult minimise_in_mixed_precision(QuasiStaticProblem& problem, std::vector<double>& u,
                                                 const NcgSettings& settings, double inner_tolerance = 1e-2);

}  // namespace pd::solver
