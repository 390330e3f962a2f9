// The lattice kernel's general particles (free cells of the NB-NUG boxes and
// the squares near them) evaluate their bonds among themselves each pair once
// in single precision (LatticeKernel::GeneralPairs). The reference is the
// same kernel with those bonds on the double-precision neighbour lists
// (SetupOptions::general_pairs_in_float = false), which evaluate each
// direction of a bond on its own with its own constants and which the other
// solver tests verify against elasticity. Everything else (the sweep's pairs
// with a lattice end) is the same code in both runs, so the differences
// measured here are the general pairs' alone.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "atomic_file.hpp"
#include "checkpoint.hpp"
#include "results_format.hpp"
#include "run.hpp"
#include "simulation.hpp"
#include "test_support.hpp"
#include "../test_commands.hpp"

using namespace pd::solver;

namespace {

// C3-A (50 mm x 25 mm, a row of 8 pores of radius 0.75 mm) as pd-mesh builds
// it at dx = 0.25 mm and delta = 3.5 dx: an NB-NUG grid whose free cells hold
// bonds with k_ij != k_ji and, at this half-integer horizon factor, one-way
// bonds (theory.md Sec. 1.6); about 20,000 particles.
const std::string& c3a_plate_file() {
  static const std::string path = [] {
    const auto folder = test::fresh_folder("general-pairs-c3a");
    return test::pd_mesh(folder, "c3a_pores.geo", "--spacing 0.25mm --horizon 0.875mm");
  }();
  return path;
}

const pd::ParticleSet& c3a_plate() {
  static const pd::ParticleSet plate = pd::read_particle_file(c3a_plate_file());
  return plate;
}

Scene scene_of(ModelType model) {
  auto scene = test::basic_scene();
  scene.model = model;
  scene.effects.surface_correction = true;
  if (model == ModelType::osb) {
    scene.material.poisson_ratio = 0.35;
    scene.material.plane = PlaneKind::strain;  // a = (kappa - 2 mu)/2 = 0.25 E: a strong dilatation term
  }
  return scene;
}


// The largest differences of the force densities and (OSB) the dilatations
// of two runs, relative to the largest value of the reference run.
struct Differences {
  double force = 0, dilatation = 0;
};
Differences differences(const Simulation& reference, const Simulation& other, std::size_t n) {
  double f_scale = 0, t_scale = 0;
  const auto& a = reference.kinematics();
  const auto& b = other.kinematics();
  for (std::size_t i = 0; i < n; ++i) f_scale = std::max(f_scale, std::hypot(a.fx[i], a.fy[i]));
  for (double t : reference.dilatation()) t_scale = std::max(t_scale, std::fabs(t));
  REQUIRE(f_scale > 0);
  Differences d;
  for (std::size_t i = 0; i < n; ++i) d.force = std::max(d.force, std::hypot(b.fx[i] - a.fx[i], b.fy[i] - a.fy[i]));
  d.force /= f_scale;
  for (std::size_t i = 0; i < reference.dilatation().size(); ++i)
    d.dilatation = std::max(d.dilatation, std::fabs(other.dilatation()[i] - reference.dilatation()[i]) / t_scale);
  return d;
}

const char* model_name(ModelType model) { return model == ModelType::pmb ? "PMB" : "OSB"; }

SetupOptions general_pairs(bool in_float) {
  SetupOptions options;
  options.general_pairs_in_float = in_float;
  return options;
}

}  // namespace

// The bound: a pair's force in float carries a few 2^-24 = 6e-8 of itself,
// and the float rest length and xi put the extension off by 6e-8 of the
// bond's relative displacement (strain x |xi|, 1e-4 |xi| here): 6e-8 |xi|
// against an extension of 1e-4 |xi|, 6e-4 of a pair's force at worst for
// the least stretched bonds, far less for most. A particle sums a few dozen
// pairs whose forces mostly cancel (a smooth field's net force is about
// delta/L of a bond's): measured about 1e-6 of the largest force density
// here (the lattice sweep's float pairs give the same order, test_osb.cpp).
// The bound 2e-5 leaves a margin; a direction with the other end's
// constants changes a free cell's force by its stiffness asymmetry, 1e-2 of
// a bond's force and more, a missing or doubled pair by a whole bond's.
TEST_CASE("the general particles' float pairs give the double lists' forces on an NB-NUG C3-A plate",
          "[lattice][general-pairs]") {
  const auto model = GENERATE(ModelType::pmb, ModelType::osb);
  const auto& p = c3a_plate();
  const auto scene = scene_of(model);
  Simulation in_float(scene, p, general_pairs(true)), in_double(scene, p, general_pairs(false));
  REQUIRE(in_float.lattice_particle_count() > p.size() / 2);
  REQUIRE(in_float.lattice_particle_count() + 1000 < p.size());  // thousands of general particles
  REQUIRE(in_double.lattice_particle_count() == in_float.lattice_particle_count());
  REQUIRE(in_float.general_pair_count() > 10000);  // the pairs are in use, and only in the float run
  REQUIRE(in_double.general_pair_count() == 0);
  const auto [ux, uy] = test::smooth_field(p);
  in_float.set_displacements(ux, uy);
  in_double.set_displacements(ux, uy);
  const auto d = differences(in_double, in_float, p.size());
  INFO(model_name(model) << ": largest differences of the float pairs from the double lists: force " << d.force
                        << ", dilatation " << d.dilatation << " (of the largest)");
  CHECK(d.force < 2e-5);
  CHECK(d.dilatation < 2e-5);
  // The elastic energy is not the kernels' (a separate double pass): equal.
  CHECK(in_float.energies().strain == in_double.energies().strain);
}

