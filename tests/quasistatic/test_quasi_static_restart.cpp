// Checkpoints and --restart of quasi-static runs (docs/solver.md,
// "Quasi-static mode"): a run continued from the checkpoint of a load step
// writes the same files as an uninterrupted one, also after Ctrl-C (docs/solver.md,
// "Interrupting a run").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <csignal>

#include "lattice.hpp"
#include "load_steps.hpp"
#include "results_format.hpp"
#include "support.hpp"
#include "../test_commands.hpp"

namespace {

using pd::test_support::existing_file_text;
using pd::test_support::file_text;

// The 4 mm x 2 mm plate of test_static_then_dynamic.cpp (dx = 0.1 mm, delta =
// 0.3 mm, 1.5 mm edge pre-crack), pulled apart at top and bottom: bonds start
// to break at load factor 1 (7.8 um per strip), the crack runs at 1.1.
const std::string scene_text = R"(particles = "plate.pdp"
[material]
youngs_modulus = 3.24e9
fracture_energy = 200
[effects]
damage = true
surface_correction = true
[quasi_static]
load_factors = [0.5, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4]
tolerance = 1e-8
[[loads]]
set = "top"
type = "displacement"
y = 7.8e-6
[[loads]]
set = "bottom"
type = "displacement"
y = -7.8e-6
[[precracks]]
from = [0.0, 0.001]
to = [0.0015, 0.001]
[output]
snapshot_interval = 1
checkpoint_interval = 1
)";

// A folder with the plate and the scene (plus `extra_scene_text`), and a
// runner of pd-solve on it: run(OUT, ARGS) writes FOLDER/OUT and FOLDER/OUT.log.
struct PlateRun {
  std::string folder;
  explicit PlateRun(const std::string& name, const std::string& extra_scene_text = "")
      : folder(pd::quasistatic::test::fresh_folder(name)) {
    pd::write_particle_file(folder + "/plate.pdp",
                            pd::make_rectangle_lattice(4e-3, 2e-3, 1e-4, 3e-4, pd::Quadrature::analytic));
    std::ofstream scene(folder + "/qs.toml");
    scene << scene_text << extra_scene_text;
  }
  int operator()(const std::string& out, const std::string& args) const {
    const std::string command = std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/qs.toml -q --threads 1 -o " +
                                folder + "/" + out + " " + args + " > " + folder + "/" + out + ".log 2>&1";
    return std::system(command.c_str());
  }
};

}  // namespace

