// A scene that switches from quasi-static to dynamic (quasi_static.then =
// "dynamic", docs/scenes.md; case C3's static-then-dynamic check): the scene
// keys, the hand-over of the equilibrium to the dynamic part, and pd-solve on
// such a scene (output folders, --restart).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "error.hpp"
#include "lattice.hpp"
#include "load_steps.hpp"
#include "results_format.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "static_then_dynamic.hpp"
#include "support.hpp"
#include "../test_commands.hpp"

using namespace pd::solver;

namespace {

using pd::test_support::file_text;

// A 4 mm x 2 mm PMMA plate (dx = 0.1 mm, delta = 0.3 mm, 800 particles) with
// an edge pre-crack 1.5 mm long at mid-height. Quasi-static part: the top and
// bottom strips pulled apart to u_y = +-7.8 um x the load factors (1.0
// breaks some 20 pairs ahead of the crack tip, the crack runs at about 8.8 um);
// dynamic part: `dynamic_loads`.
std::string switching_scene(const std::string& dynamic_loads, double end_time = 2e-6,
                            const std::string& load_factors = "[0.5, 0.9, 1.0]") {
  std::ostringstream s;
  s << R"(particles = "plate.pdp"
[material]
youngs_modulus = 3.24e9
density = 1190
fracture_energy = 200
[effects]
damage = true
surface_correction = true
[quasi_static]
load_factors = )" << load_factors << R"(
tolerance = 1e-10
then = "dynamic"
[time]
step = "auto"
end = )" << end_time << R"(
[[loads]]
phase = "quasi_static"
set = "top"
type = "displacement"
y = 7.8e-6
[[loads]]
phase = "quasi_static"
set = "bottom"
type = "displacement"
y = -7.8e-6
)" << dynamic_loads << R"(
[[precracks]]
from = [0.0, 0.001]
to = [0.0015, 0.001]
[output]
energy_interval = 10
)";
  return s.str();
}

// Velocities of the dynamic part on the same strips: y = +-value, ramped over ramp_time.
std::string velocity_loads(double value, double ramp_time) {
  std::ostringstream s;
  for (const char* set : {"top", "bottom"}) {
    s << "[[loads]]\nphase = \"dynamic\"\nset = \"" << set << "\"\ntype = \"velocity\"\ny = "
      << (set[0] == 't' ? value : -value) << "\n";
    if (ramp_time > 0) s << "ramp_time = " << ramp_time << "\n";
  }
  return s.str();
}

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "switch.toml");
  } catch (const pd::Error& e) {
    return e.what();
  }
  return "";
}

std::string write_plate(const std::string& folder) {
  const auto plate = pd::make_rectangle_lattice(4e-3, 2e-3, 1e-4, 3e-4, pd::Quadrature::analytic);
  pd::write_particle_file(folder + "/plate.pdp", plate);
  return folder + "/plate.pdp";
}

std::vector<std::string> csv_row(const std::string& text, std::size_t row) {
  std::istringstream lines(text);
  std::string line;
  for (std::size_t k = 0; k <= row; ++k) std::getline(lines, line);
  std::vector<std::string> cells;
  std::stringstream cells_text(line);
  for (std::string cell; std::getline(cells_text, cell, ',');) cells.push_back(cell);
  return cells;
}

// Loaded until bonds break ahead of the crack tip, then partly unloaded: the
// broken bonds there are no longer over-stretched, so only the hand-over of
// the bond states (not the dynamic kernel's own breaking rule) keeps them broken.
const std::string unloaded = "[0.5, 0.9, 1.0, 0.6]";

// The quasi-static part of a switching scene solved in-process, and its end state.
struct StaticPart {
  Equilibrium equilibrium;
  double strain_energy = 0;
  std::size_t broken_bonds = 0, precrack_bonds = 0;
  std::vector<double> damage;
};

StaticPart solve_static_part(const Scene& scene, const pd::ParticleSet& particles) {
  const Scene part = quasi_static_part(scene);
  QuasiStaticProblem problem(part, particles);
  std::ostringstream log;
  const auto result = solve_quasi_static(problem, part, {}, log);
  StaticPart s;
  s.equilibrium = {result.u, problem.broken_pairs(), result.steps.back().load_factor};
  s.strain_energy = problem.strain_energy(result.u);
  s.broken_bonds = problem.broken_bond_count();
  s.precrack_bonds = problem.precrack_bonds_cut();
  s.damage = result.damage;
  return s;
}

