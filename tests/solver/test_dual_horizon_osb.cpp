// Dual-horizon ordinary state-based PD (model.type = "osb" with
// model.dual_horizon = true, theory.md Sec. 6.8) on plates whose right half is
// refined (refinement.hpp), each square with the horizon m x its own side.
//
// References: with equal horizons the dual-horizon form is the
// constant-horizon OSB of theory.md Sec. 5.2 (Ren et al. 2017, Sec. 2.3, for
// the state-based form; the algebra of Sec. 6.8); every owned bond acts on
// both ends with opposite forces, so linear momentum is conserved exactly
// (Ren 2017, Eqs. (17)-(18)); a particle farther than one coarse horizon from
// the resolution change sees one horizon only, so under a homogeneous
// deformation its force vanishes by the symmetry of its family and its
// energy density is the classical one (theory.md Sec. 5.1).
//
// Not tested here: the ghost forces of dual-horizon OSB against ordinary OSB
// with a variable horizon, which does not exist (horizon_mode.cpp refuses it).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <tuple>
#include <vector>

#include "osb.hpp"
#include "simulation.hpp"
#include "test_support.hpp"

using namespace pd::solver;

namespace {

constexpr double dx = 1e-4;  // coarse spacing [m]

Scene osb_scene(std::optional<bool> dual_horizon, double nu, bool damage = false) {
  auto s = test::basic_scene();
  s.model = ModelType::osb;
  s.material.poisson_ratio = nu;
  s.dual_horizon = dual_horizon;
  s.effects.damage = damage;
  return s;
}

double largest_magnitude(const std::vector<double>& x, const std::vector<double>& y) {
  double largest = 0;
  for (std::size_t i = 0; i < x.size(); ++i) largest = std::max(largest, std::hypot(x[i], y[i]));
  return largest;
}

}  // namespace

TEST_CASE("dual-horizon OSB with one horizon is the constant-horizon OSB", "[dual_horizon][osb]") {
  // Reference: theory.md Sec. 6.8: on a uniform lattice (A_i V_ij = A_j V_ji,
  // A_i k_ij = A_j k_ji) an own entry i -> j plus the dual entry of j -> i is
  // Sec. 5.2's pair force k_ij e + 4 a Lambda (V_ij/|xi|)(theta_i/m_i +
  // theta_j/m_j); W_i and the stable step (Sec. 5.4) are the same sums.
  // nu = 0.2 (a < 0) and 0.35 (a > 0); a smooth nonlinear field.
  const double nu = GENERATE(0.2, 0.35);
  const double m = 3;
  const auto p = pd::make_rectangle_lattice(16 * dx, 12 * dx, dx, m * dx, pd::Quadrature::analytic);
  const auto field = [](double x, double y) {
    return std::pair{1e-6 * std::sin(x / (3 * dx)) + 2e-4 * y, 1e-6 * std::cos(y / (4 * dx)) * x / dx};
  };
  const auto [fx0, fy0] = test::internal_forces(osb_scene(std::nullopt, nu), p, field);
  const auto [fx1, fy1] = test::internal_forces(osb_scene(true, nu), p, field);
  const double scale = largest_magnitude(fx0, fy0);
  double difference = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    difference = std::max(difference, std::hypot(fx1[i] - fx0[i], fy1[i] - fy0[i]));
  INFO("nu = " << nu << ": largest force density " << scale << " N/m^3, largest difference " << difference);
  CHECK(scale > 0);
  CHECK(difference < 1e-12 * scale);

  // Both on the neighbour lists (double precision): the dual-horizon rows
  // against the constant-horizon lists (the lattice split is compared with
  // the rows in test_dual_horizon_lattice.cpp).
  SetupOptions lists;
  lists.lattice_kernel = false;
  Simulation constant(osb_scene(std::nullopt, nu), p, lists), dual(osb_scene(true, nu), p, lists);
  std::vector<double> ux(p.size()), uy(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) std::tie(ux[i], uy[i]) = field(p.x[i], p.y[i]);
  constant.set_displacements(ux, uy);
  dual.set_displacements(ux, uy);
  const auto w0 = constant.strain_energy_density(), w1 = dual.strain_energy_density();
  double largest_w = 0, w_difference = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    largest_w = std::max(largest_w, std::fabs(w0[i])), w_difference = std::max(w_difference, std::fabs(w1[i] - w0[i]));
  INFO("largest W " << largest_w << " J/m^3, largest difference " << w_difference << "; stable steps "
                    << constant.stable_time_step() << " and " << dual.stable_time_step() << " s");
  CHECK(largest_w > 0);
  CHECK(w_difference < 1e-12 * largest_w);
  CHECK(dual.stable_time_step() == Approx(constant.stable_time_step()).epsilon(1e-12));
}

