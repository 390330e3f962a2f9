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
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "compact_families.hpp"
#include "lattice.hpp"
#include "simulation.hpp"
#include "test_support.hpp"

using namespace pd::solver;

namespace {

struct Trajectory {
  std::vector<double> ux, uy, damage;  // displacements [m], damage index
  std::size_t broken = 0, lattice_particles = 0, moved_off = 0;
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
  return {sim.kinematics().ux,         sim.kinematics().uy,          sim.damage(),
          sim.broken_bond_count(),     sim.lattice_particle_count(), sim.moved_off_lattice_count()};
}

// The largest difference of the displacements of two runs, and the largest displacement of the first [m].
std::pair<double, double> largest_difference(const Trajectory& reference, const Trajectory& other) {
  double worst = 0, largest = 0;
  for (std::size_t i = 0; i < reference.ux.size(); ++i) {
    worst = std::max({worst, std::fabs(other.ux[i] - reference.ux[i]), std::fabs(other.uy[i] - reference.uy[i])});
    largest = std::max(largest, std::hypot(reference.ux[i], reference.uy[i]));
  }
  return {worst, largest};
}

// pd-mesh's NB-NUG grid of the C1 plate (20 mm, hole radius 4 mm) at
// dx = 0.25 mm and horizon factor m, and the scene it runs with: the
// surface correction needs more bond directions than the stencil of
// m = 1.5 has (8 at 45 degrees), so it is on from m = 2.5 only.
struct HalfIntegerCase {
  pd::ParticleSet particles;
  Scene scene;
};
HalfIntegerCase c1_plate_at(const std::string& factor) {
  const auto folder = test::fresh_folder("c1-m" + factor);
  auto p = pd::read_particle_file(test::pd_mesh(folder, "c1_plate_hole.geo", "--spacing 0.25mm --horizon-factor " + factor));
  auto scene = test::basic_scene();
  scene.effects.surface_correction = factor != "1.5";
  return {std::move(p), scene};
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

// NB-NUG grids at half-integer horizon factors hold one-way bonds: a free
// cell whose centroid lies a little inside its box holds the square beyond
// the box edge, whose horizon only touches the cell. Those squares leave the
// lattice for the neighbour lists (lattice_kernel.hpp), which compute each
// direction of a bond on its own; the trajectory must then be the neighbour
// lists' to float round-off (bound as above), and few squares may leave.
TEST_CASE("squares with one-way bonds leave the lattice, the trajectory stays the neighbour lists'", "[lattice]") {
  const std::string factor = GENERATE(as<std::string>{}, "1.5", "2.5");
  const auto [p, scene] = c1_plate_at(factor);
  const double dx = p.spacing;
  const auto general = run(p, scene, false, 0.5, 300);
  const auto lattice = run(p, scene, true, 0.5, 300);
  const std::size_t squares = pd::compact_families(p).stencil_particle_count(0);
  INFO("m = " << factor << ": " << p.size() << " particles, " << squares << " with the stencil family, "
              << lattice.lattice_particles << " on the lattice, " << lattice.moved_off << " taken off it");
  CHECK(lattice.moved_off > 0);  // the grid has one-way bonds into squares
  CHECK(lattice.lattice_particles + lattice.moved_off == squares);
  // Squares along the edges of the free-mesh boxes only: 77 of 4640 (m = 1.5)
  // and of 4012 (m = 2.5) here; 0.5 % to 0.7 % at dx = 0.1 mm, as the edges'
  // share of the plate falls with dx.
  CHECK(lattice.moved_off < squares / 25);
  const auto [worst, largest_displacement] = largest_difference(general, lattice);
  INFO("largest displacement difference after 300 steps: " << worst / dx << " dx; largest displacement "
                                                            << largest_displacement / dx << " dx");
  REQUIRE(largest_displacement > 1e-3 * dx);
  CHECK(worst < 1e-7 * dx);
}

// A free plate on the half-integer grid, 1000 steps. The model itself
// conserves neither momentum nor energy exactly on NB-NUG grids (theory.md
// Sec. 1.6): the pair's force on j comes from j's own bond with k_ji, and
// A_i k_ij != A_j k_ji between free cells, or k_ji = 0 for a one-way bond,
// whose force does work its energy does not store. The lattice path must add
// nothing to that: its change of momentum is the neighbour lists' to the
// float bound of the lattice sweep (1e-6 of the momentum's magnitude,
// test_dynamics.cpp), its energy the same to 1e-5. The model's own drift
// (measured on this plate, as a fraction of the momentum's magnitude and of
// the energy): m = 1.5: 4.2e-3 and 2.5 %, m = 2.5: 1.0e-3 and 0.4 %, against
// 2.5e-3 and 0.6 % at m = 2 and 2.3e-4 and 0.2 % at m = 3: the one-way bonds
// add to the energy error (most at m = 1.5, where a square has 8 bonds) and
// nothing of another order to the momentum's. The bounds: 1e-2 of the
// momentum, 1 % of the energy (5 % at m = 1.5).
TEST_CASE("a free plate with one-way bonds: the lattice path keeps the model's momentum and energy", "[lattice]") {
  const std::string factor = GENERATE(as<std::string>{}, "1.5", "2.5");
  const auto [p, scene] = c1_plate_at(factor);
  const double width = p.xmax - p.xmin, height = p.ymax - p.ymin;
  std::array<std::array<double, 3>, 2> change{};
  std::array<double, 2> energy_deviation{};
  for (const bool lattice_kernel : {false, true}) {
    SetupOptions options;
    options.lattice_kernel = lattice_kernel;
    Simulation sim(scene, p, options);
    test::set_smooth_velocities(sim, p, width, height);
    const auto p0 = test::momentum_of(sim, p, scene.material.density);
    const auto e0 = sim.energies();
    const double total0 = e0.kinetic_half_step + e0.strain;
    double deviation = 0;
    for (int s = 0; s < 1000; ++s) {
      sim.step();
      if (s % 50 == 49) {
        const auto e = sim.energies();
        deviation = std::max(deviation, std::fabs(e.kinetic_half_step + e.strain - total0) / total0);
      }
    }
    const auto p1 = test::momentum_of(sim, p, scene.material.density);
    change[lattice_kernel] = {p1[0] - p0[0], p1[1] - p0[1], p0[2]};
    energy_deviation[lattice_kernel] = deviation;
  }
  const double magnitude = change[0][2];
  INFO("m = " << factor << ": change of momentum, neighbour lists (" << change[0][0] << ", " << change[0][1]
              << "), lattice path (" << change[1][0] << ", " << change[1][1] << "), magnitude " << magnitude
              << " kg/s; largest deviation of the conserved energy " << energy_deviation[0] << " (lists), "
              << energy_deviation[1] << " (lattice)");
  CHECK(std::fabs(change[1][0] - change[0][0]) < 1e-6 * magnitude);
  CHECK(std::fabs(change[1][1] - change[0][1]) < 1e-6 * magnitude);
  CHECK(std::hypot(change[0][0], change[0][1]) < 1e-2 * magnitude);
  CHECK(std::fabs(energy_deviation[1] - energy_deviation[0]) < 1e-5);
  CHECK(energy_deviation[0] < (factor == "1.5" ? 5e-2 : 1e-2));
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