// Bonds that break: a jump of one dx in u_x across the line x = D + 0.3 mm
// (D = 50/9 mm: through the first pore's box of free cells, and squares),
// which stretches the bonds across it by 0.05 and more, over 5 s0, and the
// others by about 1e-4: they break or hold clearly in both forms, and a
// pair must break in both directions at once. In that step the
// displacements reach dx while other bonds stretch by 1e-4 |xi|: float
// relative displacements then carry up to 6e-4 of a short bond's, hence the
// bound 1e-3 there (a broken bond left in would add a whole bond's share,
// 1e-2 and more). Then the smooth field again with the bonds broken: the
// intact bounds. Every OSB failure variant (theory.md Sec. 5.8).
TEST_CASE("the general particles' float pairs break the double lists' bonds, in every OSB failure variant",
          "[lattice][general-pairs]") {
  const int variant = GENERATE(0, 1, 2, 3);  // PMB, then OSB (a), (b), (c)
  const auto& p = c3a_plate();
  auto scene = scene_of(variant == 0 ? ModelType::pmb : ModelType::osb);
  if (variant > 0) scene.osb_failure = osb_failures[variant - 1].failure;
  scene.effects.damage = true;
  Simulation in_float(scene, p, general_pairs(true)), in_double(scene, p, general_pairs(false));
  REQUIRE(in_float.general_pair_count() > 10000);
  const auto [ux, uy] = test::smooth_field(p);
  auto jump = ux;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.x[i] > 50e-3 / 9 + 0.3e-3) jump[i] += p.spacing;
  in_float.set_displacements(jump, uy);
  in_double.set_displacements(jump, uy);
  const auto breaking = differences(in_double, in_float, p.size());
  const auto broken = in_double.broken_bond_count();
  CHECK(in_float.broken_bond_count() == broken);
  in_float.set_displacements(ux, uy);
  in_double.set_displacements(ux, uy);
  const auto after = differences(in_double, in_float, p.size());
  INFO("variant " << variant << ": broken directed bonds " << broken << " (double lists), "
                  << in_float.broken_bond_count() << " (float pairs); breaking step: force " << breaking.force
                  << ", dilatation " << breaking.dilatation << "; after: force " << after.force << ", dilatation "
                  << after.dilatation);
  CHECK(broken > 1000);
  CHECK(breaking.force < 1e-3);
  CHECK(breaking.dilatation < 1e-3);
  CHECK(after.force < 2e-5);
  CHECK(after.dilatation < 2e-5);
  double worst_damage = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    worst_damage = std::max(worst_damage, std::fabs(in_float.damage()[i] - in_double.damage()[i]));
  CHECK(worst_damage < 1e-6);  // the same bonds broken: the damage indices to round-off
}

// A crack running: the plate pulled apart from the mid-line, 150 steps, the
// bonds breaking one step after another. Float round-off may move a bond
// that reaches its critical extension within ~1e-6 of it by a step, so the
// broken bonds may differ by a few; the bound: 0.5 % of them (a wrong
// critical extension of one end, or pairs that break one way only, changes
// the count by far more). Measured: see the INFO line.
TEST_CASE("a cracking run with the general pairs in float breaks the double lists' bonds", "[lattice][general-pairs]") {
  const auto model = GENERATE(ModelType::pmb, ModelType::osb);
  const auto& p = c3a_plate();
  auto scene = scene_of(model);
  scene.effects.damage = true;
  std::vector<std::uint64_t> broken;
  std::vector<std::vector<double>> damage, ux, uy;
  std::vector<double> strain;
  for (const bool in_float : {false, true}) {
    Simulation sim(scene, p, general_pairs(in_float));
    const double yc = 0.5 * (p.ymin + p.ymax), height = p.ymax - p.ymin;
    std::vector<double> vx(p.size(), 0.0), vy(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) vy[i] = 30.0 * std::tanh(20 * (p.y[i] - yc) / height);
    sim.set_velocities(vx, vy);
    for (int s = 0; s < 150; ++s) sim.step();
    broken.push_back(sim.broken_bond_count());
    damage.push_back(sim.damage());
    ux.push_back(sim.kinematics().ux);
    uy.push_back(sim.kinematics().uy);
    strain.push_back(sim.energies().strain);
  }
  double worst_u = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    worst_u = std::max({worst_u, std::fabs(ux[1][i] - ux[0][i]), std::fabs(uy[1][i] - uy[0][i])});
  std::size_t differing = 0;
  for (std::size_t i = 0; i < p.size(); ++i) differing += std::fabs(damage[0][i] - damage[1][i]) > 1e-6;
  INFO(model_name(model) << ": broken directed bonds " << broken[0] << " (double lists), " << broken[1]
                        << " (float pairs); particles whose damage differs: " << differing
                        << "; largest displacement difference " << worst_u / p.spacing << " dx; strain energy "
                        << strain[0] << " (double lists), relative difference "
                        << (strain[1] - strain[0]) / strain[0]);
  REQUIRE(broken[0] > 10000);  // the plate really cracks
  CHECK(std::fabs(static_cast<double>(broken[1]) - static_cast<double>(broken[0])) <= 5e-3 * broken[0]);
  CHECK(differing <= p.size() / 1000);
}

