// Dual-horizon runs with the lattice sweep (theory.md Secs. 6.7, 6.8): the
// squares whose whole family is squares at the stencil's horizon go through
// the sweep, the other particles keep dual-horizon rows for their bonds among
// themselves. PMB, and OSB, whose dilatation of a general particle is its
// rows' own entries plus its pairs of the sweep. The reference is the same
// run with every bond on the dual-horizon neighbour lists
// (SetupOptions::lattice_kernel off, double precision), which
// test_dual_horizon.cpp and test_dual_horizon_osb.cpp check against the
// physics (Ren et al. 2017). The sweep computes its pairs in single precision
// (lattice_kernel.hpp), so the two must agree to float round-off, break the
// same bonds, and a restarted run must equal the uninterrupted one bit for bit.
#include <catch2/catch.hpp>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "compact_families.hpp"
#include "effects.hpp"
#include "force_field.hpp"
#include "ghost_exchange.hpp"
#include "lattice_kernel.hpp"
#include "lattice_sweep.hpp"
#include "local_bonds.hpp"
#include "osb.hpp"
#include "particle_state.hpp"
#include "peak_memory.hpp"
#include "pmb.hpp"
#include "refinement.hpp"
#include "results_format.hpp"
#include "run.hpp"
#include "simulation.hpp"
#include "test_support.hpp"
#include "variable_horizon_bonds.hpp"
#include "../test_commands.hpp"

using namespace pd::solver;

namespace {

// pd-mesh's NB-NUG grid of the C1 plate (20 mm, hole radius 4 mm) at
// dx = 0.4 mm, m = 3, its box round the hole meshed at dx / 4: horizons
// 0.3 mm in the box, 1.2 mm outside (docs/mesher.md, "Finer boxes"). 7,545
// particles; written once per process.
const pd::ParticleSet& box_plate() {
  static const pd::ParticleSet p = pd::read_particle_file(test::pd_mesh(
      test::fresh_folder("dual_horizon_lattice_box"), "c1_plate_hole.geo",
      "--spacing 0.4mm --horizon-factor 3 --box-spacing 0.1mm"));
  return p;
}

// A plate of 40 x 20 squares of 0.1 mm, m = 3, its right half refined 4x
// (refinement.hpp), the refined squares' horizon abrupt (m x their side) or
// smoothed over `smoothing_length` [m] up to m dx at the region's edge
// (theory.md Sec. 7): then some fine squares near the edge have horizons
// close to the coarse one.
pd::ParticleSet refined_plate(double smoothing_length) {
  const double dx = 1e-4, width = 40 * dx, height = 20 * dx;
  pd::RefinementRegion r;
  r.x0 = 0.5 * width, r.y0 = 0, r.x1 = width, r.y1 = height, r.factor = 4;
  return pd::make_refined_rectangle_lattice(width, height, dx, 3 * dx, r, pd::Quadrature::analytic, smoothing_length);
}

// The model of a test run: PMB, or OSB under one of its failure variants
// (theory.md Sec. 5.8; nu = 0.35 of basic_scene, a > 0).
struct ModelCase {
  ModelType model = ModelType::pmb;
  OsbFailure failure = OsbFailure::force_and_dilatation;
};
std::string name_of(const ModelCase& c) {
  return c.model == ModelType::pmb ? "pmb" : std::string("osb, ") + to_string(c.failure);
}
// (Named: GENERATE keeps references to its arguments.)
const ModelCase pmb_case{ModelType::pmb}, osb_case{ModelType::osb};
const ModelCase osb_force_only_case{ModelType::osb, OsbFailure::force_only};
const ModelCase osb_bond_term_only_case{ModelType::osb, OsbFailure::bond_term_only};

Scene dual_horizon_scene(bool damage, const ModelCase& model = pmb_case) {
  auto s = test::basic_scene();
  s.dual_horizon = true;
  s.effects.damage = damage;
  s.model = model.model;
  s.osb_failure = model.failure;
  return s;
}

std::unique_ptr<ForceField> force_field(const Scene& scene, const pd::ParticleSet& p, bool lattice_kernel) {
  const auto setup = build_bond_setup(scene, p, pd::compact_families(p), {});
  return make_force_field(scene, p, setup, lattice_kernel);
}

SetupOptions kernel_options(bool lattice_kernel) {
  SetupOptions o;
  o.lattice_kernel = lattice_kernel;
  return o;
}

}  // namespace

