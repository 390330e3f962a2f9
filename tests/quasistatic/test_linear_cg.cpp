// Linear CG's stop on a stalled residual (solver/statics/linear_cg.hpp).
// Reference: a positive semi-definite diagonal system whose right-hand side
// has a part in the null space. CG cannot reduce that part (H d has none),
// so |r - H w| stays at least |r_null| and never halves; CG still lowers the
// quadratic model at every iteration (Nocedal & Wright 2006, Theorem 5.2).
// Without the stop such a round runs on to the iteration limit (or until the
// products of its growing null-space part blow the residual up).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "linear_cg.hpp"

namespace {

using pd::solver::EnergyProblem;

class SemiDefiniteDiagonal final : public EnergyProblem {
public:
  explicit SemiDefiniteDiagonal(std::vector<double> lambda) : lambda_(std::move(lambda)), ones_(lambda_.size(), 1.0) {}
  std::size_t unknown_count() const override { return lambda_.size(); }
  void residual(const std::vector<double>&, std::vector<double>& r) override { r.assign(lambda_.size(), 0.0); }
  void hessian_times(const std::vector<double>&, const std::vector<double>& d, std::vector<double>& hd) const override {
    hd.resize(d.size());
    for (std::size_t k = 0; k < d.size(); ++k) hd[k] = lambda_[k] * d[k];
  }
  const std::vector<double>& preconditioner() const override { return ones_; }
  double reaction_norm() const override { return 1.0; }

private:
  std::vector<double> lambda_, ones_;
};

// CG from w = 0 on diag(lambda) w = r to `tolerance`, allowed 20 windows.
pd::solver::LinearSolveResult solve_diagonal(const std::vector<double>& lambda, const std::vector<double>& r,
                                             double tolerance, std::vector<double>& w) {
  const SemiDefiniteDiagonal problem(lambda);
  pd::solver::NcgSettings settings;
  settings.tolerance = tolerance;
  settings.max_iterations = 20 * pd::solver::stagnation_window;
  return pd::solver::solve_linear(problem, std::vector<double>(lambda.size(), 0.0), r, w, settings);
}

}  // namespace

TEST_CASE("linear CG stops on a stalled residual and keeps its correction", "[statics][cg]") {
  // The range: 2000 eigenvalues from 1e-8 to 1 (geometric), so that CG needs
  // far more than the window to solve it; the null part keeps |r - H w| from
  // ever halving.
  const std::size_t n = 2000;
  std::vector<double> lambda(n), r(n, 1.0), w;
  lambda[0] = 0.0;
  for (std::size_t k = 1; k < n; ++k) lambda[k] = std::pow(1e-8, static_cast<double>(k - 1) / static_cast<double>(n - 2));
  r[0] = 10.0 * std::sqrt(static_cast<double>(n));  // |r_null| = 0.995 |r|
  const auto result = solve_diagonal(lambda, r, 1e-6, w);
  CHECK(result.stagnated);
  CHECK_FALSE(result.converged);
  CHECK_FALSE(result.diverged);
  CHECK(result.iterations == pd::solver::stagnation_window);
  // The correction kept is a descent step of the quadratic model
  // -r.w + 1/2 w.H w (CG lowers it at every iteration on a positive
  // semi-definite H): the caller's trial decides whether it is taken.
  double model = 0;
  for (std::size_t k = 0; k < n; ++k) model += -r[k] * w[k] + 0.5 * lambda[k] * w[k] * w[k];
  CHECK(model < 0);
}

TEST_CASE("linear CG on a positive definite system does not stop as stalled", "[statics][cg]") {
  // Condition number 1e4: CG halves the residual every few tens of iterations
  // (at most about sqrt(kappa) / 2 per factor e; Saad 2003, Sec. 6.11.3).
  const std::size_t n = 2000;
  std::vector<double> lambda(n), r(n, 1.0), w;
  for (std::size_t k = 0; k < n; ++k) lambda[k] = std::pow(1e4, static_cast<double>(k) / static_cast<double>(n - 1)) * 1e-4;
  const auto result = solve_diagonal(lambda, r, 1e-10, w);
  CHECK(result.converged);
  CHECK_FALSE(result.stagnated);
  double worst = 0;
  for (std::size_t k = 0; k < n; ++k) worst = std::max(worst, std::abs(w[k] * lambda[k] - 1.0));
  CHECK(worst < 1e-6);
}