// How far a plate started from a static equilibrium drifts in `steps` steps
// with its loads held: the largest kinetic energy and the largest change of
// any displacement component, against its strain energy and displacement.
struct Drift {
  double strain0 = 0, largest_u = 0, largest_kinetic = 0, largest_change = 0;
  std::size_t broken0 = 0;
};

Drift drift_from_equilibrium(Simulation& sim, int steps) {
  Drift d;
  const auto u0 = sim.displacement_xyz();
  d.strain0 = sim.energies().strain;
  d.broken0 = sim.broken_bond_count();
  for (double v : u0) d.largest_u = std::max(d.largest_u, std::fabs(v));
  for (int step = 0; step < steps; ++step) {
    sim.step();
    d.largest_kinetic = std::max(d.largest_kinetic, sim.energies().kinetic);
    const auto u = sim.displacement_xyz();
    for (std::size_t c = 0; c < u.size(); ++c) d.largest_change = std::max(d.largest_change, std::fabs(u[c] - u0[c]));
  }
  return d;
}

}  // namespace

TEST_CASE("switching scene: keys, phases of the loads and their errors", "[quasistatic][switch][scene]") {
  const auto scene = parse_scene(switching_scene(velocity_loads(0.3, 0)), "switch.toml");
  CHECK(scene.quasi_static.enabled);
  CHECK(scene.quasi_static.then_dynamic);
  CHECK(scene.time.end == 2e-6);
  CHECK(scene.material.density == 1190);
  REQUIRE(scene.loads.size() == 4);
  CHECK(scene.loads[0].phase == LoadPhase::quasi_static);
  CHECK(scene.loads[3].phase == LoadPhase::dynamic);
  const auto statics = quasi_static_part(scene), dynamics = dynamic_part(scene);
  CHECK(statics.loads.size() == 2);
  CHECK_FALSE(statics.quasi_static.then_dynamic);
  CHECK(dynamics.loads.size() == 2);
  CHECK(dynamics.loads[0].kind == LoadKind::velocity);
  CHECK_FALSE(dynamics.quasi_static.enabled);
  // The dynamic part starts from the equilibrium (its plan's warning
  // without dynamic loads says so: test_loads.cpp).
  CHECK(dynamics.starts_from_equilibrium);
  CHECK_FALSE(statics.starts_from_equilibrium);
  CHECK_FALSE(scene.starts_from_equilibrium);

  const std::string ok = switching_scene(velocity_loads(0.3, 0));
  const auto replace = [&](const std::string& from, const std::string& to) {
    std::string t = ok;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  CHECK_THAT(error_of(replace("then = \"dynamic\"", "then = \"static\"")),
             Catch::Contains("switch.toml") && Catch::Contains("quasi_static.then") && Catch::Contains("'static'"));
  CHECK_THAT(error_of(replace("then = \"dynamic\"", "thn = \"dynamic\"")),
             Catch::Contains("unknown key 'quasi_static.thn'"));
  // Without `then`, [time] is still refused, with the hint.
  CHECK_THAT(error_of(replace("then = \"dynamic\"\n", "")),
             Catch::Contains("not both") && Catch::Contains("quasi_static.then"));
  CHECK_THAT(error_of(replace("[time]\nstep = \"auto\"\nend = 2e-06\n", "")),
             Catch::Contains("missing required table [time]") && Catch::Contains("dynamic part"));
  CHECK_THAT(error_of(replace("density = 1190\n", "")), Catch::Contains("material.density"));
  CHECK_THAT(error_of(replace("phase = \"quasi_static\"\nset = \"top\"", "set = \"top\"")),
             Catch::Contains("missing key 'loads[0].phase'"));
  CHECK_THAT(error_of(replace("phase = \"quasi_static\"\nset = \"top\"", "phase = \"static\"\nset = \"top\"")),
             Catch::Contains("loads[0].phase") && Catch::Contains("'static'"));
  // Each part keeps its own rules: no velocity in the quasi-static part.
  CHECK_THAT(error_of(replace("phase = \"quasi_static\"\nset = \"top\"\ntype = \"displacement\"",
                              "phase = \"quasi_static\"\nset = \"top\"\ntype = \"velocity\"")),
             Catch::Contains("loads[0].type") && Catch::Contains("not available in quasi-static mode"));
  // `phase` has no meaning in a scene with one part.
  CHECK_THAT(error_of("particles = \"p.pdp\"\n[material]\nyoungs_modulus = 1e9\ndensity = 1000\nfracture_energy = 1\n"
                      "[time]\nstep = 1e-8\nend = 1e-6\n[[loads]]\nphase = \"dynamic\"\nset = \"top\"\n"
                      "type = \"velocity\"\ny = 1\n"),
             Catch::Contains("loads[0].phase") && Catch::Contains("only in a scene that switches"));
}

// Reference: the quasi-static end state itself. Positions are reference +
// u, so u comes back to within the round-off of the positions (1e-18 m next
// to coordinates of 4e-3 m); on a uniform lattice the energy table equals the
// dynamic bonds (docs/solver.md), so strain energy, broken bonds and damage
// agree to round-off (damage weights are floats: 1e-6).
TEST_CASE("switching scene: the dynamic part starts from the quasi-static equilibrium", "[quasistatic][switch]") {
  const auto folder = pd::quasistatic::test::fresh_folder("switch-handover");
  write_plate(folder);
  const auto scene = parse_scene(switching_scene(velocity_loads(0.3, 1e-6), 2e-6, unloaded), folder + "/switch.toml");
  const auto particles = pd::read_particle_file(scene.particle_file);
  const auto statics = solve_static_part(scene, particles);
  // The hand-over of bond states is exercised: bonds broke beyond the pre-crack.
  INFO("broken " << statics.broken_bonds << ", pre-crack " << statics.precrack_bonds);
  REQUIRE(statics.broken_bonds > statics.precrack_bonds);

  Simulation sim(dynamic_part(scene), particles);
  start_from_equilibrium(sim, statics.equilibrium);
  const std::size_t n = particles.size();
  const auto u = sim.displacement_xyz();
  double largest_difference = 0, largest_u = 0;
  for (std::size_t i = 0; i < n; ++i) {
    largest_difference = std::max({largest_difference, std::fabs(u[3 * i] - statics.equilibrium.u[i]),
                                   std::fabs(u[3 * i + 1] - statics.equilibrium.u[n + i])});
    largest_u = std::max(largest_u, std::fabs(statics.equilibrium.u[n + i]));
  }
  CHECK(largest_u > 0.6 * 7.8e-6);  // the strips are at 0.6 x 7.8 um, the crack mouth opens wider
  CHECK(largest_difference < 1e-18);
  const auto e = sim.energies();
  CHECK(e.kinetic == 0);  // the velocity ramp starts at 0
  CHECK(e.external_work == 0);
  // Both sums use the same single-precision reference bond vectors but add in a different
  // order (lattice stencils against the quasi-static bond list): equal to rounding, 1e-7.
  CHECK(e.strain == Approx(statics.strain_energy).epsilon(1e-7));
  CHECK(sim.broken_bond_count() == statics.broken_bonds);
  double largest_damage_difference = 0;
  std::size_t damaged = 0;
  for (std::size_t i = 0; i < n; ++i) {
    largest_damage_difference = std::max(largest_damage_difference, std::fabs(sim.damage()[i] - statics.damage[i]));
    if (sim.damage()[i] >= sim.scene().output.damage_thresholds[0]) {
      ++damaged;
      CHECK(sim.arrival_times()[i] == 0);  // damaged before the dynamic part began
    }
  }
  CHECK(largest_damage_difference < 1e-6);
  CHECK(damaged > 0);
}

// Reference: equilibrium. The plate is held where the quasi-static part left
// it (velocity 0 on the strips), so nothing should move: the out-of-balance
// force at the switch is the minimiser's residual (relative 1e-10, double
// precision) plus the round-off of the dynamic kernel, whose lattice part
// computes in single precision (bond forces to about 1e-7 relative,
// docs/solver.md "Single precision"). The motion is then of the order of
// 1e-6 of the displacements (kinetic energy of the order of 1e-12 of the
// strain energy). A bond state or a displacement component handed over
// wrongly would set the plate ringing with a kinetic energy of the order of
// the strain energy.
TEST_CASE("switching scene: a plate held at its static displacement stays in equilibrium", "[quasistatic][switch]") {
  const auto folder = pd::quasistatic::test::fresh_folder("switch-equilibrium");
  write_plate(folder);
  const auto scene = parse_scene(switching_scene(velocity_loads(0.0, 0), 2e-6, unloaded), folder + "/switch.toml");
  const auto particles = pd::read_particle_file(scene.particle_file);
  const auto statics = solve_static_part(scene, particles);
  Simulation sim(dynamic_part(scene), particles);
  start_from_equilibrium(sim, statics.equilibrium);
  // 1000 steps (dt about 9 ns): a P wave crosses the 4 mm plate about four times.
  const Drift d = drift_from_equilibrium(sim, 1000);
  INFO("kinetic / strain " << d.largest_kinetic / d.strain0 << ", change / u " << d.largest_change / d.largest_u);
  // Measured: kinetic / strain 4.8e-12, change / u 1.4e-6 (with the double
  // neighbour lists alone: 1.0e-21 and 4.5e-11).
  CHECK(d.largest_kinetic < 1e-9 * d.strain0);
  CHECK(d.largest_change < 1e-4 * d.largest_u);
  CHECK(sim.broken_bond_count() == d.broken0);
  CHECK(sim.energies().strain == Approx(d.strain0).epsilon(1e-6));
}

// Reference: the files of docs/solver.md for both parts; the first energy
// row of the dynamic part is the last load step's state (kinetic energy 0,
// strain energy and broken bonds of load_steps.csv); a restart of the dynamic
// part from its checkpoint equals the uninterrupted run byte for byte.
TEST_CASE("pd-solve on a switching scene: both parts' files, and restart", "[quasistatic][switch][executable]") {
  const auto folder = pd::quasistatic::test::fresh_folder("switch-executable");
  write_plate(folder);
  {
    std::ofstream scene(folder + "/switch.toml");
    scene << switching_scene(velocity_loads(0.3, 1e-6), 5e-6) << "checkpoint_interval = 50\n";
  }
  const auto run = [&](const std::string& out, const std::string& extra) {
    const std::string command = std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/switch.toml -q --threads 1 -o " + folder +
                                "/" + out + " " + extra + " > " + folder + "/" + out + ".log 2>&1";
    return std::system(command.c_str());
  };
  REQUIRE(run("full", "") == 0);
  namespace fs = std::filesystem;
  const fs::path full = fs::path(folder) / "full";
  for (const char* file : {pd::results::load_steps_file, pd::results::final_state_file, pd::results::summary_file})
    CHECK(fs::exists(full / quasi_static_part_folder / file));
  for (const char* file : {pd::results::energy_file, pd::results::arrival_file, pd::results::summary_file})
    CHECK(fs::exists(full / file));
  CHECK_THAT(file_text(folder + "/full.log"), Catch::Contains("switching to dynamic at load factor 1"));

  const std::string steps = file_text((full / quasi_static_part_folder / pd::results::load_steps_file).string());
  const auto last_step = csv_row(steps, 3);  // header, then 3 load steps
  const std::string energy = file_text((full / pd::results::energy_file).string());
  // The reaction columns of the loads 'top' and 'bottom' under the names of
  // docs/formats.md, which users' scripts read: reaction_x_<load>_N in
  // energy.csv, <load>_reaction_x_N in load_steps.csv (pd-post reads these).
  CHECK_THAT(energy.substr(0, energy.find('\n')),
             Catch::EndsWith(",broken_bonds,reaction_x_top_N,reaction_y_top_N,reaction_x_bottom_N,reaction_y_bottom_N,"
                             "particles,run_id"));
  CHECK_THAT(steps.substr(0, steps.find('\n')),
             Catch::Contains(",max_damage,top_reaction_x_N,top_reaction_y_N,bottom_reaction_x_N,bottom_reaction_y_N,"
                             "top_displacement_x_m,"));
  const auto first_row = csv_row(energy, 1);
  REQUIRE(first_row.size() >= 7);
  CHECK(first_row[1] == "0");                  // step
  CHECK(std::stod(first_row[2]) == 0);         // kinetic energy
  // strain energy, equal to rounding (see the test above)
  CHECK(std::stod(first_row[3]) == Approx(std::stod(last_step[6])).epsilon(1e-7));
  CHECK(first_row[6] == last_step[9]);         // broken bonds

  // Interrupted after the checkpoint of step 50 (dt = 46 ns, 110 steps in all), then continued.
  REQUIRE(run("restarted", "--set time.end=3e-6") == 0);
  REQUIRE(run("restarted", "--restart") == 0);
  CHECK_THAT(file_text(folder + "/restarted.log"), !Catch::Contains("switching to dynamic"));
  CHECK(file_text((fs::path(folder) / "restarted" / pd::results::energy_file).string()) == energy);
}

TEST_CASE("a switching scene's dynamic part is refused for its time step before the load steps run",
          "[quasistatic][switch][executable]") {
  // time.step above the stable limit (about 5e-8 s on this plate) is the
  // dynamic part's refusal, which no equilibrium changes: before, it came
  // after the quasi-static part (hours at the C3 scene's resolution), whose
  // files were left behind.
  const auto folder = pd::quasistatic::test::fresh_folder("switch-step-refused");
  write_plate(folder);
  {
    std::ofstream scene(folder + "/switch.toml");
    scene << switching_scene(velocity_loads(0.3, 1e-6), 5e-6);
  }
  const std::string command = std::string(PD_SOLVE_EXECUTABLE) + " " + folder +
                              "/switch.toml --set time.step=1e-6 --threads 1 -o " + folder + "/out > " + folder +
                              "/out.log 2>&1";
  CHECK(std::system(command.c_str()) != 0);
  const std::string log = file_text(folder + "/out.log");
  CHECK_THAT(log, Catch::Contains("pd-solve: error: " + folder +
                                  "/switch.toml, --set: key 'time.step' = 1e-06 s is above the stable limit"));
  CHECK_THAT(log, !Catch::Contains("load factor 0.5"));  // no load step ran
  namespace fs = std::filesystem;
  // Nothing ran: the refused run leaves no folder (before 6 December 2026
  // OUTDIR stayed behind with the dynamic part's surface-correction cache).
  CHECK_FALSE(fs::exists(fs::path(folder) / "out"));
  // A folder that existed keeps what it held.
  fs::create_directories(fs::path(folder) / "mine");
  std::ofstream(folder + "/mine/notes.txt") << "kept\n";
  const std::string into_existing = std::string(PD_SOLVE_EXECUTABLE) + " " + folder +
                                    "/switch.toml --set time.step=1e-6 --threads 1 -o " + folder + "/mine > " +
                                    folder + "/mine.log 2>&1";
  CHECK(std::system(into_existing.c_str()) != 0);
  CHECK(file_text(folder + "/mine/notes.txt") == "kept\n");
  // ... and gains nothing: no quasi_static/ folder, no result, not even the
  // dynamic part's surface-correction cache (until 7 December 2026 it stayed,
  // for the next run).
  std::vector<std::string> entries;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(folder) / "mine"))
    entries.push_back(entry.path().filename().string());
  std::sort(entries.begin(), entries.end());
  CHECK(entries == std::vector<std::string>{"notes.txt"});
  // A folder of an earlier run keeps its results: the refused run removes
  // none (before 6 December 2026 it removed the dynamic part's, as the
  // switching run clears OUTDIR before its check of the dynamic part).
  const std::string run_into_used = std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/switch.toml -q --threads 1 -o " +
                                    folder + "/used > " + folder + "/used.log 2>&1";
  REQUIRE(std::system(run_into_used.c_str()) == 0);
  const fs::path used = fs::path(folder) / "used";
  std::vector<std::string> earlier;
  for (const char* name : {pd::results::summary_file, pd::results::energy_file, pd::results::arrival_file})
    earlier.push_back(file_text((used / name).string()));
  const std::string refused_in_used = std::string(PD_SOLVE_EXECUTABLE) + " " + folder +
                                      "/switch.toml --set time.step=1e-6 --threads 1 -o " + used.string() + " > " +
                                      folder + "/used.log 2>&1";
  CHECK(std::system(refused_in_used.c_str()) != 0);
  CHECK_THAT(file_text(folder + "/used.log"), Catch::Contains("is above the stable limit"));
  std::size_t k = 0;
  for (const char* name : {pd::results::summary_file, pd::results::energy_file, pd::results::arrival_file})
    CHECK(file_text((used / name).string()) == earlier[k++]);
  CHECK(fs::exists(used / quasi_static_part_folder / pd::results::load_steps_file));
  // A summary.json of another tool where the quasi-static part writes:
  // refused before either folder loses anything (before 7 December 2026
  // OUTDIR was cleared before the quasi-static part's folder was refused).
  const fs::path part = used / quasi_static_part_folder;
  std::ofstream((part / pd::results::summary_file).string()) << "{\"tool\": \"my-tool\"}";
  const std::string part_steps = file_text((part / pd::results::load_steps_file).string());
  CHECK(std::system(run_into_used.c_str()) != 0);
  CHECK_THAT(file_text(folder + "/used.log"),
             Catch::Contains((part / pd::results::summary_file).string() +
                             ": a file of a result's name that pd-solve did not write"));
  k = 0;
  for (const char* name : {pd::results::summary_file, pd::results::energy_file, pd::results::arrival_file})
    CHECK(file_text((used / name).string()) == earlier[k++]);
  CHECK(file_text((part / pd::results::load_steps_file).string()) == part_steps);
}

