#include "mixed_precision.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "linear_cg.hpp"

namespace pd::solver {
namespace {

double norm(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;  // fixed order: independent of the thread count
  return std::sqrt(s);
}

}  // namespace

MixedPrecisionResult minimise_in_mixed_precision(QuasiStaticProblem& problem, std::vector<double>& u,
                                                 const NcgSettings& settings, double inner_tolerance) {
  MixedPrecisionResult result;
  if (!problem.lattice_kernels()) {
    result.ncg = minimise_energy(problem, u, settings);
    return result;
  }
  using Hessian = QuasiStaticProblem::LatticeHessian;
  const Hessian chosen = problem.lattice_hessian();  // the rounds' matrix (tangent unless a caller chose K0)
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  problem.set_double_residual(true);
  std::vector<double> r, trial, r_trial, w;
  NcgResult& total = result.ncg;
  problem.residual(u, r);  // double; also the reactions of this state
  ++result.rounds;
  bool reactions_of_u = true;  // false after a rejected trial state's residual
  bool small_strain_round = chosen == Hessian::small_strain;
  for (;;) {
    total.residual_norm = norm(r);
    total.reference_norm = std::max(problem.reaction_norm(), settings.force_floor);
    if (total.residual_norm <= settings.tolerance * total.reference_norm) {
      total.converged = true;
      break;
    }
    if (total.iterations >= settings.max_iterations) break;
    // The correction w with H w = r, H the tangent at u (or K0), by linear CG
    // to inner_tolerance of |r| (no further than the outer tolerance needs).
    problem.set_lattice_hessian(small_strain_round ? Hessian::small_strain : Hessian::tangent);
    NcgSettings inner = settings;
    inner.tolerance = std::max(inner_tolerance, settings.tolerance * total.reference_norm / total.residual_norm);
    inner.max_iterations = settings.max_iterations - total.iterations;
    if (settings.progress) {
      // Progress in the outer terms: iterations so far, and the residual the
      // correction has reached, as a fraction of the reference.
      const double scale = total.residual_norm / total.reference_norm;
      const long done = total.iterations;
      inner.progress = [&, scale, done](const NcgProgress& p) {
        settings.progress({done + p.iteration, p.relative_residual * scale, seconds()});
      };
    }
    const LinearSolveResult step = solve_linear(problem, u, r, w, inner);
    total.iterations += step.iterations;
    if (step.negative_curvature || step.diverged) ++result.negative_curvature_stops;
    trial = u;
    for (std::size_t k = 0; k < u.size(); ++k) trial[k] += w[k];
    problem.residual(trial, r_trial);
    ++result.rounds;
    if (norm(r_trial) < 0.9 * total.residual_norm) {  // accepted: a round must cut the residual by 10 %
      u.swap(trial);
      r.swap(r_trial);
      reactions_of_u = true;
      small_strain_round = chosen == Hessian::small_strain;
      continue;
    }
    reactions_of_u = false;
    ++result.rejected_rounds;
    if (!small_strain_round) {
      // The tangent's correction overshot (a nearly singular or indefinite
      // tangent after bonds broke): one round with K0, which is positive
      // definite wherever the bonds hold the state at rest.
      small_strain_round = true;
      continue;
    }
    // K0 misses what holds the state too (e.g. a particle left with bonds in
    // one direction only, held sideways by the geometric stiffness alone):
    // NCG on the double residual with central-difference Hessian products for
    // the rest of this minimisation, as robust as the energy table's path.
    problem.set_lattice_hessian(Hessian::central_difference);
    NcgSettings rest = settings;
    rest.max_iterations = settings.max_iterations - total.iterations;
    const long done = total.iterations;
    if (settings.progress)
      rest.progress = [&, done](const NcgProgress& p) {
        settings.progress({done + p.iteration, p.relative_residual, seconds()});
      };
    const NcgResult exact = minimise_energy(problem, u, rest);
    total.converged = exact.converged;
    total.residual_norm = exact.residual_norm;
    total.reference_norm = exact.reference_norm;
    total.iterations += exact.iterations;
    result.exact_iterations = exact.iterations;
    reactions_of_u = true;  // minimise_energy's last residual is at its final u
    break;
  }
  if (!reactions_of_u) problem.residual(u, r);  // the reactions of the state kept
  problem.set_lattice_hessian(chosen);
  problem.set_double_residual(false);
  return result;
}

}  // namespace pd::solver
