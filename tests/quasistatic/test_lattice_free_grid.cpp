// The quasi-static solver's fast path (quasi_static.kernels = "lattice") on a
// plate meshed as a free mesh (pd-mesh --grid free): no particle is a square
// of a lattice, so the lattice kernel has no sweep and its general
// particles' lists (energy-symmetric, double) carry every bond. Reference:
// the energy table's path ("lists", energy_bonds.hpp and the neighbour-list
// kernel), an independent implementation of the same energy.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "load_steps.hpp"
#include "plate_grid.hpp"
#include "quasi_static_problem.hpp"
#include "support.hpp"

using namespace pd::solver;
using namespace pd::quasistatic::test;

namespace {

// The C1 plate (20 mm x 20 mm, hole of radius 4 mm) as a free mesh at
// dx = 0.5 mm, m = 3: about 1,300 gmsh triangles.
pd::ParticleSet coarse_c1_free() {
  return pd::validation::make_plate_grid(
      {PD_C1_GEOMETRY, pd::GridKind::free, 5e-4, 1.5e-3, pd::Quadrature::analytic});
}

}  // namespace

// Both paths sum the same double bonds (the kernel's table is the energy
// table's rows, made energy-symmetric the same way), in other orders: the
// residuals, energies and exact Hessian products agree to double round-off
// (1e-12 relative; 1e-10 leaves room for the sums' order).
TEST_CASE("lattice kernels on a free mesh: residual, energy and tangent are the energy table's",
          "[quasistatic][lattice][free]") {
  const auto particles = coarse_c1_free();
  auto scene = quasi_static_scene(true);
  scene.effects.surface_correction = GENERATE(false, true);
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem lists(scene, particles);
  QuasiStaticProblem fast(lattice_scene(scene), particles);
  REQUIRE(fast.lattice_kernels());
  REQUIRE(fast.lattice_kernel()->particle_count() == 0);  // no lattice: the lists alone
  REQUIRE(lists.stiffness_asymmetry() > 1e-3);            // free cells: the table must be symmetrised
  std::vector<double> u = test_field(particles);
  const ResidualsOfBothPaths r = residuals_of_both_paths(lists, fast, u);
  REQUIRE(r.scale > 0);
  INFO("residual " << difference(r.fast, r.lists) / r.scale << ", double pass "
                   << difference(r.fast_double, r.lists) / r.scale);
  CHECK(difference(r.fast, r.lists) < 1e-10 * r.scale);
  CHECK(difference(r.fast_double, r.lists) < 1e-10 * r.scale);
  CHECK(fast.reaction_norm() == Approx(lists.reaction_norm()).epsilon(1e-10));
  CHECK(fast.strain_energy(u) == Approx(lists.strain_energy(u)).epsilon(1e-10));
  // The tangent product (deformed directions and the geometric term) is the
  // exact Hessian of the same energy, as the table's product.
  std::vector<double> d(u.size()), h_lists, h_fast;
  for (std::size_t k = 0; k < d.size(); ++k) d[k] = lists.free_mask()[k] ? 1e-6 * std::cos(0.37 * k) : 0.0;
  fast.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::tangent);
  lists.hessian_times(u, d, h_lists);
  fast.hessian_times(u, d, h_fast);
  INFO("Hessian product " << difference(h_fast, h_lists) / norm(h_lists));
  CHECK(difference(h_fast, h_lists) < 1e-9 * norm(h_lists));
  // The preconditioner's blocks hold every particle's bonds (none is left
  // without stiffness on an intact plate).
  for (std::size_t i = 0; i < particles.size(); ++i) {
    INFO("particle " << i);
    REQUIRE(fast.preconditioner()[i] > 0);
    REQUIRE(fast.preconditioner()[particles.size() + i] > 0);
  }
}

// C2 in miniature: the free-mesh plate pulled apart in load steps with
// damage (it separates in the 5th step, at u = 0.031 mm per edge: some 850
// pairs break over 40-odd re-equilibrations). The lattice path minimises in mixed precision to 1e-7 (the same
// tolerance as the table's NCG) and breaks bonds in double from its lists,
// the table in double from its own: the same steps break the same number of
// bonds, and the reactions agree to 1e-4 of the peak (both solve to 1e-7 of
// the residual; a reaction is a sum of the residual's forces).
TEST_CASE("lattice kernels on a free mesh break the same bonds as the energy table",
          "[quasistatic][lattice][free][damage]") {
  const auto particles = coarse_c1_free();
  auto scene = quasi_static_scene(true);
  scene.effects.surface_correction = true;
  scene.loads = pd::validation::opposite_edge_displacements(1.0);  // load factor = u per edge [m]
  scene.quasi_static.load_factors = {1e-5, 2e-5, 3e-5};
  for (int k = 1; k <= 30; ++k) scene.quasi_static.load_factors.push_back(3e-5 + k * 1e-6);
  scene.quasi_static.tolerance = 1e-7;
  scene.quasi_static.max_iterations = 20000;
  scene.quasi_static.stop_reaction_fraction = 0.05;
  std::ostringstream log;
  QuasiStaticProblem lists(scene, particles);
  const auto a = solve_quasi_static(lists, scene, {}, log);
  const Scene fast_scene = lattice_scene(scene);
  QuasiStaticProblem fast(fast_scene, particles);
  REQUIRE(fast.lattice_kernel()->particle_count() == 0);
  const auto b = solve_quasi_static(fast, fast_scene, {}, log);
  INFO(log.str());
  REQUIRE(a.steps.size() == b.steps.size());
  CHECK(b.stop_reason == a.stop_reason);
  CHECK_THAT(a.stop_reason, Catch::StartsWith("separated"));
  double peak = 0;
  for (const auto& step : a.steps) peak = std::max(peak, std::fabs(axial_reaction(step, lists.loads())));
  std::size_t broke = 0;
  for (std::size_t s = 0; s < a.steps.size(); ++s) {
    INFO("step " << a.steps[s].step);
    CHECK(b.steps[s].broken_bonds == a.steps[s].broken_bonds);
    broke += a.steps[s].pairs_broken;
    const double ra = axial_reaction(a.steps[s], lists.loads()), rb = axial_reaction(b.steps[s], fast.loads());
    CHECK(rb == Approx(ra).margin(1e-4 * peak));
  }
  CHECK(broke > 10);
  REQUIRE(a.damage.size() == b.damage.size());
  for (std::size_t i = 0; i < a.damage.size(); ++i) CHECK(b.damage[i] == Approx(a.damage[i]).margin(1e-9));
}