// The quasi-static part reads the surface-correction factors of the dynamic
// part's check from OUTDIR's cache, and its folder gets their copy once the
// part has passed its own checks. A part refused by them (here two of its
// loads hold the same particles) leaves its folder as it was: none where
// there was none, an earlier run's cache as it was (before 7 December 2026
// the copy came before those checks, and stayed).
TEST_CASE("a switching scene's quasi-static part refused by its checks leaves no cache in its folder and OUTDIR's results",
          "[quasistatic][switch][executable]") {
  const auto folder = pd::quasistatic::test::fresh_folder("switch-part-refused");
  write_plate(folder);
  std::ofstream(folder + "/switch.toml") << switching_scene(velocity_loads(0.3, 1e-6), 2e-7, "[0.5]");
  namespace fs = std::filesystem;
  const fs::path used = fs::path(folder) / "used";
  const auto run = [&](const std::string& extra) {
    const std::string command = std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/switch.toml -q --threads 1 -o " +
                                used.string() + " " + extra + " > " + folder + "/log.txt 2>&1";
    return pd::test_support::run_shell(command);
  };
  const fs::path part_cache = used / quasi_static_part_folder / "surface_correction.cache";
  REQUIRE(run("") == 0);
  const std::vector<const char*> results{pd::results::summary_file, pd::results::energy_file,
                                         pd::results::arrival_file};
  std::vector<std::string> earlier;
  for (const char* name : results) earlier.push_back(file_text((used / name).string()));
  const std::string factors = file_text(part_cache.string());
  REQUIRE_FALSE(factors.empty());
  CHECK((factors == file_text((used / "surface_correction.cache").string())));  // (bytes: not printed)
  // Another pre-crack (other factors), and a quasi-static support on the
  // left strip that shares the corners with the pulled strips.
  const std::string refused =
      "--set 'precracks.0.to=[0.0012, 0.001]' --set 'loads=[" + std::string(
      "{phase = \"quasi_static\", set = \"top\", type = \"displacement\", y = 7.8e-6}, "
      "{phase = \"quasi_static\", set = \"left\", type = \"fixed\"}, "
      "{phase = \"dynamic\", set = \"top\", type = \"velocity\", y = 0.3}]'");
  CHECK(run(refused) == 1);
  CHECK_THAT(file_text(folder + "/log.txt"),
             Catch::Contains("loads 'top' (displacement on set 'top') and 'left' (fixed on set 'left') both constrain "
                             "the y component of"));
  CHECK((file_text(part_cache.string()) == factors));
  // Nor OUTDIR's cache, which the dynamic part's check computed anew for the
  // other pre-crack (until 7 December 2026 it was replaced before the
  // quasi-static part's checks).
  CHECK((file_text((used / "surface_correction.cache").string()) == factors));
  // Nor does it remove the earlier run's results in OUTDIR: they go with the
  // quasi-static part's own once its checks have passed (until 7 December
  // 2026 they went once the dynamic part's had).
  for (std::size_t k = 0; k < results.size(); ++k) CHECK(file_text((used / results[k]).string()) == earlier[k]);
  // In an empty folder the refused run leaves it empty: no quasi-static
  // part, and no cache of the dynamic part's check (until 7 December 2026
  // OUTDIR's stayed, for the next run of the same particles).
  fs::remove_all(used);
  fs::create_directories(used);
  CHECK(run(refused) == 1);
  CHECK(fs::is_empty(used));
}