// Reference: the uninterrupted run. Same thread count, so every sum is done
// in the same order and the files must agree byte for byte.
TEST_CASE("a quasi-static run restarted after a load step equals the uninterrupted run",
          "[quasistatic][restart][executable]") {
  // Both kernels: the energy table, and the lattice kernels (whose checkpoints
  // hold the kernels' own bond states, docs/solver.md "Fast kernels").
  const bool lattice = GENERATE(false, true);
  const std::string kernels = lattice ? " --set 'quasi_static.kernels=\"lattice\"'" : "";
  const PlateRun run(lattice ? "restart-lattice" : "restart");
  const std::string& folder = run.folder;
  REQUIRE(run("full", kernels) == 0);
  // Interrupted after the third step (where bonds start to break), then continued with all seven.
  REQUIRE(run("restarted", "--set 'quasi_static.load_factors=[0.5, 0.9, 1.0]'" + kernels) == 0);
  REQUIRE(run("restarted", "--restart" + kernels) == 0);
  CHECK_THAT(existing_file_text(folder + "/restarted.log"), Catch::Contains("restart after load step 3"));
  namespace fs = std::filesystem;
  const fs::path full = fs::path(folder) / "full", restarted = fs::path(folder) / "restarted";
  const std::string steps = existing_file_text((full / pd::results::load_steps_file).string());
  // Seven steps, and bonds broke both before the restart and after it (broken_bonds, column 10), so
  // the restored bond states and damage load factors matter.
  REQUIRE(std::count(steps.begin(), steps.end(), '\n') == 8);
  const auto broken_bonds = [&](int step) {
    std::istringstream lines(steps);
    std::string line;
    for (int k = 0; k <= step; ++k) std::getline(lines, line);
    std::stringstream cells(line);
    std::string cell;
    for (int c = 0; c < 10; ++c) std::getline(cells, cell, ',');
    return std::stol(cell);
  };
  const long precrack = broken_bonds(1);
  CHECK(broken_bonds(3) > precrack);
  CHECK(broken_bonds(7) > broken_bonds(3));
  for (const std::string file : {pd::results::load_steps_file, pd::results::final_state_file,
                                 pd::results::snapshot_collection, "snapshots/step_00000007.vtp"})
    CHECK(existing_file_text((restarted / file).string()) == existing_file_text((full / file).string()));
  // The run's identifier (docs/formats.md, "Run identifier") as the table's
  // last column, once on each row: the restarted run's rows come from its
  // checkpoint without it and get it once more when written.
  const std::string summary = existing_file_text((restarted / pd::results::summary_file).string());
  const std::string id_key = "\"run_id\": \"";
  REQUIRE(summary.find(id_key) != std::string::npos);
  const std::string id = summary.substr(summary.find(id_key) + id_key.size(), 16);
  CHECK_THAT(steps.substr(0, steps.find('\n')), Catch::EndsWith(",bottom_displacement_y_m,run_id"));
  std::size_t ids = 0;
  for (auto at = steps.find(id); at != std::string::npos; at = steps.find(id, at + 1)) ++ids;
  CHECK(ids == 7);
  CHECK(steps.find("," + id + "\n") == steps.find(id) - 1);  // the last cell

  // Interrupted after the second step, before any bond broke: the checkpoint
  // holds the predictor's last increment (load_steps.hpp), without which the
  // third step would start from another guess (other iterations, other
  // round-off) than the uninterrupted run's. The restart gives another
  // output.energy_interval, which a quasi-static run never reads: no part of
  // its key (before the third sitting of 6 December 2026 refused as another scene).
  REQUIRE(run("early", "--set 'quasi_static.load_factors=[0.5, 0.9]'" + kernels) == 0);
  REQUIRE(run("early", "--restart --set output.energy_interval=7" + kernels) == 0);
  const fs::path early = fs::path(folder) / "early";
  for (const std::string file : {pd::results::load_steps_file, pd::results::final_state_file})
    CHECK(existing_file_text((early / file).string()) == existing_file_text((full / file).string()));

  // A folder that lacks a snapshot the checkpoint's run wrote is not that
  // run's series: refused, naming the file (before, the restart listed the
  // absent file in snapshots.pvd, exit 0).
  REQUIRE(run("gap", "--set 'quasi_static.load_factors=[0.5, 0.9]'" + kernels) == 0);
  fs::remove(fs::path(folder) / "gap" / "snapshots" / "step_00000001.vtp");
  CHECK(run("gap", "--restart" + kernels) != 0);
  CHECK_THAT(existing_file_text(folder + "/gap.log"),
             Catch::Contains("gap/snapshots/step_00000001.vtp: missing, though the run of") &&
                 Catch::Contains("load factor 0.5") && Catch::Contains("run without --restart to start over"));

  // Only load steps may be added: other load factors, or another scene, are refused.
  CHECK(run("restarted", "--restart --set 'quasi_static.load_factors=[0.5, 0.8, 1.0, 1.1, 1.2, 1.3, 1.4, 1.5]'" +
                             kernels) != 0);
  // The message names the first step that differs and both factors (before 7
  // December 2026 neither).
  CHECK_THAT(existing_file_text(folder + "/restarted.log"),
             Catch::Contains("not the first load factors of quasi_static.load_factors / increments: load step 2 was "
                             "done at load factor 0.9, and the scene now gives 0.8 (they may only be extended; run "
                             "without --restart to start over)"));
  // A shorter list than the steps done says so (before 5 December 2026: "not
  // the first load factors", as for other factors).
  CHECK(run("restarted", "--restart --set 'quasi_static.load_factors=[0.5, 0.9]'" + kernels) != 0);
  CHECK_THAT(existing_file_text(folder + "/restarted.log"),
             Catch::Contains("load steps done, and quasi_static.load_factors / increments now lists 2: a restart "
                             "may only extend the list"));
  CHECK(run("restarted", "--restart --set quasi_static.tolerance=1e-7" + kernels) != 0);
  CHECK_THAT(existing_file_text(folder + "/restarted.log"), Catch::Contains("different scene"));
}

