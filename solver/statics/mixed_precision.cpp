#include "mixed_precision.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace pd::solver {
namespace {

// The correction's quadratic energy 1/2 w.K0 w - r.w: residual r - K0 w,
// Hessian K0, judged against |r| (inner_tolerance is relative to it).
class Correction final : public EnergyProblem {
public:
  Correction(QuasiStaticProblem& problem, const std::vector<double>& r, double r_norm)
      : problem_(problem), r_(r), r_norm_(r_norm) {}
  std::size_t unknown_count() const override { return r_.size(); }
  void residual(const std::vector<double>& w, std::vector<double>& out) override {
    problem_.hessian_times(w, w, out);
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = r_[k] - out[k];
  }
  void hessian_times(const std::vector<double>& w, const std::vector<double>& d,
                     std::vector<double>& hd) const override {
    problem_.hessian_times(w, d, hd);  // K0: the same at any w
  }
  const std::vector<double>& preconditioner() const override { return problem_.preconditioner(); }
  double reaction_norm() const override { return r_norm_; }

private:
  QuasiStaticProblem& problem_;
  const std::vector<double>& r_;
  double r_norm_;
};

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
  const auto start = std::chrono::steady_clock::now();
  problem.set_double_residual(true);
  std::vector<double> r, w, before;
  NcgResult& total = result.ncg;
  double previous = INFINITY;
  for (;;) {
    problem.residual(u, r);  // double; also the reactions of this state
    ++result.rounds;
    total.residual_norm = norm(r);
    total.reference_norm = std::max(problem.reaction_norm(), settings.force_floor);
    if (total.residual_norm <= settings.tolerance * total.reference_norm) {
      total.converged = true;
      break;
    }
    if (total.iterations >= settings.max_iterations) break;
    if (!(total.residual_norm < 0.9 * previous)) {
      // A round that did not reduce the residual: K0 misses what holds the
      // state, e.g. a particle left with bonds in one direction only, held
      // sideways by the geometric stiffness alone. Back to the better state,
      // then NCG on the double residual with the exact Hessian (central
      // differences of the double force) for the rest of this minimisation.
      if (total.residual_norm > previous) u = before;
      problem.set_exact_hessian(true);
      NcgSettings rest = settings;
      rest.max_iterations = settings.max_iterations - total.iterations;
      const long done = total.iterations;
      if (settings.progress)
        rest.progress = [&, done](const NcgProgress& p) {
          settings.progress({done + p.iteration, p.relative_residual,
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
        };
      const NcgResult exact = minimise_energy(problem, u, rest);
      problem.set_exact_hessian(false);
      total.converged = exact.converged;
      total.residual_norm = exact.residual_norm;
      total.reference_norm = exact.reference_norm;
      total.iterations += exact.iterations;
      result.exact_iterations = exact.iterations;
      break;
    }
    previous = total.residual_norm;
    before = u;
    Correction correction(problem, r, total.residual_norm);
    NcgSettings inner = settings;
    inner.tolerance = std::max(inner_tolerance, settings.tolerance * total.reference_norm / total.residual_norm);
    inner.force_floor = 0;
    inner.max_iterations = settings.max_iterations - total.iterations;
    if (settings.progress) {
      // Progress in the outer terms: iterations so far, and the residual the
      // correction has reached, as a fraction of the reference.
      const double scale = total.residual_norm / total.reference_norm;
      const long done = total.iterations;
      inner.progress = [&, scale, done](const NcgProgress& p) {
        settings.progress({done + p.iteration, p.relative_residual * scale,
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
      };
    }
    w.assign(u.size(), 0.0);
    const NcgResult step = minimise_energy(correction, w, inner);
    total.iterations += step.iterations;
    for (std::size_t k = 0; k < u.size(); ++k) u[k] += w[k];
  }
  problem.set_double_residual(false);
  return result;
}

}  // namespace pd::solver