// A log that stops the run, as a killed process would, once `trigger` has
// been written to it: the run stops at a known point, the same every time.
class StoppingLog : public std::stringbuf {
public:
  explicit StoppingLog(std::string trigger) : trigger_(std::move(trigger)) {}
  struct Stopped {};

protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    const auto written = std::stringbuf::xsputn(s, n);
    if (str().find(trigger_) != std::string::npos) throw Stopped{};
    return written;
  }

private:
  std::string trigger_;
};

// Reference: the uninterrupted run, in the same process with the same thread
// count, so the files must agree byte for byte.
TEST_CASE("a switching run stopped before the switch continues with --restart", "[quasistatic][switch][restart]") {
  const auto folder = pd::quasistatic::test::fresh_folder("switch-stopped");
  write_plate(folder);
  {
    // About 40 time steps: the dynamic part's only checkpoint is the one at the switch; the
    // quasi-static part checkpoints after every load step all the same.
    std::ofstream scene(folder + "/switch.toml");
    scene << switching_scene(velocity_loads(0.3, 1e-6), 2e-6) << "checkpoint_interval = 50\n";
  }
  const Scene scene = read_scene(folder + "/switch.toml");
  namespace fs = std::filesystem;
  const auto run = [&](const std::string& out, bool restart, std::streambuf* log_buffer) {
    std::ostream log(log_buffer);
    log.exceptions(std::ios::badbit);  // the log's exception reaches the caller, as a crash would stop the run
    RunOptions options;
    options.output_dir = folder + "/" + out;
    options.restart = restart;
    options.show_progress = false;
    options.log = &log;
    return run_scene(scene, options);
  };
  std::stringbuf full_log;
  run("full", false, &full_log);
  const auto same_files = [&](const std::string& out) {
    for (const std::string& file : {std::string(pd::results::energy_file), std::string(pd::results::arrival_file),
                                   std::string(quasi_static_part_folder) + "/" + pd::results::load_steps_file,
                                   std::string(quasi_static_part_folder) + "/" + pd::results::final_state_file})
      CHECK(file_text(folder + "/" + out + "/" + file) == file_text(folder + "/full/" + file));
  };

  // A fresh run stopped where `trigger` is logged.
  const auto stop_at = [&](const std::string& trigger) {
    StoppingLog stopping(trigger);
    CHECK_THROWS_AS(run("stopped", false, &stopping), StoppingLog::Stopped);
  };
  // The stopped run continued to the end: its files are those of the full run; returns its log.
  const auto restart = [&] {
    std::stringbuf log;
    run("stopped", true, &log);
    same_files("stopped");
    return log.str();
  };

  SECTION("stopped inside the quasi-static part: it continues after its last checkpoint") {
    // Stopped while reporting load step 3, whose checkpoint is not written yet: the one of step 2 is on disk.
    stop_at("step 3: load factor");
    CHECK_FALSE(fs::exists(folder + "/stopped/" + checkpoint_file));
    CHECK_THAT(restart(), Catch::Contains("restart after load step 2") && Catch::Contains("switching to dynamic"));
  }
  SECTION("stopped at the switch: the quasi-static part is not repeated") {
    stop_at("switching to dynamic");
    // The checkpoint of the last load step: no step is solved again.
    CHECK_THAT(restart(), Catch::Contains("restart after load step 3") && Catch::Contains("done: 3 load steps"));
  }
  SECTION("stopped in the dynamic part: it continues from the checkpoint written at the switch") {
    // Stopped when the dynamic part prints its plan, after its step-0 checkpoint (written before the plan).
    stop_at("time step:");
    REQUIRE(fs::exists(folder + "/stopped/" + checkpoint_file));
    CHECK_THAT(restart(), !Catch::Contains("switching to dynamic") && !Catch::Contains("load step"));
  }
  SECTION("no checkpoint at all: the error names both places") {
    std::stringbuf log;
    CHECK_THROWS_WITH(run("never-run", true, &log), Catch::Contains("nothing to restart from") &&
                                                       Catch::Contains("quasi_static/checkpoint.bin"));
  }
}