// A run that ended on its stop condition stays ended: the checkpoint of the
// last load step holds the stop decision, so --restart is refused (the scene
// has three load factors left after it), as is one with no load step left;
// the finished run's results stay as they are (before, such a restart took
// no step and rewrote them, exit 0).
TEST_CASE("a quasi-static run that met its stop condition takes no step after --restart",
          "[quasistatic][restart][executable]") {
  // Just ahead of the pre-crack tip: damaged past 0.2 when the crack runs, at load factor 1.1 (step 4 of 7).
  const PlateRun run("restart-stopped", "[stop]\nbox = [0.0016, 0.0009, 0.0018, 0.0011]\ndamage = 0.2\n");
  const std::string& folder = run.folder;
  REQUIRE(run("out", "") == 0);
  CHECK_THAT(existing_file_text(folder + "/out.log"), Catch::Contains("done: 4 load steps (stop condition"));
  const std::string steps = existing_file_text(folder + "/out/" + pd::results::load_steps_file);
  const std::string summary = existing_file_text(folder + "/out/" + pd::results::summary_file);
  CHECK(run("out", "--restart") != 0);
  CHECK_THAT(existing_file_text(folder + "/out.log"),
             Catch::Contains("the run stopped after load step 4") && Catch::Contains("a restart would stop again") &&
                 !Catch::Contains("step 5:"));
  CHECK(existing_file_text(folder + "/out/" + pd::results::load_steps_file) == steps);
  CHECK(existing_file_text(folder + "/out/" + pd::results::summary_file) == summary);
  // Without the stop, a scene whose load steps the checkpoint holds all.
  const PlateRun plain("restart-done", "");
  REQUIRE(plain("out", "--set 'quasi_static.load_factors=[0.5, 1.0]'") == 0);
  CHECK(plain("out", "--restart --set 'quasi_static.load_factors=[0.5, 1.0]'") != 0);
  CHECK_THAT(existing_file_text(plain.folder + "/out.log"),
             Catch::Contains("the scene's 2 load steps are all done in") && Catch::Contains("(2 done)"));
  // Load factors other than the saved ones are refused before the restart
  // touches the folder: the finished run keeps its summary.json (before 5
  // December 2026 it was removed, and pd-post read the run as incomplete).
  const std::string finished = existing_file_text(plain.folder + "/out/" + pd::results::summary_file);
  CHECK(plain("out", "--restart --set 'quasi_static.load_factors=[0.7, 1.0, 1.5]'") != 0);
  CHECK_THAT(existing_file_text(plain.folder + "/out.log"), Catch::Contains("not the first load factors"));
  CHECK(existing_file_text(plain.folder + "/out/" + pd::results::summary_file) == finished);
  CHECK(plain("out", "--restart --set 'quasi_static.load_factors=[0.5, 1.0, 1.2]'") == 0);
  CHECK_THAT(existing_file_text(plain.folder + "/out.log"), Catch::Contains("restart after load step 2"));
}