TEST_CASE("dual horizon with the lattice sweep: forces equal the neighbour lists' at a deformed state",
          "[dual_horizon][lattice]") {
  // The C1 plate with its box at dx / 4, and a plate with a refined half,
  // its horizons abrupt or smoothed over 5 coarse spacings.
  // PMB on all three; OSB (no smoothing for OSB, theory.md Sec. 7) on the
  // box plate and the abrupt refined half.
  const int plate = GENERATE(0, 1, 2);
  const ModelCase model = GENERATE(pmb_case, osb_case);
  if (model.model == ModelType::osb && plate == 2) return;
  const pd::ParticleSet p = plate == 0 ? box_plate() : refined_plate(plate == 1 ? 0.0 : 5e-4);
  const Scene scene = dual_horizon_scene(false, model);
  const auto lists = force_field(scene, p, false);
  const auto lattice = force_field(scene, p, true);
  const std::size_t squares = pd::compact_families(p).stencil_particle_count(0);
  INFO(name_of(model) << ", plate " << plate << ": " << p.size() << " particles, " << squares << " with the stencil family, " << lattice->lattice_particle_count()
                << " on the lattice, " << lattice->moved_off_lattice_count() << " taken off it");
  // The squares with the stencil family are on the lattice, less those the
  // one-way check takes off (theory.md Sec. 6.7).
  CHECK(lattice->lattice_particle_count() > 100);
  CHECK(lattice->lattice_particle_count() + lattice->moved_off_lattice_count() == squares);
  // The bound of the step is the same: every row's stiffness sum, whichever kernel has its bonds.
  CHECK(lattice->stable_time_step() == lists->stable_time_step());

  // A smooth nonlinear field of strains about 1e-3.
  const double width = p.xmax - p.xmin;
  const auto deformed = [&] {
    auto s = state_at_rest(p, scene.output.damage_thresholds.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      s.motion.ux[i] = 1e-3 * width * std::sin(2.0 * p.x[i] / width) * std::cos(3.0 * p.y[i] / width);
      s.motion.uy[i] = 5e-4 * width * std::cos(4.0 * p.x[i] / width + 1.0) * std::sin(p.y[i] / width);
    }
    return s;
  };
  auto reference = deformed(), swept = deformed();
  lists->compute(reference);
  lattice->compute(swept);
  const Kinematics& a = reference.motion;
  const Kinematics& b = swept.motion;
  double scale = 0, difference = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    scale = std::max({scale, std::fabs(a.fx[i]), std::fabs(a.fy[i])});
    difference = std::max({difference, std::fabs(b.fx[i] - a.fx[i]), std::fabs(b.fy[i] - a.fy[i])});
  }
  INFO("largest force density " << scale << " N/m^3, largest difference " << difference << " ("
                                << difference / scale << " of it)");
  REQUIRE(scale > 0);
  // Single precision: a pair force carries about 1e-7 of itself, and a
  // particle's force is a sum of dozens of them that nearly cancel.
  CHECK(difference < 1e-5 * scale);

  // The strain energy, W_i of every particle (an OSB particle's a theta_i^2
  // from its whole family), summed. Both in double from the double
  // displacements (LatticeKernel::strain_energy_density), but the lists'
  // reference bonds xi are float (bond_table.hpp) and the sweep's exact
  // grid steps: about 1e-8 of the energy apart (measured 5e-9 to 7e-9).
  std::vector<double> w_lists, w_lattice;
  lists->strain_energy_density(reference, w_lists);
  lattice->strain_energy_density(swept, w_lattice);
  double energy_lists = 0, energy_lattice = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    energy_lists += p.volume[i] * w_lists[i], energy_lattice += p.volume[i] * w_lattice[i];
  INFO("strain energy per unit thickness: lists " << energy_lists << " J/m, lattice " << energy_lattice << " J/m");
  REQUIRE(energy_lists > 0);
  CHECK(std::fabs(energy_lattice - energy_lists) < 1e-7 * energy_lists);
  if (model.model != ModelType::osb) return;
  // OSB: the dilatation of every particle, the lattice's from the float
  // sweep's pairs plus the general particles' own row entries in double.
  const auto& theta_lists = lists->dilatation();
  const auto& theta_lattice = lattice->dilatation();
  REQUIRE(theta_lattice.size() == p.size());
  double theta_scale = 0, theta_difference = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    theta_scale = std::max(theta_scale, std::fabs(theta_lists[i]));
    theta_difference = std::max(theta_difference, std::fabs(theta_lattice[i] - theta_lists[i]));
  }
  INFO("largest dilatation " << theta_scale << ", largest difference " << theta_difference);
  REQUIRE(theta_scale > 0);
  CHECK(theta_difference < 1e-5 * theta_scale);
}