// A log that raises SIGINT once `trigger` has been written to it: Ctrl-C at
// a known point of the run, the same every time.
class InterruptingLog : public std::stringbuf {
public:
  explicit InterruptingLog(std::string trigger) : trigger_(std::move(trigger)) {}

protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    const auto written = std::stringbuf::xsputn(s, n);
    if (!raised_ && str().find(trigger_) != std::string::npos) {
      raised_ = true;
      std::raise(SIGINT);
    }
    return written;
  }

private:
  std::string trigger_;
  bool raised_ = false;
};

// Reference: the uninterrupted run, in the same process with the same thread
// count (byte for byte). Ctrl-C in a switching scene's quasi-static part, here
// without checkpoints: the part stops before the dynamic one with the
// checkpoint of its last completed load step and says so; --restart finishes
// it and the dynamic part as the uninterrupted run did. Before the second
// sitting of 5 December 2026 the process ended at once, and without
// checkpoints nothing was left to restart from.
TEST_CASE("Ctrl-C in a switching scene's quasi-static part: --restart goes on from its last load step",
          "[quasistatic][switch][restart]") {
  const auto folder = pd::quasistatic::test::fresh_folder("switch-interrupted");
  write_plate(folder);
  {
    std::ofstream scene(folder + "/switch.toml");
    scene << switching_scene(velocity_loads(0.3, 1e-6), 2e-6);
  }
  const Scene scene = read_scene(folder + "/switch.toml");
  const auto run = [&](const std::string& out, bool restart, std::streambuf* log_buffer) {
    std::ostream log(log_buffer);
    RunOptions options;
    options.output_dir = folder + "/" + out;
    options.restart = restart;
    options.show_progress = false;
    options.log = &log;
    options.threads = 1;  // (spinning threads would wait long on a busy machine)
    return run_scene(scene, options);
  };
  std::stringbuf full_log;
  run("full", false, &full_log);
  const std::string part = folder + "/stopped/" + quasi_static_part_folder + "/";
  const auto interrupt_at = [&](const std::string& trigger, const std::string& said) {
    InterruptingLog interrupting(trigger);
    CHECK_THROWS_WITH(run("stopped", false, &interrupting),
                      "interrupted by SIGINT after load step " + said + ": " + part + checkpoint_file +
                          " holds that step, load_steps.csv the rows of the steps done; the same command with "
                          "--restart continues the run");
    CHECK(std::filesystem::exists(part + checkpoint_file));
    CHECK_FALSE(std::filesystem::exists(folder + "/stopped/" + pd::results::energy_file));
  };
  SECTION("after a load step") {
    interrupt_at("step 2: load factor", "2 of 3 (load factor 0.9)");
    CHECK_FALSE(std::filesystem::exists(part + pd::results::summary_file));
  }
  SECTION("while the part writes its end files") {
    interrupt_at("done: 3 load steps", "3 of 3 (load factor 1)");
  }
  std::stringbuf log;
  run("stopped", true, &log);
  CHECK_THAT(log.str(), Catch::Contains("switching to dynamic"));
  for (const std::string& file : {std::string(pd::results::energy_file), std::string(pd::results::arrival_file),
                                 std::string(quasi_static_part_folder) + "/" + pd::results::load_steps_file,
                                 std::string(quasi_static_part_folder) + "/" + pd::results::final_state_file})
    CHECK(file_text(folder + "/stopped/" + file) == file_text(folder + "/full/" + file));
}