// load_steps.csv's prescribed displacement of a load that varies over its set
// (LoadSpec's value + gradient . (p - at)) is its mean over the set's
// particles. Reference: the top row's centres run from x = 0.05 to 3.95 mm,
// mean 2 mm, so y = 7.8 um + 1e-3 (x - 1 mm) has the mean 8.8 um; at load
// factor 0.5, 4.4 um (the constant part alone would say 3.9 um).
TEST_CASE("load_steps.csv gives a varying displacement load's mean over its set", "[quasistatic][executable]") {
  const PlateRun run("varying-load");
  REQUIRE(run("out", "--set 'quasi_static.load_factors=[0.5]' --set effects.damage=false "
                     "--set 'loads.top.y={value = 7.8e-6, gradient = [1e-3, 0], at = [0.001, 0.002]}'") == 0);
  std::istringstream rows(existing_file_text(run.folder + "/out/" + pd::results::load_steps_file));
  std::string header, row;
  std::getline(rows, header);
  std::getline(rows, row);  // the one load step
  const auto cells = [](const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
    return out;
  };
  const auto names = cells(header), values = cells(row);
  const auto top_y = std::find(names.begin(), names.end(), "top_displacement_y_m") - names.begin();
  REQUIRE(static_cast<std::size_t>(top_y) < values.size());
  CHECK(std::stod(values[top_y]) == Approx(4.4e-6).epsilon(1e-9));
}

// A minimisation that did not converge, with on_nonconvergence = "warn": the
// warning reaches the terminal when stdout goes to a file (before 5 December
// 2026 it went to stdout only), once into one place (2>&1), and summary.json.
TEST_CASE("a quasi-static non-convergence warning reaches stderr when stdout is a file",
          "[quasistatic][executable]") {
  const PlateRun run("nonconvergence-echo");
  const std::string command = std::string(PD_SOLVE_EXECUTABLE) + " " + run.folder + "/qs.toml -q --threads 1 -o " +
                              run.folder + "/out --set 'quasi_static.load_factors=[0.5]' --set effects.damage=false " +
                              "--set quasi_static.max_iterations=3 --set 'quasi_static.on_nonconvergence=\"warn\"'";
  const std::string out = run.folder + "/out.txt", err = run.folder + "/err.txt";
  REQUIRE(std::system((command + " > " + out + " 2> " + err).c_str()) == 0);
  INFO(existing_file_text(out) + "\n--- stderr:\n" + existing_file_text(err));
  CHECK_THAT(existing_file_text(out), Catch::Contains("\nwarning: ") && Catch::Contains("not converged after 3"));
  CHECK_THAT(existing_file_text(err), Catch::Contains("pd-solve: warning: ") && Catch::Contains("not converged after 3"));
  REQUIRE(std::system((command + " > " + out + " 2>&1").c_str()) == 0);
  const std::string both = existing_file_text(out);
  CHECK(both.find("not converged after 3") != std::string::npos);
  CHECK(both.find("not converged after 3") == both.rfind("not converged after 3"));
  // And in summary.json's warnings.
  const std::string summary = existing_file_text(run.folder + "/out/" + pd::results::summary_file);
  const auto warnings = summary.find("\"warnings\"");
  REQUIRE(warnings != std::string::npos);
  CHECK(summary.find("not converged after 3", warnings) != std::string::npos);
}