TEST_CASE("dual-horizon OSB conserves linear momentum to round-off across a resolution change",
          "[dual_horizon][osb]") {
  // Reference: the dual property, Ren et al. 2017, Eqs. (17)-(18): every
  // owned bond's force acts on both ends with opposite signs, its owner's
  // dilatation included (theory.md Sec. 6.8). Random velocities over a plate
  // refined 2x (24 x 12 coarse spacings, m = 3), 300 steps; without damage
  // (2 m/s) and with damage (200 m/s breaks bonds within the 300 steps, own
  // entries in the dilatation pre-pass and their dual copies in the force
  // pass of the same step), under each failure variant (theory.md Sec. 5.8).
  // Variant (c) at nu = 0.35: it keeps a broken bond's dilatation, and with
  // a < 0 (nu = 0.2) its energy a theta^2 falls without bound as particles
  // fly apart at 200 m/s (Sec. 5.8: not convex in the opening), which ends
  // such a run with non-finite values, one horizon or two.
  const auto p = test::half_refined_plate(24 * dx, 12 * dx, dx, 3, 2);
  {
    const auto [change, broken] = test::momentum_change_on_lists(osb_scene(true, 0.2), p, 2.0);
    INFO("no damage: momentum change " << change << " of the magnitude sum");
    CHECK(change < 1e-13);
  }
  for (const auto& variant : osb_failures) {
    auto scene = osb_scene(true, variant.failure == OsbFailure::bond_term_only ? 0.35 : 0.2, true);
    scene.osb_failure = variant.failure;
    const auto [change, broken] = test::momentum_change_on_lists(scene, p, 200.0);
    INFO(variant.name << ": momentum change " << change << " of the magnitude sum; broken bonds " << broken);
    CHECK(broken > 0);  // the random field breaks bonds: they are part of the test
    CHECK(change < 1e-13);
  }
}

