// The damped (Levenberg-Marquardt) rounds of the lattice path's minimiser
// (theory.md Sec. 4.14, solver/statics/mixed_precision.*): a state whose
// tangent is indefinite and whose small-strain stiffness K0 is singular,
// where the undamped rounds are both dropped.
#include <catch2/catch.hpp>
#include <cmath>

#include "mixed_precision.hpp"
#include "ncg.hpp"
#include "quasi_static_problem.hpp"
#include "support.hpp"

using namespace pd::solver;
using namespace pd::quasistatic::test;

namespace {

// The C1 plate (coarse NB-NUG, m = 3) held on its left edge and pushed
// 1e-4 m to the left on its right edge (a compression of some 1e-2), and
// one lattice particle of it, near a quarter of the plate's width and half
// its height, whose bonds have all been cut except those along its own row:
// it is held by its row's bonds alone, which the compression shortens.
struct HeldByItsRow {
  pd::ParticleSet particles = coarse_c1_nbnug();
  Scene scene;
  std::uint32_t particle = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cut;  // every pair of `particle` off its row
  HeldByItsRow() {
    scene = quasi_static_scene(true);
    scene.loads = {fixed("left"), x_displacement("right", -1e-4)};
    const double x = particles.xmin + 0.25 * (particles.xmax - particles.xmin);
    const double y = 0.5 * (particles.ymin + particles.ymax);
    const std::vector<std::uint8_t> on_lattice = QuasiStaticProblem(lattice_scene(scene), particles).lattice_kernel()->lattice_membership();
    double nearest = INFINITY;
    for (std::uint32_t i = 0; i < particles.size(); ++i) {
      if (!on_lattice[i]) continue;
      const double d = std::hypot(particles.x[i] - x, particles.y[i] - y);
      if (d < nearest) nearest = d, particle = i;
    }
    const std::uint32_t p = particle;
    for (auto k = particles.family_offsets[p]; k < particles.family_offsets[p + 1]; ++k) {
      const auto j = particles.neighbors[k];
      if (std::fabs(particles.y[j] - particles.y[p]) > 1e-6 * particles.spacing) cut.emplace_back(p, j);
    }
  }
};

}  // namespace

// Reference: the energy table's minimiser (NCG with the exact Hessian of the
// bond energies in double, ncg.hpp: an implementation independent of the
// lattice kernels and of the rounds under test) on the same bonds, started
// with the particle 0.06 dx off its row, where its compressed row bonds are
// already stretched back (a bond of length L compressed by e is back at L
// about L sqrt(2e) off the line) and hold it: its path stays where the
// energy is convex. The lattice path starts with the particle 2e-3 dx off
// its row: there the compressed bonds push it out (the tangent's sideways
// stiffness -k e/|y| < 0: CG meets negative curvature) and K0 holds it by
// nothing sideways (singular: its CG diverges), so both undamped rounds are
// dropped; the damped rounds must leave the saddle (energy test) and end
// undamped at the same equilibrium, without the central-difference NCG
// (with the damping term taken out of the product, the rounds are dropped
// up to the largest mu and that NCG takes over: the test fails).
// Tolerances: the lattice path's equilibrium matches the table's to 1e-5 of
// the largest displacement (test_lattice_kernels.cpp); the particle's
// sideways position, set by the differences of small bond stretches, to
// 1e-4 of itself.
TEST_CASE("damped rounds move a particle held by compressed bonds to the energy table's equilibrium",
          "[quasistatic][lattice]") {
  const HeldByItsRow setup;
  const std::size_t n = setup.particles.size();
  const std::uint32_t p = setup.particle;
  const double dx = setup.particles.spacing;
  REQUIRE(setup.cut.size() > 6);
  const auto family = setup.particles.family_offsets[p + 1] - setup.particles.family_offsets[p];
  INFO("particle " << p << " at (" << setup.particles.x[p] << ", " << setup.particles.y[p] << "), family " << family
                   << ", pairs cut " << setup.cut.size() << ", spacing " << dx);
  REQUIRE(family - setup.cut.size() >= 2);

  QuasiStaticProblem lists(setup.scene, setup.particles);
  REQUIRE(lists.break_pairs(setup.cut) == setup.cut.size());
  std::vector<double> u_lists(2 * n, 0.0);
  u_lists[n + p] = 0.06 * dx;
  lists.set_load_factor(1.0, u_lists);
  NcgSettings settings;
  settings.tolerance = 1e-9;
  settings.max_iterations = 50000;
  const auto reference = minimise_energy(lists, u_lists, settings);
  INFO("reference: " << reference.iterations << " NCG iterations, relative residual " << reference.relative_residual());
  REQUIRE(reference.converged);
  INFO("reference offset " << u_lists[n + p] / dx << " dx");
  REQUIRE(u_lists[n + p] > 0.02 * dx);  // the particle stands off its row

  QuasiStaticProblem fast(lattice_scene(setup.scene), setup.particles);
  REQUIRE(fast.break_pairs(setup.cut) == setup.cut.size());
  std::vector<double> u_fast(2 * n, 0.0);
  u_fast[n + p] = 2e-3 * dx;
  fast.set_load_factor(1.0, u_fast);
  settings.tolerance = 1e-8;
  settings.max_iterations = 5000;
  const auto result = minimise_in_mixed_precision(fast, u_fast, settings);
  INFO("lattice: " << result.ncg.iterations << " CG iterations, " << result.rounds << " rounds, "
                   << result.rejected_rounds << " dropped, " << result.damped_rounds << " damped (largest mu "
                   << result.largest_damping << "), " << result.exact_iterations
                   << " central-difference NCG iterations; particle at " << u_fast[n + p] / dx << " dx, reference "
                   << u_lists[n + p] / dx << " dx");
  REQUIRE(result.ncg.converged);
  CHECK(result.damped_rounds > 0);
  CHECK(result.exact_iterations == 0);  // no fallback
  CHECK(u_fast[n + p] == Approx(u_lists[n + p]).epsilon(1e-4));
  double largest = 0, off = 0;
  for (std::size_t k = 0; k < 2 * n; ++k)
    if (k != p && k != n + p) {
      largest = std::max(largest, std::fabs(u_lists[k]));
      off = std::max(off, std::fabs(u_fast[k] - u_lists[k]));
    }
  CHECK(off < 1e-5 * largest);
  for (std::size_t l = 0; l < lists.reactions().size(); ++l)
    CHECK(fast.reactions()[l].reaction_x == Approx(lists.reactions()[l].reaction_x).epsilon(1e-5));
}
