#include "ncg.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

namespace pd::solver {
namespace {

double local_dot(const std::vector<double>& a, const std::vector<double>& b) {
  const std::int64_t n = static_cast<std::int64_t>(a.size());
  double sum = 0;
  // Fixed-order serial sum: results must not depend on the thread count.
  for (std::int64_t i = 0; i < n; ++i) sum += a[i] * b[i];
  return sum;
}

}  // namespace

NcgResult minimise_energy(EnergyProblem& problem, std::vector<double>& u, const NcgSettings& settings,
                          const Communicator& communicator) {
  const auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    return communicator.sum(local_dot(a, b));
  };
  const std::size_t m = problem.unknown_count();
  std::vector<double> r, s(m), d(m), hd;
  NcgResult result;

  const auto measure = [&] {
    problem.residual(u, r);
    result.residual_norm = std::sqrt(dot(r, r));
    result.reference_norm = std::max(problem.reaction_norm(), settings.force_floor);
    // (A non-finite norm, from forces beyond double's range, never converges.)
    return std::isfinite(result.residual_norm) && std::isfinite(result.reference_norm) &&
           result.residual_norm <= settings.tolerance * result.reference_norm;
  };
  const auto precondition = [&] {
    problem.precondition(r, s);
  };

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last_report = start;
  const auto report = [&](long iteration) {
    if (!settings.progress) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_report).count() < settings.progress_interval) return;
    last_report = now;
    settings.progress({iteration, result.relative_residual(), std::chrono::duration<double>(now - start).count()});
  };

  if (measure()) {
    result.converged = true;
    return result;
  }
  // The least relative residual so far and where (NcgSettings::stall_iterations).
  result.least_relative_residual = result.relative_residual();
  long least_at = 0;
  const auto stalled = [&](long iteration) {
    const double now = result.relative_residual();
    if (now < result.least_relative_residual || std::isnan(result.least_relative_residual)) {
      result.least_relative_residual = now;
      least_at = iteration;
      return false;
    }
    result.stalled_iterations = iteration - least_at;
    return settings.stall_iterations > 0 && result.stalled_iterations >= std::max(settings.stall_iterations, least_at);
  };
  precondition();
  d = s;
  double r_dot_s = dot(r, s);
  for (long iteration = 1; iteration <= settings.max_iterations; ++iteration) {
    result.iterations = iteration;
    problem.hessian_times(u, d, hd);
    const double curvature = dot(d, hd);
    double slope = dot(r, d);  // minus the energy's derivative along d
    if (!(curvature > 0) || !(slope > 0)) {
      // Not a descent direction of positive curvature: restart along the preconditioned gradient.
      d = s;
      problem.hessian_times(u, d, hd);
      slope = dot(r, d);
      const double c = dot(d, hd);
      if (!(c > 0) || !(slope > 0)) {  // nothing left to descend: leave unconverged
        result.no_descent = true;
        break;
      }
      const double alpha = slope / c;
      for (std::size_t k = 0; k < m; ++k) u[k] += alpha * d[k];
    } else {
      const double alpha = slope / curvature;
      for (std::size_t k = 0; k < m; ++k) u[k] += alpha * d[k];
    }
    if (measure()) {
      result.converged = true;
      return result;
    }
    if (stalled(iteration)) {
      result.stalled = true;
      break;
    }
    report(iteration);
    if (settings.abandon && settings.abandon()) throw MinimisationAbandoned();
    // The Polak-Ribiere numerator r_new . (s_new - s_old): r_new . s_old
    // before s is overwritten (no copy of s: memory and time).
    const double r_dot_s_old = dot(r, s);
    precondition();
    const double r_dot_s_new = dot(r, s);
    double beta = (r_dot_s_new - r_dot_s_old) / r_dot_s;
    if (!(beta > 0) || (settings.restart_interval > 0 && iteration % settings.restart_interval == 0)) beta = 0;
    for (std::size_t k = 0; k < m; ++k) d[k] = s[k] + beta * d[k];
    r_dot_s = r_dot_s_new;
  }
  return result;
}

}  // namespace pd::solver
