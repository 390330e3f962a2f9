// The structured-lattice kernel against the neighbour-list kernel on the same
// runs: the reference is the neighbour-list path (double precision), which
// every other solver test verifies against physics. The lattice kernel
// computes the same bond forces in single precision from displacement
// differences (lattice_kernel.hpp), so the trajectories must agree to float
// round-off: the displacements (up to 0.01 dx here) carry 2^-24 = 6e-8 of
// themselves per operation, so after a few hundred steps positions may differ
// by about 1e-9 dx; the bound 1e-7 dx is a bond-stretch error of 1e-7, far
// below the strains of interest (1e-4 and up) and the breaking stretch. A
// cracking run must break the same bonds.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "lattice.hpp"
#include "simulation.hpp"
#include "test_support.hpp"

using namespace pd::solver;

namespace {

struct Trajectory {
  std::vector<double> ux, uy, damage;  // displacements [m], damage index
  std::size_t broken = 0, lattice_particles = 0;
};

// Opposite halves pulled apart: a smooth field with a strong stretch in the middle.
void pull_apart(Simulation& sim, const pd::ParticleSet& p, double speed) {
  const double centre = 0.5 * (p.xmin + p.xmax), width = p.xmax - p.xmin;
  std::vector<double> vx(p.size()), vy(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    vx[i] = speed * std::tanh(8 * (p.x[i] - centre) / width);
    vy[i] = 0.2 * speed * std::sin(6 * p.y[i] / width);
  }
  sim.set_velocities(vx, vy);
}

Trajectory run(const pd::ParticleSet& p, const Scene& scene, bool lattice_kernel, double speed, int steps) {
  SetupOptions options;
  options.lattice_kernel = lattice_kernel;
  Simulation sim(scene, p, options);
  pull_apart(sim, p, speed);
  for (int s = 0; s < steps; ++s) sim.step();
  return {sim.kinematics().ux, sim.kinematics().uy, sim.damage(), sim.broken_bond_count(), sim.lattice_particle_count()};
}

}  // namespace

TEST_CASE("lattice kernel and neighbour lists give the same elastic trajectory", "[lattice]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(40 * dx, 30 * dx, dx, 4 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.effects.surface_correction = true;
  const auto general = run(p, scene, false, 0.5, 400);
  const auto lattice = run(p, scene, true, 0.5, 400);
  // Interior squares (more than one horizon from every edge) qualify.
  CHECK(lattice.lattice_particles == (40 - 2 * 4) * (30 - 2 * 4));
  double worst = 0, largest_displacement = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    worst = std::max({worst, std::fabs(lattice.ux[i] - general.ux[i]), std::fabs(lattice.uy[i] - general.uy[i])});
    largest_displacement = std::max(largest_displacement, std::hypot(general.ux[i], general.uy[i]));
  }
  INFO("largest displacement difference after 400 steps: " << worst / dx << " dx; largest displacement "
                                                         << largest_displacement / dx << " dx");
  REQUIRE(largest_displacement > 1e-3 * dx);  // the particles really moved
  CHECK(worst < 1e-7 * dx);
}

TEST_CASE("lattice kernel and neighbour lists break the same bonds", "[lattice]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(40 * dx, 30 * dx, dx, 4 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.effects.damage = true;
  const auto general = run(p, scene, false, 40.0, 300);
  const auto lattice = run(p, scene, true, 40.0, 300);
  INFO("broken directed bonds: neighbour lists " << general.broken << ", lattice kernel " << lattice.broken);
  REQUIRE(general.broken > 1000);  // the run really cracks
  CHECK(lattice.broken == general.broken);
  double worst = 0;
  for (std::size_t i = 0; i < p.size(); ++i) worst = std::max(worst, std::fabs(lattice.damage[i] - general.damage[i]));
  CHECK(worst < 1e-6);
}

TEST_CASE("the strain energy an energy row's force sweep sums equals the double-precision pass", "[lattice]") {
  // Reference: the separate pass over the bonds in double precision (the
  // neighbour-list law for the general particles, each lattice pair once in
  // double), which the elastic-energy tests check against classical
  // elasticity. The sweep's sums are float (docs/solver.md, "Single
  // precision"): a pair's energy carries about 1e-7 of itself, a particle's
  // sum of ~50 pairs a few 1e-7, and the float displacements 6e-8 |u| put
  // an extension off by up to 6e-8 |u|: about 1e-6 of the largest W_i here.
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(40 * dx, 30 * dx, dx, 4 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.effects.damage = true;
  scene.effects.surface_correction = true;
  Simulation swept(scene, p), passed(scene, p);
  REQUIRE(swept.lattice_particle_count() > 0);
  pull_apart(swept, p, 40.0);
  pull_apart(passed, p, 40.0);
  for (int s = 0; s < 150; ++s) {
    swept.step(true);  // every step an energy row: the energy must not change the forces
    passed.step();
  }
  REQUIRE(passed.broken_bond_count() > 1000);  // broken pairs must be left out of both
  CHECK(swept.kinematics().ux == passed.kinematics().ux);
  CHECK(swept.broken_bond_count() == passed.broken_bond_count());
  const auto& w_sweep = swept.strain_energy_density();
  const auto& w_pass = passed.strain_energy_density();
  const double largest = *std::max_element(w_pass.begin(), w_pass.end());
  REQUIRE(largest > 0);
  double worst = 0;
  for (std::size_t i = 0; i < p.size(); ++i) worst = std::max(worst, std::fabs(w_sweep[i] - w_pass[i]));
  INFO("largest difference " << worst / largest << " of the largest W_i");
  CHECK(worst < 1e-5 * largest);
  CHECK(swept.energies().strain == Approx(passed.energies().strain).epsilon(1e-6));
}