// Reference: the scene of case C3's static-then-dynamic check
// (geometries/c3_static_then_dynamic.toml, [Peng, Chen, Bobaru 2023, App. 3]):
// 0.042 mm per strip quasi-statically, then 0.3 m/s.
TEST_CASE("the C3 static-then-dynamic scene is read", "[quasistatic][switch][scene]") {
  const auto folder = std::filesystem::path(PD_C1_GEOMETRY).parent_path();
  const auto scene = read_scene((folder / "c3_static_then_dynamic.toml").string());
  CHECK(scene.quasi_static.then_dynamic);
  CHECK(scene.quasi_static.load_factors.back() == 1.0);
  const auto statics = quasi_static_part(scene), dynamics = dynamic_part(scene);
  REQUIRE(statics.loads.size() == 2);
  CHECK(statics.loads[0].y == Approx(4.2e-5));
  REQUIRE(dynamics.loads.size() == 2);
  CHECK(dynamics.loads[0].kind == LoadKind::velocity);
  CHECK(dynamics.loads[0].y == Approx(0.3));
  CHECK(dynamics.loads[0].time_function.kind == TimeFunction::Kind::constant);
  CHECK(dynamics.stop.enabled);
  CHECK_FALSE(statics.stop.enabled);
}

// The same hand-over with the ordinary state-based model (theory.md Sec. 5.6):
// the quasi-static OSB residual is the dynamic OSB force, so the dynamic part
// starts in equilibrium, with the bonds the quasi-static part broke.
TEST_CASE("switching scene with OSB: a plate held at its static displacement stays in equilibrium",
          "[quasistatic][switch][osb]") {
  const auto folder = pd::quasistatic::test::fresh_folder("switch-equilibrium-osb");
  write_plate(folder);
  std::string text = switching_scene(velocity_loads(0.0, 0), 2e-6, unloaded);
  text.replace(text.find("[material]"), 10, "[model]\ntype = \"osb\"\n[material]\npoisson_ratio = 0.25");
  text.replace(text.find("surface_correction = true"), 25, "surface_correction = false");
  const auto scene = parse_scene(text, folder + "/switch.toml");
  REQUIRE(scene.model == ModelType::osb);
  const auto particles = pd::read_particle_file(scene.particle_file);
  const auto statics = solve_static_part(scene, particles);
  INFO("broken " << statics.broken_bonds << ", pre-crack " << statics.precrack_bonds);
  CHECK(statics.broken_bonds > statics.precrack_bonds);
  Simulation sim(dynamic_part(scene), particles);
  start_from_equilibrium(sim, statics.equilibrium);
  CHECK(sim.energies().strain == Approx(statics.strain_energy).epsilon(1e-9));
  const Drift d = drift_from_equilibrium(sim, 1000);
  INFO("kinetic / strain " << d.largest_kinetic / d.strain0 << ", change / u " << d.largest_change / d.largest_u);
  CHECK(d.largest_kinetic < 1e-9 * d.strain0);
  CHECK(d.largest_change < 1e-4 * d.largest_u);
  CHECK(sim.broken_bond_count() == d.broken0);
}
