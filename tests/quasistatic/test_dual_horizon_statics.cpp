// The linear dual-horizon solution of validation/dual_horizon_statics.hpp
// (theory.md Sec. 6.5), used for C1 on grids whose horizons vary (NB-NUG
// boxes meshed finer than the squares, docs/accuracy-cost.md).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "c1_comparison.hpp"
#include "dual_horizon_statics.hpp"
#include "ncg.hpp"
#include "quasi_static_problem.hpp"
#include "support.hpp"

namespace {

using namespace pd;
using namespace pd::validation;

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }

}  // namespace

TEST_CASE("dual-horizon statics: with one horizon it is the NCG minimum of ordinary PMB", "[quasistatic][dual_horizon]") {
  // Reference: the quasi-static NCG minimisation of solver/statics (the energy
  // bond table, an independent code path) on the same uniform grid; with
  // equal horizons dual-horizon PD is ordinary PMB (theory.md Sec. 6). The
  // NCG minimises the nonlinear PMB energy (extension |y| - |xi|), the linear
  // solution its small-strain form, so the two differ by O(strain): at the
  // C1 edge displacement U = 1e-7 m (strain 1e-5) by 5e-6 U in u_x, 9e-6 U in
  // u_y and 7e-6 of the reaction; at U / 10 ten times less relative to U.
  // (On free cells they differ by design as well: solver/statics symmetrises
  // the unequal stiffnesses k_ij != k_ji of a pair, dual-horizon PD gives each
  // bond its owner's.)
  const auto p = validation::make_plate_grid({PD_C1_GEOMETRY, GridKind::uniform, 4e-4, 1.2e-3, Quadrature::analytic});
  double previous = 0;
  for (double U : {1e-7, 1e-8}) {
    C1Material material;
    material.edge_displacement = U;
    PdOptions ncg;
    ncg.surface_correction = false;
    ncg.tolerance = 1e-11;
    PdOptions dual = ncg;
    dual.dual_horizon = true;
    const auto a = solve_c1_pd(p, material, ncg);
    const auto b = solve_c1_pd(p, material, dual);
    // u_y is fixed only up to a rigid translation (no y constraint): compare about the means.
    const double ma = mean(a.uy), mb = mean(b.uy);
    double dx = 0, dy = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      dx = std::max(dx, std::fabs(a.ux[i] - b.ux[i]));
      dy = std::max(dy, std::fabs((a.uy[i] - ma) - (b.uy[i] - mb)));
    }
    const double reaction = std::fabs(b.reaction_x / a.reaction_x - 1);
    INFO("U = " << U << " m: max |du_x| / U = " << dx / U << ", max |du_y| / U = " << dy / U
                << ", reaction ratio - 1 = " << reaction << "; CG iterations " << b.iterations);
    const double scale = U / 1e-7;  // the strain relative to C1's
    CHECK(dx < 1e-5 * scale * U);
    CHECK(dy < 2e-5 * scale * U);
    CHECK(reaction < 1.5e-5 * scale);
    // The difference is the nonlinearity: it falls with the strain.
    if (previous > 0) CHECK(reaction < 0.2 * previous);
    previous = reaction;
    // The strain energy density at the solution, which pd-validate-c1's
    // rows and hole stresses read (the dual-horizon path once left it empty,
    // and --dual-horizon ended in a segmentation fault): the same total.
    REQUIRE(b.strain_energy_density.size() == p.size());
    double energy_a = 0, energy_b = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      energy_a += a.strain_energy_density[i] * p.volume[i], energy_b += b.strain_energy_density[i] * p.volume[i];
    CHECK(energy_b == Approx(energy_a).epsilon(1e-4));
  }
}

TEST_CASE("dual-horizon statics: boxes at dx / 2 stay in equilibrium as a whole", "[quasistatic][dual_horizon]") {
  // Reference: Newton's third law. The bonds of a dual-horizon table act on
  // both ends with opposite forces, so at equilibrium of the free unknowns
  // the constraint forces on the two strips cancel; with unequal dual entries
  // (k_ij V_i != k_ji V_j) they would not. Also the solution is an
  // equilibrium: the true residual, recomputed after the iterations, meets
  // the tolerance.
  const auto p = validation::make_plate_grid({PD_C1_GEOMETRY, GridKind::nbnug, 4e-4, 1.2e-3, Quadrature::analytic, 2});
  std::size_t fine = 0;
  for (double h : p.horizon) fine += h < 1.2e-3 * (1 - 1e-9);
  REQUIRE(fine > 1000);  // the box cells, at 0.6 mm
  auto scene = quasistatic::test::quasi_static_scene();
  scene.quasi_static.enabled = false;
  scene.dual_horizon = true;
  const double u = 1e-7;
  const auto r = solve_dual_horizon_static(scene, p, {{"left", -u}, {"right", u}}, 1e-10, 20000);
  INFO("iterations " << r.iterations << ", relative residual " << r.relative_residual << ", reactions "
                     << r.reaction_x.at(0) << " and " << r.reaction_x.at(1) << " N/m");
  CHECK(r.converged);
  CHECK(r.relative_residual < 1e-9);
  CHECK(r.reaction_x.at(1) > 0);
  CHECK(std::fabs(r.reaction_x.at(0) + r.reaction_x.at(1)) < 1e-6 * r.reaction_x.at(1));
}