TEST_CASE("dual-horizon OSB: homogeneous deformations away from a resolution change give no force and the "
          "classical energy density",
          "[dual_horizon][osb]") {
  // Reference: classical 2D elasticity (theory.md Sec. 5.1): isotropic
  // expansion e: W = 2 kappa e^2; simple shear u_x = g y: W = mu g^2 / 2.
  // A plate of 48 x 32 coarse spacings, its right half refined 2x, m = 6 on
  // both sides (the constant-horizon OSB test's resolution for simple shear:
  // the lattice's angular quadrature is within 0.33 % there, test_osb.cpp).
  // A particle more than one coarse horizon from the interface has an own
  // family and a dual family of one horizon only, and (more than two coarse
  // horizons from the plate's edges) neighbours whose dilatations are equal:
  // its force cancels by symmetry, and W is the constant-horizon OSB's, within
  // 0.5 % of the classical value as in test_osb.cpp. The symmetry holds to
  // the round-off of the bond table, which stores xi in float (bond_table.hpp):
  // two opposite bonds may differ by a float's last bit, 1e-7 of a bond's
  // force; measured up to 4e-10 of the largest force (at the edges), bound 1e-8.
  const double m = 6, width = 48 * dx, height = 32 * dx, coarse_horizon = m * dx;
  const auto p = test::half_refined_plate(width, height, dx, m, 2);
  const double nu = GENERATE(0.2, 0.35);
  const Scene scene = osb_scene(true, nu);
  const double E = scene.material.youngs_modulus;
  const double kappa = E / (2 * (1 - nu)), mu = E / (2 * (1 + nu));  // plane stress
  const double e = 1e-6;
  struct Deformation {
    const char* name;
    std::array<double, 2> (*u)(double, double, double);
    double energy;
  };
  const Deformation deformations[] = {
      {"isotropic expansion", [](double x, double y, double s) { return std::array{s * x, s * y}; },
       2 * kappa * e * e},
      {"simple shear", [](double, double y, double s) { return std::array{s * y, 0.0}; }, 0.5 * mu * e * e},
  };
  // On the rows in double: the bound below is double round-off of the float
  // reference bonds, finer than the lattice sweep's float arithmetic.
  SetupOptions lists;
  lists.lattice_kernel = false;
  for (const auto& d : deformations) {
    Simulation sim(scene, p, lists);
    std::vector<double> ux(p.size()), uy(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto u = d.u(p.x[i], p.y[i], e);
      ux[i] = u[0], uy[i] = u[1];
    }
    sim.set_displacements(ux, uy);
    const auto& k = sim.kinematics();
    const auto w = sim.strain_energy_density();
    const double scale = largest_magnitude(k.fx, k.fy);
    double force = 0, energy_error = 0;
    int coarse = 0, fine = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double edge = std::min({p.x[i], width - p.x[i], p.y[i], height - p.y[i]});
      if (edge < 2 * coarse_horizon || std::fabs(p.x[i] - 0.5 * width) < coarse_horizon) continue;
      (p.x[i] < 0.5 * width ? coarse : fine) += 1;
      force = std::max(force, std::hypot(k.fx[i], k.fy[i]));
      energy_error = std::max(energy_error, std::fabs(w[i] - d.energy) / d.energy);
    }
    INFO("nu = " << nu << ", " << d.name << ": " << coarse << " coarse and " << fine
                 << " fine interior particles, largest force " << force << " of " << scale
                 << " N/m^3, largest energy error " << energy_error);
    CHECK(coarse > 20);
    CHECK(fine > 80);
    CHECK(scale > 0);
    CHECK(force < 1e-8 * scale);
    CHECK(energy_error < 0.005);
  }
}

TEST_CASE("dual-horizon OSB: a free plate across a resolution change conserves its energy", "[dual_horizon][osb]") {
  // Reference: theory.md Sec. 6.8: the dual-horizon OSB force is minus the
  // derivative of sum_i A_i W_i (with Lambda held, which at these strains,
  // 1e-4, is far below the bound), W_i over i's own horizon; velocity-Verlet
  // then keeps the half-step kinetic energy plus the strain energy (Sec.
  // 4.4), as the constant-horizon OSB test of test_osb.cpp checks at 0.1 %.
  // A wrong factor between the forces and W_i (the halved bond term, the
  // owner's dilatation alone, the energy of the own entries) would not
  // conserve it. A plate of 16 x 12 coarse spacings, its right half refined
  // 2x, m = 3, nu = 0.2 (a < 0), smooth initial velocities, 2,000 steps
  // (45 us, some 15 periods of the slowest in-plane modes). Measured: largest
  // deviation 5.8e-7 over 4,000 steps, the strain energy up to 36 % of the total.
  const double width = 16 * dx, height = 12 * dx;
  const auto p = test::half_refined_plate(width, height, dx, 3, 2);
  const Scene scene = osb_scene(true, 0.2);
  Simulation sim(scene, p);
  test::set_smooth_velocities(sim, p, width, height);
  const auto e0 = sim.energies();
  const double total0 = e0.kinetic_half_step + e0.strain;
  double largest_deviation = 0, largest_strain = 0;
  for (int s = 0; s < 2000; ++s) {
    sim.step();
    if (s % 50 == 49) {
      const auto e = sim.energies();
      largest_deviation = std::max(largest_deviation, std::fabs(e.kinetic_half_step + e.strain - total0) / total0);
      largest_strain = std::max(largest_strain, e.strain / total0);
    }
  }
  INFO("largest deviation of the conserved energy " << largest_deviation << ", strain share up to "
                                                    << largest_strain << ", dt " << sim.time_step() << " s");
  CHECK_FALSE(sim.non_finite().found);
  CHECK(largest_strain > 0.1);  // the plate did deform
  CHECK(largest_deviation < 1e-3);
}