namespace {
// The largest difference of the force densities of two runs, relative to the largest of the first.
double force_difference(const Simulation& reference, const Simulation& other, std::size_t n) {
  const auto& a = reference.kinematics();
  const auto& b = other.kinematics();
  double scale = 0, difference = 0;
  for (std::size_t i = 0; i < n; ++i) {
    scale = std::max(scale, std::hypot(a.fx[i], a.fy[i]));
    difference = std::max(difference, std::hypot(b.fx[i] - a.fx[i], b.fy[i] - a.fy[i]));
  }
  REQUIRE(scale > 0);
  return difference / scale;
}
}  // namespace

// The general particles' dual-horizon rows evaluated each pair once in
// float (LatticeKernel::GeneralPairs) against the same rows in double, each
// entry on its own (SetupOptions::general_pairs_in_float = false), which the
// test above checks against the neighbour lists. Pairs of a fine and a
// coarse particle have two bonds with different constants, and a coarse
// particle's bond to a fine one beyond the fine one's horizon has no
// reverse. Then a homogeneous dilatation u = eps (x - x_c) stretches every
// bond by exactly eps, between the critical stretches s0(delta) of the
// fine and the coarse horizons (s0 ~ delta^-1/2): the bonds of every owner
// whose s0 is below eps break and the others hold, so that a pair of a
// fine and a coarse particle breaks one way only. Reference of the count:
// the owners' family sizes (analytic); a pair broken both ways, or neither,
// would change it by its fine bond. After it, a smooth field: the forces of
// the bonds that hold, and the damage indices.
TEST_CASE("dual horizon with the lattice sweep: the general rows' float pairs give the double rows' forces and "
          "break each direction at its owner's critical stretch",
          "[dual_horizon][lattice][general-pairs]") {
  const int plate = GENERATE(0, 1, 2);
  const pd::ParticleSet p = plate == 0 ? box_plate() : refined_plate(plate == 1 ? 0.0 : 5e-4);
  const Scene scene = dual_horizon_scene(true);
  SetupOptions in_double;
  in_double.general_pairs_in_float = false;
  Simulation pairs(scene, p), rows(scene, p, in_double);
  INFO("plate " << plate << ": " << p.size() << " particles, " << pairs.general_pair_count() << " general pairs");
  REQUIRE(pairs.general_pair_count() > 1000);  // the pairs are in use, and only in the float run
  REQUIRE(rows.general_pair_count() == 0);
  REQUIRE(pairs.lattice_particle_count() == rows.lattice_particle_count());

  // The bound of the one-horizon pairs (test_general_pairs.cpp): a float
  // pair's force is off by about 6e-4 of itself at worst for the least
  // stretched bonds, a particle's sum of dozens of them by about 1e-6 of the
  // largest force density; a bond with the other end's constants or a
  // reaction left out changes a force by a whole bond's share, 1e-2 and more.
  const auto [ux, uy] = test::smooth_field(p);
  pairs.set_displacements(ux, uy);
  rows.set_displacements(ux, uy);
  const double intact = force_difference(rows, pairs, p.size());
  INFO("smooth field: largest force difference " << intact << " of the largest force density");
  CHECK(intact < 2e-5);
  CHECK(pairs.energies().strain == rows.energies().strain);  // a separate double pass on the same states

  // eps in the widest gap (in log) between the owners' critical stretches.
  std::vector<double> s0(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) s0[i] = Pmb::constants(scene.material, p.horizon[i]).critical_stretch;
  std::vector<double> levels = s0;
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  REQUIRE(levels.size() >= 2);
  double eps = 0, gap = 0;
  for (std::size_t l = 0; l + 1 < levels.size(); ++l)
    if (levels[l + 1] / levels[l] > gap) gap = levels[l + 1] / levels[l], eps = std::sqrt(levels[l] * levels[l + 1]);
  const auto families = pd::compact_families(p);
  std::uint64_t expected = 0, bonds = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    bonds += families.family_size(i);
    if (s0[i] < eps) expected += families.family_size(i);
  }
  INFO("eps " << eps << " (a factor " << std::sqrt(gap) << " from the nearest s0); directed bonds " << bonds
              << ", of owners with s0 < eps " << expected);
  REQUIRE(expected > 0);
  REQUIRE(expected < bonds);
  const double xc = 0.5 * (p.xmin + p.xmax), yc = 0.5 * (p.ymin + p.ymax);
  std::vector<double> dilated_x(p.size()), dilated_y(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) dilated_x[i] = eps * (p.x[i] - xc), dilated_y[i] = eps * (p.y[i] - yc);
  pairs.set_displacements(dilated_x, dilated_y);
  rows.set_displacements(dilated_x, dilated_y);
  CHECK(rows.broken_bond_count() == expected);
  CHECK(pairs.broken_bond_count() == expected);

  pairs.set_displacements(ux, uy);
  rows.set_displacements(ux, uy);
  const double after = force_difference(rows, pairs, p.size());
  double worst_damage = 0, largest_damage = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    worst_damage = std::max(worst_damage, std::fabs(pairs.damage()[i] - rows.damage()[i]));
    largest_damage = std::max(largest_damage, rows.damage()[i]);
  }
  INFO("after the breaks: largest force difference " << after << ", largest damage difference " << worst_damage
                                                      << " (largest damage " << largest_damage << ")");
  CHECK(largest_damage > 0.1);
  CHECK(after < 2e-5);
  CHECK(worst_damage < 1e-6);
  CHECK(pairs.energies().strain == rows.energies().strain);
}