// Reference: the uninterrupted load steps. A request to stop within a load
// step abandons it (here after bonds broke in it, in the minimisation after
// that breaking round): the state handed back is the last completed step's,
// u and bond states exactly as they were at its end, and the steps resumed
// from it on a new problem (as --restart does from its checkpoint) are the
// uninterrupted ones, bit for bit. A request after a step ends the steps
// there. Both kernels: NCG on the energy table, linear CG on the lattice
// kernels (each asks after every iteration).
TEST_CASE("load steps stopped on request go on from the last completed step as if never stopped",
          "[quasistatic][restart]") {
  using namespace pd::solver;
  const bool lattice = GENERATE(false, true);
  const auto plate = pd::make_rectangle_lattice(4e-3, 2e-3, 1e-4, 3e-4, pd::Quadrature::analytic);
  Scene scene = pd::quasistatic::test::precracked_plate_scene();
  if (lattice) scene = pd::quasistatic::test::lattice_scene(scene);
  scene.quasi_static.load_factors = {0.5, 0.9, 1.0, 1.05};
  std::ostringstream log;
  // The uninterrupted steps, and the state at the end of each.
  std::vector<std::vector<double>> u_after;
  std::vector<std::vector<std::uint8_t>> bonds_after;
  QuasiStaticProblem full_problem(scene, plate);
  const auto full = solve_quasi_static(full_problem, scene, {}, log,
                                       [&](const QuasiStaticProblem& p, const std::vector<double>& u, const LoadStepRecord&) {
                                         u_after.push_back(u);
                                         bonds_after.push_back(p.bond_states());
                                       });
  REQUIRE(full.steps.size() == 4);
  REQUIRE(full.steps[2].pairs_broken > 0);  // step 3 breaks pairs ahead of the tip, in more than one round
  REQUIRE(full.steps[2].minimisations > 1);

  // Stopped within step 3, a few iterations into its first re-equilibration.
  QuasiStaticProblem problem(scene, plate);
  long steps_done = 0, asked_since_breaking = 0;
  std::size_t broken_before = 0;
  const auto abandoned = solve_quasi_static(
      problem, scene, {}, log,
      [&](const QuasiStaticProblem& p, const std::vector<double>&, const LoadStepRecord&) {
        ++steps_done;
        broken_before = p.broken_bond_count();
      },
      nullptr, {}, nullptr, nullptr,
      [&] { return steps_done == 2 && problem.broken_bond_count() > broken_before && ++asked_since_breaking > 3; });
  REQUIRE(abandoned.interrupted);
  const InterruptedLoadSteps& stop = *abandoned.interrupted;
  CHECK(stop.abandoned);
  CHECK(stop.step == 3);
  CHECK(abandoned.stop_reason == "interrupted");
  CHECK(abandoned.steps.size() == 2);
  CHECK(stop.state.load_factors_done == std::vector<double>{0.5, 0.9});
  CHECK(stop.state.u == u_after[1]);
  CHECK(stop.bond_states == bonds_after[1]);
  CHECK(problem.broken_bond_count() > broken_before);  // the abandoned step's breaks stay in its problem

  // Resumed on a new problem from that state: steps 3 and 4 as the uninterrupted run took them.
  QuasiStaticProblem resumed_problem(scene, plate);
  resumed_problem.set_bond_states(stop.bond_states);
  const auto resumed = solve_quasi_static(resumed_problem, scene, {}, log, {}, &stop.state);
  REQUIRE(resumed.steps.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    CHECK(resumed.steps[k].iterations == full.steps[k + 2].iterations);
    CHECK(resumed.steps[k].pairs_broken == full.steps[k + 2].pairs_broken);
    CHECK(resumed.steps[k].strain_energy == full.steps[k + 2].strain_energy);
  }
  CHECK(resumed.u == full.u);
  CHECK(resumed_problem.bond_states() == bonds_after[3]);

  // Asked after step 2: the steps end there, with that step's state.
  QuasiStaticProblem after_problem(scene, plate);
  steps_done = 0;
  const auto after = solve_quasi_static(
      after_problem, scene, {}, log,
      [&](const QuasiStaticProblem&, const std::vector<double>&, const LoadStepRecord&) { ++steps_done; }, nullptr, {},
      nullptr, nullptr, [&] { return steps_done == 2; });
  REQUIRE(after.interrupted);
  CHECK_FALSE(after.interrupted->abandoned);
  CHECK(after.interrupted->step == 2);
  CHECK(after.steps.size() == 2);
  CHECK(after.interrupted->state.u == u_after[1]);
  CHECK(after.interrupted->bond_states == bonds_after[1]);
}