// A checkpoint holds the bond states of the general particles' bonds bond
// by bond (general_intact_); a restarted run takes the pairs' states back
// from them. The plate is torn apart along its mid-line through the pores
// (initial velocities +-30 m/s above and below it), so that pairs among
// general particles break before and after the checkpoint; the run
// interrupted at step 40 and continued to step 80 must write the
// uninterrupted run's files byte for byte.
TEST_CASE("a cracking run with the general pairs in float restarts bit for bit", "[lattice][general-pairs][restart]") {
  const auto model = GENERATE(ModelType::pmb, ModelType::osb);
  const auto& p = c3a_plate();
  auto scene = scene_of(model);
  scene.particle_file = c3a_plate_file();
  scene.effects.damage = true;
  scene.time.automatic = false;
  scene.time.step = 2e-8;
  scene.output.energy_interval = 10;
  scene.output.snapshot_interval = 40;
  scene.output.checkpoint_interval = 40;
  scene.restart_key_text = "general pairs restart scene";
  const double yc = 0.5 * (p.ymin + p.ymax);
  LoadSpec up;
  up.name = "up";
  up.kind = LoadKind::initial_velocity;
  up.region.has_box = true;
  up.region.box = {p.xmin - 1.0, yc, p.xmax + 1.0, p.ymax + 1.0};
  up.has_y = true;
  up.y = 30.0;
  LoadSpec down = up;
  down.name = "down";
  down.region.box = {p.xmin - 1.0, p.ymin - 1.0, p.xmax + 1.0, yc};
  down.y = -30.0;
  scene.loads = {up, down};
  REQUIRE(Simulation(scene, p, SetupOptions{}).general_pair_count() > 10000);  // a run's default: the float pairs
  const auto folder = test::fresh_folder(std::string("general-pairs-restart-") + model_name(model));
  std::ostringstream log;
  RunOptions options = test::quiet_options(log);
  scene.time.end = 80 * scene.time.step;
  options.output_dir = folder + "/whole";
  CHECK(run_scene(scene, options).steps == 80);
  scene.time.end = 40 * scene.time.step;
  options.output_dir = folder + "/split";
  CHECK(run_scene(scene, options).steps == 40);
  const auto at_checkpoint = read_checkpoint(folder + "/split/" + checkpoint_file, "general pairs restart scene\nparticles " +
                                                                                     pd::file_hash_hex(scene.particle_file));
  scene.time.end = 80 * scene.time.step;
  options.restart = true;
  CHECK(run_scene(scene, options).steps == 80);
  const auto text = [&](const std::string& run, const std::string& file) {
    return pd::test_support::existing_file_text(folder + "/" + run + "/" + file);
  };
  CHECK(text("whole", pd::results::energy_file) == text("split", pd::results::energy_file));
  CHECK(text("whole", pd::results::arrival_file) == text("split", pd::results::arrival_file));
  CHECK(text("whole", "snapshots/step_00000080.vtp") == text("split", "snapshots/step_00000080.vtp"));
  // Bonds broke before the checkpoint and after it (the states went through it).
  const auto at_end = read_checkpoint(folder + "/whole/" + checkpoint_file, "general pairs restart scene\nparticles " +
                                                                                pd::file_hash_hex(scene.particle_file));
  double damage_then = 0, damage_at_end = 0;
  for (double d : at_checkpoint.state.damage) damage_then += d;
  for (double d : at_end.state.damage) damage_at_end += d;
  INFO(model_name(model) << ": sum of the damage indices at step 40 " << damage_then << ", at step 80 "
                         << damage_at_end);
  CHECK(damage_then > 10);
  CHECK(damage_at_end > damage_then);
}