namespace {
// A cracking run of `model` on the box plate with the lattice split and on
// the lists: the same broken bonds, displacements, damage and energies.
void check_cracking_run(const ModelCase& model) {
  const auto& p = box_plate();
  const Scene scene = dual_horizon_scene(true, model);
  const double dx = p.spacing, centre = 0.5 * (p.xmin + p.xmax), width = p.xmax - p.xmin;
  struct Result {
    std::vector<double> ux, uy, damage;
    std::uint64_t broken = 0;
    std::vector<std::uint64_t> broken_per_step;  // directed bonds broken after each step
    EnergyTotals energies;
  };
  std::vector<Result> results;
  for (const bool lattice_kernel : {false, true}) {
    Simulation sim(scene, p, kernel_options(lattice_kernel));
    // The two halves pulled apart, fast enough to break bonds in the box and outside it.
    std::vector<double> vx(p.size()), vy(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      vx[i] = 30.0 * std::tanh(8 * (p.x[i] - centre) / width);
      vy[i] = 6.0 * std::sin(6 * p.y[i] / width);
    }
    sim.set_velocities(vx, vy);
    std::vector<std::uint64_t> broken_per_step;
    for (int s = 0; s < 200; ++s) {
      sim.step();
      broken_per_step.push_back(sim.broken_bond_count());
    }
    REQUIRE_FALSE(sim.non_finite().found);
    results.push_back({sim.kinematics().ux, sim.kinematics().uy, sim.damage(), sim.broken_bond_count(),
                       std::move(broken_per_step), sim.energies()});
  }
  const auto& lists = results[0];
  const auto& lattice = results[1];
  double worst_u = 0, largest_u = 0, worst_damage = 0, largest_damage = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    worst_u = std::max({worst_u, std::fabs(lattice.ux[i] - lists.ux[i]), std::fabs(lattice.uy[i] - lists.uy[i])});
    largest_u = std::max(largest_u, std::hypot(lists.ux[i], lists.uy[i]));
    worst_damage = std::max(worst_damage, std::fabs(lattice.damage[i] - lists.damage[i]));
    largest_damage = std::max(largest_damage, lists.damage[i]);
  }
  INFO(name_of(model) << ": broken directed bonds: lists " << lists.broken << ", lattice " << lattice.broken
                                       << "; largest displacement difference " << worst_u / dx << " dx of "
                                       << largest_u / dx << " dx; largest damage difference " << worst_damage
                                       << " (largest damage " << largest_damage << ")");
  REQUIRE(lists.broken > 1000);  // the run really cracks
  CHECK(lattice.broken == lists.broken);
  // The first step after which the two runs' broken bonds differ in number (200: none).
  const auto first_apart = static_cast<int>(
      std::mismatch(lists.broken_per_step.begin(), lists.broken_per_step.end(), lattice.broken_per_step.begin())
          .first -
      lists.broken_per_step.begin());
  INFO("the broken bonds' counts first differ after step " << first_apart << " of 200");
  // As test_lattice_kernel.cpp: float round-off of displacements of about 0.01 dx.
  // While no bond's stretch comes within the sweep's round-off of its
  // critical stretch the two runs break every bond at the same step and stay
  // 5e-8 to 7e-8 dx apart (this plate is the same from any checkout,
  // docs/mesher.md, "Determinism"). A compiler that rounds differently (an
  // instrumented build, another optimisation level) can move one bond's break
  // a step: its impulse then moves the positions by about 3e-5 dx (seen on
  // such builds: 2.85e-5 dx with the same 18,750 bonds broken at the end).
  // A wrong force moves them by far more than 1e-3 dx within 200 steps.
  if (first_apart == 200)
    CHECK(worst_u < 1e-7 * dx);
  else
    CHECK(worst_u < 1e-3 * dx);
  // The damage index of the sweep counts broken weights in units of 2^-20 of
  // a cell (lattice_kernel.hpp); a bond broken a step apart does not change
  // the final damage once both runs have broken it.
  CHECK(worst_damage < 1e-6);
  // The energies of the last step: the same displacements to float
  // round-off and the same broken bonds give the same strain and kinetic
  // energies to about the displacements' relative round-off.
  INFO("strain energy: lists " << lists.energies.strain << " J/m, lattice " << lattice.energies.strain
                               << " J/m; kinetic: lists " << lists.energies.kinetic << ", lattice "
                               << lattice.energies.kinetic);
  CHECK(lattice.energies.strain == Approx(lists.energies.strain).epsilon(1e-5));
  CHECK(lattice.energies.kinetic == Approx(lists.energies.kinetic).epsilon(1e-5));
}
}  // namespace

