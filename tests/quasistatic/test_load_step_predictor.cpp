// The load steps' predictor (load_step_predictor.hpp, theory.md Sec. 4.11).
#include <catch2/catch.hpp>
#include <cmath>

#include "load_step_predictor.hpp"
#include "mixed_precision.hpp"
#include "quasi_static_problem.hpp"
#include "support.hpp"

using namespace pd::solver;
using namespace pd::quasistatic::test;

// Reference: a displacement path u(q) = a + q b, on which the extrapolated
// increment is exact (to double round-off); the scaled guess is exact on
// u(q) = q b only. Prescribed components are left alone.
TEST_CASE("the predictor is exact on a straight path, the scaled guess on a path from rest",
          "[quasistatic]") {
  const std::vector<std::uint8_t> free = {1, 1, 0, 1};
  const std::vector<double> a = {1e-6, -2e-6, 0, 3e-7}, b = {2e-5, 1e-5, 0, -4e-6};
  const auto at = [&](double q, bool from_rest) {
    std::vector<double> u(4);
    for (std::size_t c = 0; c < 4; ++c) u[c] = (from_rest ? 0.0 : a[c]) + q * b[c];
    return u;
  };
  const std::vector<double> done = {1.0, 1.5};
  std::vector<double> increment(4), u = at(1.5, false);
  for (std::size_t c = 0; c < 4; ++c) increment[c] = at(1.5, false)[c] - at(1.0, false)[c];
  u[2] = 7;  // a prescribed component: not the predictor's
  predict_load_step(u, free, increment, done, 1.6);
  const auto expected = at(1.6, false);
  for (std::size_t c : {0, 1, 3}) CHECK(u[c] == Approx(expected[c]).epsilon(1e-14));
  CHECK(u[2] == 7);
  // Without an increment (the last step broke bonds): scaled.
  u = at(1.5, true);
  predict_load_step(u, free, {}, done, 1.6);
  for (std::size_t c : {0, 1, 3}) CHECK(u[c] == Approx(at(1.6, true)[c]).epsilon(1e-14));
}

// Reference: Taylor expansion of the equilibrium path u(q) of the plate
// (geometrically nonlinear: the bonds' deformed directions). The scaled guess
// is off by O(q dq) of its curvature, the extrapolated increment by O(dq^2):
// with steps of dq = 0.01 at q = 4 the latter's residual must be far below the
// former's (measured ~100 times; asserted 10 times).
TEST_CASE("the extrapolated increment starts a small load step closer to equilibrium than scaling",
          "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  const std::size_t n = particles.size();
  auto scene = quasi_static_scene(false);
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem fast(lattice_scene(scene), particles);
  NcgSettings settings;
  settings.tolerance = 1e-9;
  settings.max_iterations = 20000;
  std::vector<double> u(2 * n, 0.0), previous;
  const std::vector<double> factors = {4.0, 4.01};
  for (double q : factors) {
    previous = u;
    fast.set_load_factor(q, u);
    REQUIRE(minimise_in_mixed_precision(fast, u, settings).ncg.converged);
  }
  std::vector<double> increment(2 * n);
  for (std::size_t c = 0; c < 2 * n; ++c) increment[c] = u[c] - previous[c];
  const auto residual_from = [&](const std::vector<double>& last_increment) {
    std::vector<double> guess = u, r;
    predict_load_step(guess, fast.free_mask(), last_increment, factors, 4.02);
    fast.set_load_factor(4.02, guess);
    fast.set_double_residual(true);
    fast.residual(guess, r);
    double sum = 0;
    for (double v : r) sum += v * v;
    return std::sqrt(sum) / fast.reaction_norm();
  };
  const double scaled = residual_from({});
  const double extrapolated = residual_from(increment);
  CHECK(scaled > 1e-6);  // the scaled guess needs iterations at the solver's tolerance
  CHECK(extrapolated < 0.1 * scaled);
}