// Ctrl-C (SIGINT) during a quasi-static run: it stops at the next safe point
// (after its load step, or within it, whose work it drops), writes the
// checkpoint of the last completed load step (also with checkpoint_interval
// = 0) and load_steps.csv, no summary.json nor final_state.vtp, and says so
// (exit status 1); --restart then finishes the run with the files of an
// uninterrupted one, byte for byte. Before the second sitting of 5 December
// 2026 the process ended at once (exit 130, nothing on stderr), and without
// checkpoints nothing was left to restart from.
TEST_CASE("Ctrl-C ends a quasi-static run with the checkpoint of its last load step, from which --restart goes on",
          "[quasistatic][restart][executable]") {
  namespace fs = std::filesystem;
  const PlateRun run("interrupted");
  // 105 load steps to 1.05 (pairs break from 1.0 on): a second or two of work, stopped after the first.
  std::string factors = "[";
  for (int k = 1; k <= 105; ++k) factors += (k > 1 ? ", " : "") + std::to_string(k * 0.01);
  factors += "]";
  const std::vector<std::string> options{"--set", "quasi_static.load_factors=" + factors, "--set",
                                         "output.snapshot_interval=0", "--set", "output.checkpoint_interval=0"};
  const std::string shell_options = " --set 'quasi_static.load_factors=" + factors +
                                    "' --set output.snapshot_interval=0 --set output.checkpoint_interval=0";
  const std::string out = run.folder + "/out", log = run.folder + "/out.log";
  std::vector<std::string> command{PD_SOLVE_EXECUTABLE, run.folder + "/qs.toml", "-q", "--threads", "1", "-o", out};
  command.insert(command.end(), options.begin(), options.end());
  const pid_t child = pd::test_support::start_process(command, log);
  REQUIRE(child > 0);
  // Once its first load step is reported.
  for (int wait = 0; wait < 6000 && file_text(out + "/" + pd::results::load_steps_file).find("\n1,") ==
                                        std::string::npos;
       ++wait)
    ::usleep(10000);
  const int status = pd::test_support::interrupt_and_wait(child, SIGINT);
  const std::string text = file_text(log);
  INFO(text);
  CHECK(status == 1);
  const std::string said = "pd-solve: error: interrupted by SIGINT ";
  REQUIRE(text.find(said) != std::string::npos);
  CHECK(text.find(said) == text.rfind("pd-solve: error: "));  // one line
  // "after load step K of 105" (K done) or "in load step K of 105 ..., which was abandoned" (K - 1 done).
  const std::string where = text.substr(text.find(said) + said.size());
  const bool abandoned = where.rfind("in load step ", 0) == 0;
  CHECK((abandoned || where.rfind("after load step ", 0) == 0));
  const long step = std::stol(where.substr(where.find("load step ") + 10));
  const long done = abandoned ? step - 1 : step;
  CHECK(step >= 1);
  CHECK(step < 105);
  CHECK_THAT(where, Catch::Contains(" of 105 (load factor ") &&
                        Catch::Contains(out + "/checkpoint.bin holds ") &&
                        Catch::EndsWith("; the same command with --restart continues the run\n"));
  if (abandoned) CHECK_THAT(where, Catch::Contains("which was abandoned"));
  CHECK(fs::exists(out + "/checkpoint.bin"));
  CHECK_FALSE(fs::exists(out + "/" + pd::results::summary_file));
  CHECK_FALSE(fs::exists(out + "/" + pd::results::final_state_file));
  const std::string rows = existing_file_text(out + "/" + pd::results::load_steps_file);
  CHECK(std::count(rows.begin(), rows.end(), '\n') == done + 1);

  // --restart goes on from there; the files equal the uninterrupted run's.
  REQUIRE(run("out", "--restart" + shell_options) == 0);
  CHECK_THAT(existing_file_text(log), Catch::Contains("restart after load step " + std::to_string(done) + "\n"));
  REQUIRE(run("full", shell_options) == 0);
  for (const std::string file : {pd::results::load_steps_file, pd::results::final_state_file})
    CHECK(existing_file_text(out + "/" + file) == existing_file_text(run.folder + "/full/" + file));
}