TEST_CASE("dual horizon with the lattice sweep: a cracking run breaks the bonds the neighbour lists break",
          "[dual_horizon][lattice]") {
  check_cracking_run(pmb_case);
}

// OSB under each failure variant of theory.md Sec. 5.8 (one test case each:
// a pair of runs takes some 12 s of one core).
TEST_CASE("dual-horizon OSB with the lattice sweep: a cracking run breaks the bonds the neighbour lists break",
          "[dual_horizon][lattice][osb]") {
  check_cracking_run(osb_case);
}

TEST_CASE("dual-horizon OSB with the lattice sweep: cracking under osb_failure = force_only",
          "[dual_horizon][lattice][osb]") {
  check_cracking_run(osb_force_only_case);
}

TEST_CASE("dual-horizon OSB with the lattice sweep: cracking under osb_failure = bond_term_only",
          "[dual_horizon][lattice][osb]") {
  check_cracking_run(osb_bond_term_only_case);
}

// The set-up of a one-process dual-horizon OSB run with the lattice split
// makes no table of every bond (since 8 December 2026; before, it built the
// whole table for its stable step and dropped it once the lattice was made,
// a peak of 2346 MiB at C3-A with boxes at dx / 2, docs/scaling.md): the
// step is summed from the bonds, bit for bit the whole table's bound
// (theory.md Secs. 5.4, 6.8), and the rows hold the general particles'
// bonds among themselves only. On a plate of squares with a small refined
// corner (12,800 squares, 256 refined children, m = 3) the set-up's rise of
// the resident set must stay below a quarter of what the whole table's
// arrays hold (the old set-up rose by more than all of them: the table and
// the owned bonds it is built from). Measured with the process's peak
// resident set, reset just before (Linux; elsewhere the reset does nothing
// and the rise reads low).
TEST_CASE("dual-horizon OSB with the lattice sweep on one process: the set-up builds no table of every bond",
          "[dual_horizon][lattice][osb]") {
  return_large_blocks_when_freed();  // as pd-solve: a freed table leaves the resident set
  const double dx = 1e-4, width = 160 * dx, height = 80 * dx;
  pd::RefinementRegion corner;
  corner.x0 = width - 8 * dx, corner.y0 = 0, corner.x1 = width, corner.y1 = 8 * dx, corner.factor = 2;
  const pd::ParticleSet p =
      pd::make_refined_rectangle_lattice(width, height, dx, 3 * dx, corner, pd::Quadrature::analytic);
  const Scene scene = dual_horizon_scene(true, osb_case);
  const auto setup = build_bond_setup(scene, p, pd::compact_families(p), {});
  REQUIRE(setup.horizon_mode == HorizonMode::dual_horizon);

  reset_peak_memory();
  const double resident_before = static_cast<double>(peak_memory_bytes());
  const auto field = make_force_field(scene, p, setup, true);
  const double rise = static_cast<double>(peak_memory_bytes()) - resident_before;
  REQUIRE(field->lattice_particle_count() > p.size() / 2);

  // The whole table, built here after the measurement.
  const BondTable whole =
      variable_horizon_table<Osb>(p, setup, scene.material, HorizonMode::dual_horizon, true, nullptr);
  double table_bytes = 0;
  const auto add = [&](const char*, auto member) {
    const auto& array = whole.*member;
    table_bytes += static_cast<double>(array.size() * sizeof(array[0]));
  };
  BondTable::for_each_entry_array(add);
  BondTable::for_each_particle_array(add);
  INFO("set-up rise " << rise / (1 << 20) << " MiB, the whole table's arrays " << table_bytes / (1 << 20)
                      << " MiB, " << setup.families.bond_count() << " directed bonds");
  CHECK(rise < 0.25 * table_bytes);
  // Its step is the whole table's bound, bit for bit.
  const double a = Osb::dilatation_coefficient(Osb::constants(scene.material, setup.horizon));
  CHECK(field->stable_time_step() == dual_horizon_state_stable_time_step(whole, a, scene.material.density));
}

