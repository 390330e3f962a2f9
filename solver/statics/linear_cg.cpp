#include "linear_cg.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>

namespace pd::solver {
namespace {

// |r - H w| above this multiple of |r|: the iteration is diverging.
constexpr double divergence_factor = 1e3;

}  // namespace

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  const std::int64_t n = static_cast<std::int64_t>(a.size());
  double sum = 0;
  for (std::int64_t i = 0; i < n; ++i) sum += a[i] * b[i];
  return sum;
}

LinearSolveResult solve_linear(const EnergyProblem& problem, const std::vector<double>& state,
                               const std::vector<double>& r, std::vector<double>& w, const NcgSettings& settings) {
  const std::size_t m = r.size();
  LinearSolveResult result;
  w.assign(m, 0.0);
  std::vector<double> residual = r, s(m), d(m), hd;
  const double target = settings.tolerance * std::sqrt(dot(r, r));
  result.residual_norm = std::sqrt(dot(r, r));
  if (result.residual_norm <= target) {
    result.converged = true;
    return result;
  }
  problem.precondition(residual, s);
  d = s;
  double r_dot_s = dot(residual, s);

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last_report = start;
  const double initial = result.residual_norm;
  double mark = initial;  // the residual when it last halved
  long mark_iteration = 0;
  for (long iteration = 1; iteration <= settings.max_iterations; ++iteration) {
    problem.hessian_times(state, d, hd);
    const double curvature = dot(d, hd);
    if (!(curvature > 0)) {
      result.negative_curvature = true;
      break;
    }
    result.iterations = iteration;
    const double alpha = r_dot_s / curvature;
    for (std::size_t k = 0; k < m; ++k) {
      w[k] += alpha * d[k];
      residual[k] -= alpha * hd[k];
    }
    result.residual_norm = std::sqrt(dot(residual, residual));
    if (result.residual_norm <= target) {
      result.converged = true;
      break;
    }
    if (result.residual_norm > divergence_factor * initial) {
      // Not a direction of negative curvature, but CG on a tangent that is
      // not positive definite away from the directions it tested: the
      // correction is worthless, and the caller goes on without it.
      result.diverged = true;
      w.assign(m, 0.0);
      break;
    }
    if (result.residual_norm <= 0.5 * mark) {
      mark = result.residual_norm;
      mark_iteration = iteration;
    } else if (iteration - mark_iteration >= stagnation_window) {
      result.stagnated = true;
      break;
    }
    if (settings.progress) {
      const auto now = Clock::now();
      if (std::chrono::duration<double>(now - last_report).count() >= settings.progress_interval) {
        last_report = now;
        settings.progress({iteration, result.residual_norm / initial, std::chrono::duration<double>(now - start).count()});
      }
    }
    if (settings.abandon && settings.abandon()) throw MinimisationAbandoned();
    problem.precondition(residual, s);
    const double r_dot_s_new = dot(residual, s);
    const double beta = r_dot_s_new / r_dot_s;
    for (std::size_t k = 0; k < m; ++k) d[k] = s[k] + beta * d[k];
    r_dot_s = r_dot_s_new;
  }
  return result;
}

}  // namespace pd::solver