TEST_CASE("dual-horizon statics: refuses scenes it does not solve", "[quasistatic][dual_horizon]") {
  const auto p = quasistatic::test::coarse_c1_nbnug();
  auto scene = quasistatic::test::quasi_static_scene();  // quasi_static on, dual_horizon unset
  CHECK_THROWS_WITH(solve_dual_horizon_static(scene, p, {{"left", 0.0}}, 1e-8, 10),
                    Catch::Contains("needs model.dual_horizon = true"));
  scene.quasi_static.enabled = false;
  scene.dual_horizon = true;
  CHECK_THROWS_WITH(solve_dual_horizon_static(scene, p, {{"middle", 0.0}}, 1e-8, 10),
                    Catch::Contains("no boundary set 'middle'"));
}

TEST_CASE("quasi-static with dual horizons: the minimiser finds the linear dual-horizon equilibrium",
          "[quasistatic][dual_horizon]") {
  // Reference: the linear dual-horizon solution above (an assembled
  // small-strain system from the dynamic solver's dual-horizon rows, solved by
  // CG), an independent path to the same equilibrium. The solver's minimiser
  // uses the energy table of theory.md Sec. 6.6 and keeps the geometric
  // nonlinearity, so the two differ by O(strain), as with one horizon (first
  // test above): at U = 1e-7 m (strain 1e-5) within 1e-5 U in u_x, 2e-5 U in
  // u_y and 1.5e-5 of the reaction. Grid: C1 with its boxes at dx / 2, where
  // the bond of a coarse and a fine particle has two owners' constants.
  const auto p = validation::make_plate_grid({PD_C1_GEOMETRY, GridKind::nbnug, 4e-4, 1.2e-3, Quadrature::analytic, 2});
  const double U = 1e-7;
  auto scene = quasistatic::test::quasi_static_scene();
  scene.dual_horizon = true;
  scene.loads = opposite_edge_displacements(U);
  solver::QuasiStaticProblem problem(scene, p);
  std::vector<double> u;
  problem.set_load_factor(1.0, u);
  solver::NcgSettings settings;
  settings.tolerance = 1e-11;
  settings.max_iterations = 20000;
  const auto minimum = solver::minimise_energy(problem, u, settings);
  REQUIRE(minimum.converged);

  auto linear_scene = scene;
  linear_scene.quasi_static.enabled = false;
  const auto linear = solve_dual_horizon_static(linear_scene, p, {{"left", -U}, {"right", U}}, 1e-11, 20000);
  REQUIRE(linear.converged);

  const std::size_t n = p.size();
  std::vector<double> uy_min(u.begin() + static_cast<std::ptrdiff_t>(n), u.end());
  const double ma = mean(uy_min), mb = mean(linear.uy);
  double dx = 0, dy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    dx = std::max(dx, std::fabs(u[i] - linear.ux[i]));
    dy = std::max(dy, std::fabs((uy_min[i] - ma) - (linear.uy[i] - mb)));
  }
  const double reaction = problem.reactions().at(1).reaction_x / scene.material.thickness;
  const double reaction_error = std::fabs(reaction / linear.reaction_x.at(1) - 1);
  INFO("NCG iterations " << minimum.iterations << ", CG iterations " << linear.iterations << ": max |du_x| / U = "
                         << dx / U << ", max |du_y| / U = " << dy / U << ", reaction ratio - 1 = " << reaction_error);
  CHECK(dx < 1e-5 * U);
  CHECK(dy < 2e-5 * U);
  CHECK(reaction_error < 1.5e-5);
}

TEST_CASE("quasi-static with variable horizons: what it refuses", "[quasistatic][dual_horizon]") {
  // The particle set has two horizons (boxes at dx / 2).
  const auto p = validation::make_plate_grid({PD_C1_GEOMETRY, GridKind::nbnug, 4e-4, 1.2e-3, Quadrature::analytic, 2});
  auto scene = quasistatic::test::quasi_static_scene();
  scene.loads = opposite_edge_displacements(1e-7);
  scene.dual_horizon = false;  // ordinary PD: no energy to minimise
  CHECK_THROWS_WITH(solver::QuasiStaticProblem(scene, p), Catch::Contains("set model.dual_horizon = true"));
  scene.dual_horizon = true;
  scene.effects.damage = true;
  CHECK_THROWS_WITH(solver::QuasiStaticProblem(scene, p), Catch::Contains("needs effects.damage = false"));
  scene.effects.damage = false;
  scene.quasi_static.lattice_kernels = true;
  CHECK_THROWS_WITH(solver::QuasiStaticProblem(scene, p), Catch::Contains("use \"lists\""));
}