// The general pairs' values reach each end in its row's order, and each
// pair is evaluated by one thread: one and two threads give the same run bit
// for bit while pairs of the rows break (PMB: the rows in float pairs).
TEST_CASE("dual horizon with the lattice sweep: a cracking run does not depend on the thread count",
          "[dual_horizon][lattice][general-pairs]") {
  const auto& p = box_plate();
  const Scene scene = dual_horizon_scene(true);
  const double centre = 0.5 * (p.xmin + p.xmax), width = p.xmax - p.xmin;
  std::vector<double> vx(p.size()), vy(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    vx[i] = 30.0 * std::tanh(8 * (p.x[i] - centre) / width);
    vy[i] = 6.0 * std::sin(6 * p.y[i] / width);
  }
  const auto run_with = [&](int threads) {
    omp_set_num_threads(threads);
    Simulation sim(scene, p);
    REQUIRE(sim.general_pair_count() > 1000);
    sim.set_velocities(vx, vy);
    for (int s = 0; s < 120; ++s) sim.step();
    return std::make_pair(sim.save_state(), sim.damage());
  };
  const int default_threads = omp_get_max_threads();
  const auto one = run_with(1), two = run_with(2);
  omp_set_num_threads(default_threads);
  CHECK(one.first.kinematics.ux == two.first.kinematics.ux);
  CHECK(one.first.kinematics.vy == two.first.kinematics.vy);
  CHECK(one.first.bond_states == two.first.bond_states);
  CHECK(one.second == two.second);
  CHECK(std::count(one.first.bond_states.begin(), one.first.bond_states.end(), 0) > 1000);
}

namespace {
// Reference: the dual property (Ren et al. 2017, Eqs. (17)-(18)); the sweep
// applies each pair force to both ends in float sums, so momentum holds to
// float round-off (test_dynamics.cpp's bound for the lattice: 1e-6 of the
// magnitude), the lists' rows to double round-off. With OSB the owner's
// theta_i / m_i goes with both copies of a row's bond, and both ends' with a
// pair of the sweep (theory.md Sec. 6.8).
void check_momentum(const ModelCase& model, bool damage) {
  const auto& p = box_plate();
  const Scene scene = dual_horizon_scene(damage, model);
  Simulation sim(scene, p, kernel_options(true));
  REQUIRE(sim.lattice_particle_count() > 0);
  const double amplitude = damage ? 100.0 : 1.0;  // m/s
  const double change = test::momentum_change_over_steps(sim, p, scene.material.density, amplitude, 2024, 300);
  INFO(name_of(model) << ", damage " << damage << ": momentum change " << change << " of the magnitude sum; broken bonds "
                 << sim.broken_bond_count());
  if (damage) CHECK(sim.broken_bond_count() > 0);
  CHECK(change < 1e-6);
}
}  // namespace

TEST_CASE("dual horizon with the lattice sweep: linear momentum is conserved to the sweep's float round-off",
          "[dual_horizon][lattice]") {
  check_momentum(pmb_case, GENERATE(false, true));
}

TEST_CASE("dual-horizon OSB with the lattice sweep: linear momentum is conserved to the sweep's float round-off",
          "[dual_horizon][lattice][osb]") {
  check_momentum(osb_case, GENERATE(false, true));
}

TEST_CASE("dual horizon with the lattice sweep: a restart from a checkpoint equals the uninterrupted run bit for bit",
          "[dual_horizon][lattice][restart]") {
  // Reference: the uninterrupted run (the bond states go through the
  // checkpoint in the kernel's own layout: the sweep's bits, then the
  // dual-horizon rows' entries).
  const ModelCase model = GENERATE(pmb_case, osb_case);
  INFO(name_of(model));
  const auto folder = test::fresh_folder(model.model == ModelType::pmb ? "dual_horizon_lattice_restart"
                                                                       : "dual_horizon_lattice_restart_osb");
  const std::string plate = test::pd_mesh(folder, "c1_plate_hole.geo",
                                          "--spacing 0.4mm --horizon-factor 3 --box-spacing 0.1mm");
  auto scene = dual_horizon_scene(true, model);
  scene.particle_file = plate;
  // A fixed step, the automatic one of this plate (its box cells set it).
  scene.time.step = Simulation(scene, pd::read_particle_file(plate)).time_step();
  scene.time.automatic = false;
  scene.output.energy_interval = 10;
  scene.output.snapshot_interval = 40;
  scene.output.checkpoint_interval = 50;
  scene.restart_key_text = "dual horizon lattice restart";
  for (const char* side : {"top", "bottom"}) {
    LoadSpec l;
    l.name = side;
    l.kind = LoadKind::velocity;
    l.region.set = side;
    l.has_y = true;
    l.y = std::string(side) == "top" ? 25.0 : -25.0;
    scene.loads.push_back(l);
  }
  std::ostringstream log;
  RunOptions options = test::quiet_options(log);
  scene.time.end = 160 * scene.time.step;
  options.output_dir = folder + "/whole";
  CHECK(run_scene(scene, options).steps == 160);
  // The plan names both kernels.
  CHECK(log.str().find("kernel:    lattice sweep for ") != std::string::npos);
  CHECK(log.str().find("dual-horizon rows for ") != std::string::npos);

  scene.time.end = 100 * scene.time.step;
  options.output_dir = folder + "/split";
  CHECK(run_scene(scene, options).steps == 100);
  scene.time.end = 160 * scene.time.step;
  options.restart = true;
  CHECK(run_scene(scene, options).steps == 160);

  using pd::test_support::existing_file_text;
  const auto energy = existing_file_text(folder + "/whole/" + pd::results::energy_file);
  CHECK(existing_file_text(folder + "/whole/" + pd::results::arrival_file) ==
        existing_file_text(folder + "/split/" + pd::results::arrival_file));
  CHECK(energy == existing_file_text(folder + "/split/" + pd::results::energy_file));
  CHECK(existing_file_text(folder + "/whole/snapshots/step_00000160.vtp") ==
        existing_file_text(folder + "/split/snapshots/step_00000160.vtp"));
  // Bonds broke before the checkpoint the restart read (step 100), so their
  // states went through it: the energy row of step 100, column broken_bonds
  // (found by the header: the row ends with the particle count and the run's
  // identifier; until 7 December 2026 this read the last column, the
  // particle count, which is never 0).
  std::istringstream rows(energy);
  std::string header, row;
  std::getline(rows, header);
  std::size_t broken_column = 0;
  {
    std::istringstream names(header);
    for (std::string name; std::getline(names, name, ',') && name != "broken_bonds";) ++broken_column;
  }
  REQUIRE(broken_column == 6);  // time_s, step, kinetic_J, strain_J, external_work_J, total_minus_work_J
  double broken_at_checkpoint = -1;
  while (std::getline(rows, row)) {
    const std::vector<double> values = pd::test_support::csv_numbers(header, row);
    if (values.at(1) == 100) broken_at_checkpoint = values.at(broken_column);
  }
  INFO("directed bonds broken at step 100: " << broken_at_checkpoint);
  CHECK(broken_at_checkpoint > 0);
}

// A process of a distributed run (LatticeSubdomain: its owned particles,
// then its ghosts) holds the general particles' dual-horizon rows of its
// owned particles only, a ghost's row empty (local_rows). Its float pairs
// with a ghost end are made from the owned end's row, which holds all that
// end receives: each owned particle gets the one-process force and damage
// bit for bit (the same float operations on the same values; a pair whose
// ends the local numbering swaps negates each of them exactly), and the
// pairs of two owned particles come first, evaluated before the ghosts'
// displacements arrive. Its broken bonds are its owned rows' own entries:
// the two halves of the plate count the one-process count between them
// (a dual entry there is another row's bond, which may break alone at its
// owner's critical stretch). Every particle general (no lattice particle,
// the kernel's rows hold every bond), so that every bond is on the pairs;
// the homogeneous dilatation of the test above breaks one way only the
// pairs of a fine and a coarse particle, many across the halves' cut.
namespace {
struct RowsOnPart {
  std::vector<double> fx, fy, damage;  // per local particle
  std::uint64_t broken = 0;
  std::size_t pairs = 0;
};

// The kernel on the local particles `ids` (indices of `p`, the first
// `owned` of them owned, all of p's particles among them) at (ux, uy); the
// ghosts' displacements arrive with the ghost exchange only (NaN before).
RowsOnPart rows_on_part(const pd::ParticleSet& p, const BondSetup& setup, const Scene& scene,
                        const std::vector<std::uint32_t>& ids, std::size_t owned, const std::vector<double>& ux,
                        const std::vector<double>& uy) {
  const std::size_t n = ids.size();
  const LocalBonds local = local_bonds(p, setup, ids, owned);
  LatticeModelSetup model;
  model.general_lists_without_lattice = true;
  model.general_pairs_in_float = true;
  model.dual_horizon_rows = [&](const std::vector<std::uint8_t>&, std::vector<std::uint8_t>* intact) {
    std::vector<std::uint8_t> whole_intact;
    const std::vector<std::uint8_t> none(p.size(), 0);
    BondTable whole = dual_horizon_general_rows<Pmb>(p, setup, scene.material, none, true, &whole_intact);
    LocalRows rows = local_rows(std::move(whole), std::move(whole_intact), {}, ids, owned);
    *intact = std::move(rows.intact);
    return std::move(rows.table);
  };
  LatticeSubdomain subdomain;
  subdomain.owned_count = owned;
  subdomain.is_lattice.assign(n, 0);
  LatticeKernel kernel(local.particles, local.setup, model, true, &subdomain);
  Kinematics k;
  k.ux.assign(n, std::nan("")), k.uy.assign(n, std::nan(""));
  for (std::size_t l = 0; l < owned; ++l) k.ux[l] = ux[ids[l]], k.uy[l] = uy[ids[l]];
  k.fx.assign(n, 0.0), k.fy.assign(n, 0.0);
  GhostExchange exchange;
  if (owned < n) {
    exchange.start_displacements = [] {};
    exchange.finish_displacements = [&] {
      for (std::size_t l = owned; l < n; ++l) k.ux[l] = ux[ids[l]], k.uy[l] = uy[ids[l]];
    };
    kernel.set_ghost_exchange(exchange);
  }
  RowsOnPart r;
  r.damage.assign(n, 0.0);
  kernel.compute<Pmb, DamageOn>(k, r.damage);
  r.fx = k.fx, r.fy = k.fy;
  r.broken = kernel.broken_bond_count();
  r.pairs = kernel.general_pair_count();
  return r;
}
}  // namespace

TEST_CASE("dual horizon: a process's general rows give their owned particles the one-process forces and damage on "
          "float pairs with ghost ends, and count each broken bond once over the processes",
          "[dual_horizon][lattice][general-pairs][subdomain]") {
  const auto& p = box_plate();
  const Scene scene = dual_horizon_scene(true);
  const BondSetup setup = build_bond_setup(scene, p, pd::compact_families(p), {});
  // One process: every particle owned.
  std::vector<std::uint32_t> all(p.size());
  for (std::uint32_t i = 0; i < p.size(); ++i) all[i] = i;
  // The halves left and right of a cut through the box round the hole.
  const double cut = 0.5 * (p.xmin + p.xmax) + 0.3e-3;
  std::vector<std::uint32_t> left, right;
  for (std::uint32_t i = 0; i < p.size(); ++i) (p.x[i] < cut ? left : right).push_back(i);
  std::vector<std::uint32_t> left_first = left, right_first = right;
  left_first.insert(left_first.end(), right.begin(), right.end());
  right_first.insert(right_first.end(), left.begin(), left.end());
  REQUIRE(left.size() > 1000);
  REQUIRE(right.size() > 1000);

  // Between the coarse (1.2 mm) and the fine (0.3 mm) horizons' s0.
  const double eps = std::sqrt(Pmb::constants(scene.material, 1.2e-3).critical_stretch *
                               Pmb::constants(scene.material, 0.3e-3).critical_stretch);
  const double xc = 0.5 * (p.xmin + p.xmax), yc = 0.5 * (p.ymin + p.ymax);
  const auto [smooth_x, smooth_y] = test::smooth_field(p);
  std::vector<double> dilated_x(p.size()), dilated_y(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) dilated_x[i] = eps * (p.x[i] - xc), dilated_y[i] = eps * (p.y[i] - yc);
  for (const bool dilated : {false, true}) {
    INFO((dilated ? "the dilatation that breaks the coarse owners' bonds" : "the smooth field"));
    const auto& ux = dilated ? dilated_x : smooth_x;
    const auto& uy = dilated ? dilated_y : smooth_y;
    const RowsOnPart one = rows_on_part(p, setup, scene, all, p.size(), ux, uy);
    const RowsOnPart on_left = rows_on_part(p, setup, scene, left_first, left.size(), ux, uy);
    const RowsOnPart on_right = rows_on_part(p, setup, scene, right_first, right.size(), ux, uy);
    REQUIRE(one.pairs > 10000);
    // Each half's pairs: those of its owned rows, with ghost ends too.
    CHECK(on_left.pairs > left.size());
    CHECK(on_right.pairs > right.size());
    CHECK(on_left.pairs + on_right.pairs > one.pairs);
    std::size_t differ = 0;
    for (const auto* part : {&on_left, &on_right}) {
      const auto& ids = part == &on_left ? left_first : right_first;
      const std::size_t owned = part == &on_left ? left.size() : right.size();
      for (std::size_t l = 0; l < owned; ++l)
        differ += part->fx[l] != one.fx[ids[l]] || part->fy[l] != one.fy[ids[l]] ||
                  part->damage[l] != one.damage[ids[l]];
    }
    CHECK(differ == 0);
    if (!dilated) {
      CHECK(one.broken == 0);
    } else {
      // The bonds the coarse particles own: thousands (their own entries
      // broken, each the reaction of a fine particle's pair half).
      CHECK(one.broken > 10000);
      CHECK(on_left.broken + on_right.broken == one.broken);
    }
  }
}
