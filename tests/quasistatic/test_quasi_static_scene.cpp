// The [quasi_static] scene section (docs/scenes.md) and pd-solve on a
// quasi-static scene file.
#include <catch2/catch.hpp>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "error.hpp"
#include "json_text.hpp"
#include "lattice.hpp"
#include "loads.hpp"
#include "quasi_static_run.hpp"
#include "results_format.hpp"
#include "scene.hpp"
#include "support.hpp"
#include "../test_commands.hpp"

using pd::solver::parse_scene;

namespace {

const std::string head = R"(particles = "plate.pdp"
[material]
youngs_modulus = 3.24e9
fracture_energy = 200
)";
const std::string loads = R"(
[[loads]]
set = "left"
type = "displacement"
x = -1e-7
[[loads]]
set = "right"
type = "displacement"
x = 1e-7
)";

std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_scene(text, "qs.toml", overrides);
  } catch (const pd::Error& e) {
    return e.what();
  }
  return "";
}

// The small plate (2 mm x 1 mm, dx = 0.1 mm) in a fresh folder with `scene`
// as its qs.toml; run(extra) runs pd-solve on it into `out` with `extra` on
// the command line, its output in `log`, and gives the exit status.
struct SmallPlateRun {
  std::string folder, out, log;
  int run(const std::string& extra) const {
    return pd::test_support::run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/qs.toml -q -o " + out +
                                       " " + extra + " > " + log + " 2>&1");
  }
};

SmallPlateRun small_plate_run(const std::string& name, const std::string& scene) {
  SmallPlateRun plate;
  plate.folder = pd::quasistatic::test::fresh_folder(name);
  plate.out = plate.folder + "/out";
  plate.log = plate.folder + "/log.txt";
  pd::write_particle_file(plate.folder + "/plate.pdp",
                          pd::make_rectangle_lattice(2e-3, 1e-3, 1e-4, 3e-4, pd::Quadrature::analytic));
  std::ofstream(plate.folder + "/qs.toml") << scene;
  return plate;
}

}  // namespace

TEST_CASE("quasi-static scene: load factors from a list or from runs of increments", "[quasistatic][scene]") {
  const auto list = parse_scene(head + "[quasi_static]\nload_factors = [0.5, 1.0]\n" + loads, "qs.toml");
  CHECK(list.quasi_static.enabled);
  CHECK(list.quasi_static.load_factors == std::vector<double>{0.5, 1.0});
  CHECK(list.material.density == 0);  // not needed without dynamics
  const auto runs = parse_scene(head + "[quasi_static]\nincrements = [[2, 1.0], [3, 0.25]]\ntolerance = 1e-7\n"
                                "max_iterations = 500\non_nonconvergence = \"warn\"\n" + loads, "qs.toml");
  REQUIRE(runs.quasi_static.load_factors.size() == 5);
  CHECK(runs.quasi_static.load_factors == std::vector<double>{1.0, 2.0, 2.25, 2.5, 2.75});
  // Each factor is its row's start plus its place times the increment, not a
  // running sum: 300 increments of 0.01 end at 3 exactly and 20000 of 1e-6 at
  // 0.02 (summed, 2.99999999999998 and 0.019999999999999348, before 7 December 2026).
  const auto many = parse_scene(head + "[quasi_static]\nincrements = [[300, 0.01], [20000, 1e-6]]\n" + loads, "qs.toml");
  REQUIRE(many.quasi_static.load_factors.size() == 20300);
  CHECK(many.quasi_static.load_factors[99] == 1.0);
  CHECK(many.quasi_static.load_factors[299] == 3.0);
  CHECK(many.quasi_static.load_factors.back() == 3.02);
  const auto small = parse_scene(head + "[quasi_static]\nincrements = [[20000, 1e-6]]\n" + loads, "qs.toml");
  CHECK(small.quasi_static.load_factors.back() == 0.02);
  CHECK(runs.quasi_static.tolerance == 1e-7);
  CHECK(runs.quasi_static.max_iterations == 500);
  CHECK(runs.quasi_static.warn_on_nonconvergence);
  CHECK_FALSE(runs.quasi_static.lattice_kernels);  // default: the energy table
  CHECK(runs.quasi_static.progress_interval == 10);
  const auto fast = parse_scene(head + "[quasi_static]\nload_factors = [1.0]\nkernels = \"lattice\"\n"
                                "progress_interval = 0\n" + loads, "qs.toml");
  CHECK(fast.quasi_static.lattice_kernels);
  CHECK(fast.quasi_static.progress_interval == 0);
  // A dynamic scene is unchanged: no [quasi_static], quasi-static mode off.
  const auto dynamic = parse_scene(head + "density = 1190\n[time]\nstep = \"auto\"\nend = 1e-6\n", "d.toml");
  CHECK_FALSE(dynamic.quasi_static.enabled);
}

TEST_CASE("quasi-static scene: bad input names the file, key and value", "[quasistatic][scene]") {
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\ntolerence = 1e-6\n"),
             Catch::Contains("qs.toml") && Catch::Contains("unknown key 'quasi_static.tolerence'"));
  CHECK_THAT(error_of(head + "[quasi_static]\ntolerance = 1e-6\n"),
             Catch::Contains("exactly one of 'load_factors'"));
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\n[time]\nstep = 1e-8\nend = 1e-6\n"),
             Catch::Contains("either dynamic ([time]) or quasi-static"));
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\non_nonconvergence = \"ignore\"\n"),
             Catch::Contains("quasi_static.on_nonconvergence") && Catch::Contains("'ignore'"));
  CHECK_THAT(error_of(head + "[quasi_static]\nincrements = [[2.5, 1.0]]\n"),
             Catch::Contains("quasi_static.increments"));
  // Rows of at most 1e7 each that add up to more: each step's factor was
  // kept before any limit was checked, 8 bytes a step (before 7 December 2026).
  CHECK_THAT(error_of(head + "[quasi_static]\nincrements = [[6000000, 1e-9], [2, 1e-3], [5000000, 1e-9]]\n"),
             Catch::Contains("key 'quasi_static.increments' = [[6000000, 1e-09], [2, 0.001], [5000000, 1e-09]]: "
                             "the rows add up to more than 1e7 load steps (11000002 by row 3); expected at most 1e7 "
                             "in all"));
  CHECK(parse_scene(head + "[quasi_static]\nincrements = [[9999999, 1e-9], [1, 1e-3]]\n", "qs.toml")
            .quasi_static.load_factors.size() == 10000000);
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\n[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = 1\n"),
             Catch::Contains("loads[0].type") && Catch::Contains("not available in quasi-static mode"));
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\n[[loads]]\nset = \"top\"\ntype = \"displacement\"\n"
                             "y = 1e-6\nramp_time = 1e-5\n"),
             Catch::Contains("loads[0].ramp_time"));
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\ntolerance = 2\n"),
             Catch::Contains("quasi_static.tolerance") && Catch::Contains("= 2"));
  // Below the round-off of the forces' sums no minimisation converges: each
  // ran to max_iterations, and the run failed advising more (before 7
  // December 2026).
  for (const std::string tiny : {"1e-300", "1e-16"})
    CHECK(error_of(head + "[quasi_static]\nload_factors = [1.0]\ntolerance = " + tiny + "\n") ==
          "qs.toml:7: key 'quasi_static.tolerance' = " + tiny +
              ": below the round-off of double arithmetic (2.2e-16), which no minimisation can reach; expected a "
              "relative residual from 2.2e-16 to below 1, e.g. 1e-10");
  CHECK(parse_scene(head + "[quasi_static]\nload_factors = [1.0]\ntolerance = 1e-15\n", "qs.toml")
            .quasi_static.tolerance == 1e-15);
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\nkernels = \"float\"\n"),
             Catch::Contains("quasi_static.kernels") && Catch::Contains("\"lists\" or \"lattice\""));
  CHECK_THAT(error_of(head + "poisson_ratio = 0.3\n[model]\ntype = \"osb\"\n[quasi_static]\nload_factors = [1.0]\n"
                             "kernels = \"lattice\"\n"),
             Catch::Contains("qs.toml") && Catch::Contains("\"pmb\" only"));
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\nprogress_interval = -1\n"),
             Catch::Contains("quasi_static.progress_interval"));
  // Counts below 1 were told "a number of steps >= 0", though 0 is refused
  // too and these count iterations and rounds (before 7 December 2026).
  for (const std::string bad : {"-1", "0"}) {
    CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\nmax_iterations = " + bad + "\n"),
               Catch::Contains("key 'quasi_static.max_iterations' = " + bad + ": expected a number of iterations >= 1"));
    CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\nmax_breaking_rounds = " + bad + "\n"),
               Catch::Contains("key 'quasi_static.max_breaking_rounds' = " + bad +
                               ": expected a number of rounds >= 1"));
  }
  // Load factors that are all 0 leave the loads out: the run computed the
  // unloaded plate and ended as a success (before 7 December 2026).
  for (const std::string zero : {"[0]", "[0.0, -0.0]"})
    CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = " + zero + "\n" + loads),
               Catch::Contains("qs.toml:6: key 'quasi_static.load_factors' = " + zero +
                               ": every load factor is 0: the loads would never act"));
  CHECK(parse_scene(head + "[quasi_static]\nload_factors = [0, 1.0]\n" + loads, "qs.toml").quasi_static.load_factors ==
        std::vector<double>{0.0, 1.0});
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\nmax_iterations = 1.5\n"),
             Catch::Contains("key 'quasi_static.max_iterations' = 1.5: expected a whole number of iterations"));
  CHECK_THAT(error_of(head + "[quasi_static]\nload_factors = [1.0]\nmax_breaking_rounds = 2.0\n"),
             Catch::Contains("key 'quasi_static.max_breaking_rounds' = 2.0: expected a whole number of rounds"));
}

// Reference: the plate is a uniform lattice pulled at both ends; the run must
// write its files and report per step what docs/solver.md promises.
// Load steps given both ways, one of them by --set, which adds a key and
// cannot remove the scene's: the refusal says where each came from and how
// to give the steps instead (before 7 December 2026 it said neither, and a
// user who had written `--set quasi_static.increments=...` on a scene with a
// list saw a scene that, as written, gave only one).
TEST_CASE("quasi-static load steps given by the scene and by --set the other way are refused saying so",
          "[quasistatic][scene]") {
  const std::string list = head + "[quasi_static]\nload_factors = [0.5, 1.0]\n" + loads;
  const std::string runs = head + "[quasi_static]\nincrements = [[2, 0.5]]\n" + loads;
  const std::string what = "qs.toml: [quasi_static]: give exactly one of 'load_factors' (a list of load factors) or "
                           "'increments' ([[count, increment], ...]): both are given, ";
  CHECK(error_of(list, {"quasi_static.increments=[[300, 0.01]]"}) ==
        what + "'load_factors' at qs.toml:6 and 'increments' by --set; --set cannot remove the scene's key: give the "
               "load steps with it (--set 'quasi_static.load_factors=...'), or edit the scene");
  CHECK(error_of(runs, {"quasi_static.load_factors=[1.0]"}) ==
        what + "'load_factors' by --set and 'increments' at qs.toml:6; --set cannot remove the scene's key: give the "
               "load steps with it (--set 'quasi_static.increments=...'), or edit the scene");
  CHECK(error_of(head + "[quasi_static]\nload_factors = [1.0]\nincrements = [[2, 0.5]]\n" + loads) ==
        what + "'load_factors' at qs.toml:6 and 'increments' at qs.toml:7");
  CHECK(error_of(list, {"quasi_static.load_factors=[0.25, 0.5]"}).empty());
}

TEST_CASE("pd-solve runs a quasi-static scene and reports every load step", "[quasistatic][executable]") {
  const auto folder = pd::quasistatic::test::fresh_folder("executable");
  const auto plate = pd::make_rectangle_lattice(2e-3, 1e-3, 1e-4, 3e-4, pd::Quadrature::analytic);
  pd::write_particle_file(folder + "/plate.pdp", plate);
  {
    std::ofstream scene(folder + "/qs.toml");
    scene << head << "[effects]\ndamage = false\n[quasi_static]\nload_factors = [0.5, 1.0]\n[output]\n"
          << "snapshot_interval = 1\n" << loads;
  }
  const std::string out = folder + "/out";
  const std::string command = std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/qs.toml -o " + out + " > " +
                              folder + "/log.txt 2>&1";
  REQUIRE(std::system(command.c_str()) == 0);
  std::ifstream log(folder + "/log.txt");
  std::stringstream text;
  text << log.rdbuf();
  CHECK_THAT(text.str(), Catch::Contains("step 2: load factor 1,") && Catch::Contains("relative residual") &&
                             Catch::Contains("energy") && Catch::Contains("reaction"));
  for (const char* file : {pd::results::load_steps_file, pd::results::final_state_file, pd::results::summary_file,
                           pd::results::snapshot_collection})
    CHECK(std::filesystem::exists(std::filesystem::path(out) / file));
  std::ifstream csv(std::filesystem::path(out) / pd::results::load_steps_file);
  std::string header, row1, row2;
  std::getline(csv, header), std::getline(csv, row1), std::getline(csv, row2);
  CHECK_THAT(header, Catch::StartsWith("step,load_factor,minimisations,iterations,relative_residual"));
  CHECK_THAT(row2, Catch::StartsWith("2,1,1,"));

  // Non-convergence is an error naming the scene and the keys to change.
  const std::string failing = std::string(PD_SOLVE_EXECUTABLE) + " " + folder +
                              "/qs.toml --set quasi_static.max_iterations=1 --set quasi_static.tolerance=1e-12 -o " +
                              out + "2 > " + folder + "/fail.txt 2>&1";
  CHECK(std::system(failing.c_str()) != 0);
  std::ifstream fail(folder + "/fail.txt");
  std::stringstream fail_text;
  fail_text << fail.rdbuf();
  CHECK_THAT(fail_text.str(), Catch::Contains("qs.toml: load step 1") && Catch::Contains("not converged") &&
                                  Catch::Contains("quasi_static.max_iterations"));
}

// The loads' values are held to the material's and the plate's scales
// (docs/scenes.md, "Load values in another unit") at the largest load factor,
// which scales them: 1e-7 m at load factor 3000 is 0.3 mm on a 2 mm plate, a
// strain of 15 %. Before 7 December 2026 only their values at load factor 1
// were, and such a run went through without a word.
TEST_CASE("a quasi-static plan warns of a load that its largest load factor makes too large",
          "[quasistatic][executable]") {
  const auto plate =
      small_plate_run("large-load-factor", head + "[effects]\ndamage = false\n[quasi_static]\nload_factors = [1.0]\n" + loads);
  const std::string &folder = plate.folder, &out = plate.out, &log = plate.log;
  const auto run = [&](const std::string& factors) {
    return plate.run("--set 'quasi_static.load_factors=" + factors + "'");
  };
  REQUIRE(run("[0.5, 1.0]") == 0);
  CHECK_THAT(pd::test_support::file_text(log), !Catch::Contains("warning"));
  REQUIRE(run("[1000, -3000]") == 0);
  const std::string warning = "load 'right': at the largest load factor, 3000, a displacement of up to 0.0003 m is "
                              "0.15 times the plate's size";
  CHECK_THAT(pd::test_support::file_text(log),
             Catch::Contains("\n  warning:   " + warning) && Catch::Contains("displacements are in m (1 mm = 1e-3)"));
  CHECK_THAT(pd::test_support::file_text(out + "/" + pd::results::summary_file), Catch::Contains(warning));
  // A load factor at which the forces overflow: one line that says so and
  // names the key, with or without on_nonconvergence = "warn" (before 7
  // December 2026: "relative residual -nan > quasi_static.tolerance").
  for (const char* extra : {"", " --set 'quasi_static.on_nonconvergence=\"warn\"'"}) {
    INFO(extra);
    CHECK(pd::test_support::run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/qs.toml -q -o " + out +
                                      " --set 'quasi_static.load_factors=[1e300]'" + extra + " > " + log +
                                      " 2>&1") != 0);
    const std::string text = pd::test_support::file_text(log);
    CHECK_THAT(text, Catch::Contains("qs.toml: load step 1 (load factor 1e+300): the forces are no finite numbers: "
                                     "the loads at this load factor are too large for the arithmetic") &&
                         Catch::Contains("key 'quasi_static.load_factors'") && !Catch::Contains("nan"));
  }
  // A load factor at which the forces' squares underflow: refused as its
  // loads are applied (before 7 December 2026 the residual read 0, the step
  // took 0 iterations with the interior at rest, and the run ended as a
  // success, exit 0), with either kernels.
  for (const char* kernels : {"lists", "lattice"}) {
    INFO(kernels);
    CHECK(pd::test_support::run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/qs.toml -q -o " + out +
                                      " --set 'quasi_static.load_factors=[1e-300]' --set 'quasi_static.kernels=\"" +
                                      kernels + "\"' > " + log + " 2>&1") == 1);
    const std::string text = pd::test_support::file_text(log);
    CHECK_THAT(text, Catch::EndsWith("\npd-solve: error: " + folder + "/qs.toml: load step 1 (load factor 1e-300): the "
                                     "forces are too small for the arithmetic (their squares are below the smallest "
                                     "double): the minimisation could not measure them; check the load values and key "
                                     "'quasi_static.load_factors'\n") &&
                         !Catch::Contains("step 1: load factor"));
  }
  // ... refused as the step's loads are applied, before its minimisation
  // runs: at a later step too; before 7 December 2026 after that
  // minimisation, which with the lattice kernels took 28 rounds (15 dropped,
  // 13 damped; its progress line said so).
  for (const char* kernels : {"lists", "lattice"}) {
    INFO(kernels);
    CHECK(pd::test_support::run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/qs.toml -o " + out +
                                      " --set 'quasi_static.load_factors=[1, 1e300]' --set "
                                      "quasi_static.progress_interval=0 --set 'quasi_static.kernels=\"" +
                                      kernels + "\"' > " + log + " 2>&1") == 1);
    const std::string text = pd::test_support::file_text(log);
    CHECK_THAT(text, Catch::Contains("\nstep 1: load factor 1, ") &&
                         Catch::Contains("\npd-solve: error: " + folder +
                                         "/qs.toml: load step 2 (load factor 1e+300): the forces are no finite "
                                         "numbers") &&
                         !Catch::Contains("load step 2 (load factor 1e+300), minimisation") &&
                         !Catch::Contains("rounds dropped"));
    CHECK_THAT(pd::test_support::file_text(out + "/" + pd::results::load_steps_file),
               Catch::StartsWith("step,load_factor,") && Catch::Contains("\n1,1,1,") && !Catch::Contains("\n2,"));
  }
}

// The refusals of a load factor name the key the scene gave the load steps
// by: before 7 December 2026 they named 'quasi_static.load_factors' for a
// scene that gave 'increments'.
TEST_CASE("a quasi-static load factor refused names increments when the scene gave them",
          "[quasistatic][executable]") {
  const auto plate = small_plate_run("increments-key", head + "[effects]\ndamage = false\n[quasi_static]\n"
                                                              "increments = [[1, 1e300]]\n" + loads);
  CHECK(plate.run("") == 1);
  CHECK_THAT(pd::test_support::file_text(plate.log),
             Catch::Contains("qs.toml: load step 1 (load factor 1e+300): the forces are no finite numbers") &&
                 Catch::Contains("key 'quasi_static.increments'") && !Catch::Contains("load_factors"));
}

// A quasi-static run refused after its set-up has computed the
// surface-correction factors (here two loads that hold the same particles)
// leaves a folder that existed as it found it: before 7 December 2026 it
// gained the cache. The corrected run writes it.
TEST_CASE("a refused quasi-static run leaves no surface-correction cache in the folder", "[quasistatic][executable]") {
  namespace fs = std::filesystem;
  const auto plate = small_plate_run("refused-cache", head + "[effects]\ndamage = false\nsurface_correction = true\n" +
                                                          "[quasi_static]\nload_factors = [1.0]\n" + loads);
  const std::string &folder = plate.folder, &out = plate.out, &log = plate.log;
  fs::create_directories(out);
  std::ofstream(out + "/notes.txt") << "kept\n";
  const auto run = [&](const std::string& extra) { return plate.run(extra); };
  CHECK(run("--set 'loads=[{set = \"left\", type = \"displacement\", x = -1e-7}, {set = \"left\", type = "
            "\"fixed\", name = \"hold\"}]'") == 1);
  CHECK_THAT(pd::test_support::file_text(log),
             Catch::Contains("pd-solve: error: " + folder + "/qs.toml") && Catch::Contains("both constrain"));
  std::vector<std::string> entries;
  for (const auto& entry : fs::recursive_directory_iterator(out)) entries.push_back(entry.path().filename().string());
  CHECK(entries == std::vector<std::string>{"notes.txt"});
  REQUIRE(run("") == 0);
  CHECK(fs::is_regular_file(out + "/surface_correction.cache"));
}

// A traction that nothing holds against has no equilibrium: the plate would
// move off as a rigid body. Refused at set-up, naming the traction, the
// component and its resultant (1 MPa on a 2 mm edge, 1 m thick: 2000 N);
// before 7 December 2026 each minimisation ran to max_iterations (20000 by
// default) and the run failed advising more. Tractions that balance, or a
// support that holds that component, run.
TEST_CASE("a quasi-static traction that no load holds against is refused at set-up", "[quasistatic][executable]") {
  const auto plate = small_plate_run("unheld-traction", head + "[effects]\ndamage = false\n[quasi_static]\n" +
                                                            "load_factors = [1.0]\nmax_iterations = 300\n");
  const std::string &folder = plate.folder, &log = plate.log;
  const auto run = [&](const std::string& loads) { return plate.run("--set 'loads=[" + loads + "]'"); };
  const std::string pull = "{set = \"right\", type = \"traction\", x = 1e6, name = \"pull\"}";
  CHECK(run(pull) == 1);
  CHECK(pd::test_support::file_text(log) ==
        "pd-solve: error: " + folder + "/qs.toml: the traction 'pull' (traction on set 'right') pushes the plate along "
        "x with a resultant of 1000 N at load factor 1, and no load holds the x component of any particle: the plate "
        "has no equilibrium (it would move off as a rigid body, each minimisation running to "
        "quasi_static.max_iterations); hold it, e.g. a load of type = \"fixed\" on the opposite edge or a pin "
        "(nearest = [x, y], type = \"fixed\"), or balance the tractions\n");
  CHECK_FALSE(std::filesystem::exists(folder + "/out"));
  // A support that holds only y does not hold a pull along x.
  CHECK(run(pull + ", {set = \"left\", type = \"displacement\", y = 0}") == 1);
  CHECK_THAT(pd::test_support::file_text(log), Catch::Contains("no load holds the x component of any particle"));
  REQUIRE(run(pull + ", {set = \"left\", type = \"displacement\", x = 0}") == 0);
  REQUIRE(run(pull + ", {set = \"left\", type = \"traction\", x = -1e6}") == 0);
}

// A couple of tractions (top edge pushed along +x, bottom edge along -x: no
// resultant) on a plate held at one particle only: nothing resists the turn
// about that particle, and the plate has no equilibrium. Refused at set-up,
// naming the tractions, their moment (1e5 Pa x 2 mm x 1 m = 200 N on each
// edge's set, three rows of particles deep, whose centres lie at y = 0.85 and
// 0.15 mm: -200 N x 0.7 mm = -0.14 N m, clockwise, about any point) and the
// load that holds. Before 7
// December 2026 each minimisation ran to max_iterations (here 2000) and the
// run failed advising more. A second held point, or x held along a line of
// heights (a roller edge), resists the turn and runs; so does a pull whose
// line of action passes through the pin.
TEST_CASE("a quasi-static couple that nothing holds against turning is refused at set-up", "[quasistatic][executable]") {
  const auto plate = small_plate_run("unheld-couple", head + "[effects]\ndamage = false\n[quasi_static]\n" +
                                                          "load_factors = [1.0]\nmax_iterations = 2000\n");
  const std::string &folder = plate.folder, &log = plate.log;
  const auto run = [&](const std::string& loads) { return plate.run("--set 'loads=[" + loads + "]'"); };
  const std::string pin = "{name = \"pin\", nearest = [0.001, 0.0005], type = \"fixed\"}";
  const std::string couple = "{name = \"top\", set = \"top\", type = \"traction\", x = 1e5}, "
                             "{name = \"bottom\", set = \"bottom\", type = \"traction\", x = -1e5}";
  CHECK(run(pin + ", " + couple) == 1);
  CHECK(pd::test_support::file_text(log) ==
        "pd-solve: error: " + folder + "/qs.toml: the tractions 'top' (traction on set 'top'), 'bottom' (traction on "
        "set 'bottom') turn the plate with a moment of -0.14 N m at load factor 1 about (0.95, 0.45) mm, and the load "
        "'pin' (fixed on the particle nearest to [0.001, 0.0005]) that holds the plate leaves it free to turn about "
        "that point (it holds x components only at y = 0.45 mm and y components only at x = 0.95 mm): the plate has "
        "no equilibrium (it would turn as a rigid body, each minimisation running to quasi_static.max_iterations); "
        "hold a second point away from it, e.g. a load of type = \"fixed\" on an edge, or balance the tractions' "
        "moment\n");
  CHECK_FALSE(std::filesystem::exists(folder + "/out"));
  // No load holding anything at all: the same turn, about the tractions' centre.
  CHECK(run(couple) == 1);
  CHECK_THAT(pd::test_support::file_text(log),
             Catch::Contains("turn the plate with a moment of -0.14 N m at load factor 1 about (1, 0.5) mm, and no "
                             "load holds any particle: the plate has no equilibrium"));
  // Held at a second point: the turn is resisted.
  REQUIRE(run(pin + ", {name = \"roller\", nearest = [0.0, 0.0005], type = \"displacement\", y = 0}, " + couple) ==
          0);
  // x held along the left edge (heights 0.05 to 0.95 mm) and y at the pin.
  REQUIRE(run("{set = \"left\", type = \"displacement\", x = 0}, {nearest = [0.0, 0.0005], type = \"displacement\", "
              "y = 0, name = \"pin_y\"}, " + couple) == 0);
  // Balanced pulls along the pin's own line: no moment, and the free turn is harmless.
  REQUIRE(run("{name = \"pin\", nearest = [0.001, 0.00045], type = \"fixed\"}, {set = \"right\", type = "
              "\"traction\", x = 1e5}, {set = \"left\", type = \"traction\", x = -1e5}") == 0);
}

// Constraints that give every particle they hold the same displacement, and
// no traction: the plate follows them rigidly and the run computes nothing
// (a support forgotten). The plan and summary.json warn, naming the loads
// (before 7 December 2026 the run ended as a success without a word); a
// support that holds another part otherwise, or fixed supports alone
// (warned as a plate at rest), as said.
TEST_CASE("a quasi-static plan warns of constraints the whole plate follows rigidly", "[quasistatic][executable]") {
  const auto plate =
      small_plate_run("rigid-loads", head + "[effects]\ndamage = false\n[quasi_static]\nload_factors = [1.0]\n");
  const std::string &out = plate.out, &log = plate.log;
  const auto run = [&](const std::string& loads) { return plate.run("--set 'loads=[" + loads + "]'"); };
  const std::string pull = "{set = \"right\", type = \"displacement\", x = 1e-7, name = \"pull\"}";
  REQUIRE(run(pull) == 0);
  const std::string warning =
      "the constraint 'pull' (displacement on set 'right') prescribes the same displacement, (1e-07, free) m at load "
      "factor 1, to every particle it holds, and no traction acts: the whole plate follows rigidly and carries no "
      "load (strain energy 0 at every step); hold another part of it otherwise, e.g. a load of type = \"fixed\" on "
      "the opposite edge (docs/scenes.md, [[loads]])";
  CHECK_THAT(pd::test_support::file_text(log), Catch::Contains("\n  warning:   " + warning + "\n"));
  // (summary.json escapes the quotes of "fixed".)
  CHECK_THAT(pd::test_support::file_text(out + "/" + pd::results::summary_file),
             Catch::Contains(warning.substr(0, warning.find("type = "))));
  REQUIRE(run("{set = \"left\", type = \"fixed\", name = \"hold\"}") == 0);
  CHECK_THAT(pd::test_support::file_text(log),
             Catch::Contains("the constraint 'hold' (fixed on set 'left') prescribes the same displacement, (0, 0) m at "
                             "load factor 1, to every particle it holds, and no traction acts: the whole plate stays "
                             "at rest"));
  REQUIRE(run(pull + ", {set = \"left\", type = \"fixed\"}") == 0);
  CHECK_THAT(pd::test_support::file_text(log), !Catch::Contains("warning"));
  // The same displacement on both edges is still a translation; another value is not.
  REQUIRE(run(pull + ", {set = \"left\", type = \"displacement\", x = 1e-7}") == 0);
  CHECK_THAT(pd::test_support::file_text(log), Catch::Contains("follows rigidly"));
  REQUIRE(run(pull + ", {set = \"left\", type = \"displacement\", x = -1e-7}") == 0);
  CHECK_THAT(pd::test_support::file_text(log), !Catch::Contains("warning"));
}

// quasi_static.stop_reaction_fraction stops on a load cell reading (the
// displacement loads' reaction) that falls as bonds break: without damage,
// or without a displacement load that moves its set, it can never stop the
// run. The plan and summary.json say so (before 7 December 2026 the key was
// taken without a word).
TEST_CASE("a quasi-static plan warns of a stop_reaction_fraction that cannot stop the run",
          "[quasistatic][executable]") {
  const auto plate = small_plate_run(
      "idle-stop-fraction", head + "[quasi_static]\nload_factors = [1.0]\nstop_reaction_fraction = 0.05\n" + loads);
  const std::string &out = plate.out, &log = plate.log;
  const auto run = [&](const std::string& extra) { return plate.run(extra); };
  REQUIRE(run("--set effects.damage=false") == 0);
  const std::string without_damage = "quasi_static.stop_reaction_fraction = 0.05 has no effect: with effects.damage = "
                                     "false no bond breaks, and the sample never separates; leave it out";
  CHECK_THAT(pd::test_support::file_text(log), Catch::Contains("\n  warning:   " + without_damage));
  CHECK_THAT(pd::test_support::file_text(out + "/" + pd::results::summary_file), Catch::Contains(without_damage));
  // Supports alone under a traction: their reaction balances the traction at
  // every equilibrium. A fixed edge, and (until 7 December 2026 without a
  // word) a displacement of 0 along x.
  const std::string supports_only =
      "\n  warning:   quasi_static.stop_reaction_fraction = 0.05 has no effect: it compares the reaction of the "
      "displacement loads that move their set (the load cell) with its peak, and no load of type = \"displacement\" "
      "moves its set (the supports' reaction, fixed loads' or displacements' of 0, balances the tractions at every "
      "equilibrium and does not fall as bonds break); pull with a displacement load, or stop on damage with a [stop] "
      "region (docs/scenes.md)\n";
  for (const std::string support : {"type = \"fixed\"", "type = \"displacement\", x = 0"}) {
    INFO(support);
    REQUIRE(run("--set 'loads=[{set = \"right\", type = \"traction\", x = 1e5}, {set = \"left\", " + support +
                "}]'") == 0);
    CHECK_THAT(pd::test_support::file_text(log), Catch::Contains(supports_only));
  }
  REQUIRE(run("") == 0);
  CHECK_THAT(pd::test_support::file_text(log), !Catch::Contains("warning"));
}

// A [stop] region the pre-cracks already damage would end the run after its
// first load step as if a crack had reached it: refused before the plan, as
// a dynamic run refuses it (before 7 December 2026: one load step, "stop
// condition", exit 0). A region ahead of the pre-crack runs.
TEST_CASE("a quasi-static stop condition that the pre-cracks already meet is refused", "[quasistatic][executable]") {
  const auto plate = small_plate_run("stop-at-start", head + "[quasi_static]\nload_factors = [1.0]\n" + loads +
                                                          "[[precracks]]\nfrom = [0.0, 0.0005]\nto = [0.001, 0.0005]\n" +
                                                          "[stop]\nbox = [0.0003, 0.0004, 0.0007, 0.0006]\ndamage = 0.2\n");
  const std::string &folder = plate.folder, &out = plate.out, &log = plate.log;
  const auto run = [&](const std::string& extra) { return plate.run(extra); };
  CHECK(run("") == 1);
  const std::string text = pd::test_support::file_text(log);
  CHECK_THAT(text, Catch::StartsWith("pd-solve: error: " + folder + "/qs.toml: table [stop]: damage >= 0.2 in box [") &&
                       Catch::Contains("] holds before the first load step (damage ") &&
                       Catch::EndsWith(" there at the start, from the pre-cracks): the run would stop at once; choose "
                                       "a region the crack has to reach, or a higher stop.damage\n"));
  CHECK_FALSE(std::filesystem::exists(out));
  REQUIRE(run("--set 'stop.box=[0.0015, 0.0004, 0.0019, 0.0006]'") == 0);
  CHECK_THAT(pd::test_support::file_text(log), Catch::Contains("done: 1 load step (last load step)"));
}

// load_steps.csv is rewritten whole (atomically, synced) at most once a second
// between snapshots (quasi_static_run.cpp; before the third sitting of 5 December 2026 after every
// load step: 8,000 steps of a 50-particle plate took 66 s instead of 0.35 s).
// Every completed step's row must still reach it: at the end of a run of fast
// steps, and when a later step fails (here bonds still breaking after
// max_breaking_rounds = 1 at a jump of the load factor from 3 to 1003).
TEST_CASE("load_steps.csv holds every completed load step, also when a later step fails",
          "[quasistatic][executable]") {
  const auto folder = pd::quasistatic::test::fresh_folder("rows_kept");
  const auto plate = pd::make_rectangle_lattice(2e-3, 1e-3, 1e-4, 3e-4, pd::Quadrature::analytic);
  pd::write_particle_file(folder + "/plate.pdp", plate);
  {
    std::ofstream scene(folder + "/qs.toml");
    scene << head << "[quasi_static]\nincrements = [[300, 0.01], [1, 1000]]\nmax_breaking_rounds = 1\n" << loads;
  }
  const auto rows_of = [](const std::string& out) {
    std::ifstream csv(std::filesystem::path(out) / pd::results::load_steps_file);
    std::vector<std::string> lines;
    for (std::string line; std::getline(csv, line);) lines.push_back(line);
    return lines;
  };
  const std::string run = std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/qs.toml -q -o ";
  const std::string failed = folder + "/failed", finished = folder + "/finished";
  CHECK(std::system((run + failed + " > " + folder + "/log.txt 2>&1").c_str()) != 0);
  const auto failed_rows = rows_of(failed);
  REQUIRE(failed_rows.size() == 301);  // the header and steps 1 to 300
  // (300 increments of 0.01 end at 3, written exactly since 7 December 2026.)
  CHECK_THAT(failed_rows.back(), Catch::StartsWith("300,3,"));
  // The same steps without the failing one: all 300 rows, the same bytes.
  CHECK(std::system((run + finished + " --set 'quasi_static.increments=[[300, 0.01]]' > " + folder +
                     "/log2.txt 2>&1").c_str()) == 0);
  CHECK(rows_of(finished) == failed_rows);
}

// A quasi-static plan is held to the limits of a dynamic run's (plan_limits.hpp,
// docs/scenes.md): its load steps' least cost (4 bond sweeps each at the sweep
// timed at set-up) in the plan, a warning beyond a day, refused beyond a year
// even at 1e10 directed bond evaluations per second; more than 10,000
// snapshot files a plan warning, snapshots beyond the free disk refused before
// the folder changes. Before the second sitting of 5 December 2026
// `increments = [[10000000, 1e-9]]` with output.snapshot_interval = 1 started
// writing 1e7 snapshots (169 GB for the user's plate) without a word.
TEST_CASE("a quasi-static plan is held to the limits of a dynamic run's", "[quasistatic][executable]") {
  using namespace pd::solver;
  // The count: 1e5 load steps at 1 s per sweep are days; after a restart, those left.
  // A load step sweeps the bonds 4 times at the least (solve_quasi_static): the
  // residual at its start that refuses forces that are no numbers, the
  // minimisation's first residual, and the strain and potential energies of its
  // row: 1e5 x 4 x 1 s = 4.62963 days. (Before 7 December 2026 the plan counted
  // 3, leaving out the first, and said 3.47222 days.)
  Scene scene = pd::quasistatic::test::quasi_static_scene();
  scene.quasi_static.load_factors.assign(100000, 1.0);
  const RunLength days = load_step_length(scene, 1e6, 0, 1.0);
  CHECK(days.description ==
        "quasi_static.load_factors / increments: 100000 load steps; at the 1 s per bond sweep measured at set-up and "
        "at least 4 sweeps per load step (2 more per NCG iteration) that is at least about 4.62963 days");
  CHECK(check_run_length(days, "qs.toml") == days.description);
  CHECK(check_run_length(load_step_length(scene, 1e6, 0, 0.1), "qs.toml").empty());  // 0.46 days
  const RunLength left = load_step_length(scene, 1e6, 99000, 1.0);
  CHECK_THAT(left.description, Catch::StartsWith("quasi_static.load_factors / increments: 100000 load steps, 1000 of "
                                                 "them after the checkpoint's 99000; "));
  CHECK(check_run_length(left, "qs.toml").empty());
  // 1e7 load steps of 2e10 directed bonds, 4 sweeps each: 926 days of sweeps at 1e10 per second.
  scene.quasi_static.load_factors.assign(10000000, 1.0);
  CHECK_THROWS_WITH(check_run_length(load_step_length(scene, 2e10, 0, 1e-3), "qs.toml"),
                    Catch::StartsWith("qs.toml: quasi_static.load_factors / increments: 10000000 load steps; ") &&
                        Catch::EndsWith(" (925.926 days even at 1e10 directed bond evaluations per second); refused "
                                        "(give fewer load steps: quasi_static.load_factors or increments)"));

  // pd-solve: 20,000 snapshots of a 200-particle plate (160 MB, not written) are a plan warning.
  const auto folder = pd::quasistatic::test::fresh_folder("plan-limits");
  pd::write_particle_file(folder + "/plate.pdp",
                          pd::make_rectangle_lattice(2e-3, 1e-3, 1e-4, 3e-4, pd::Quadrature::analytic));
  pd::write_particle_file(folder + "/large.pdp",
                          pd::make_rectangle_lattice(20e-3, 10e-3, 1e-4, 3e-4, pd::Quadrature::analytic));
  const std::string path = folder + "/qs.toml";
  std::ofstream(path) << head << "[effects]\ndamage = false\nsurface_correction = false\n[quasi_static]\n"
                      << "increments = [[20000, 1e-6]]\n[output]\nsnapshot_interval = 1\n" << loads;
  const std::string log = folder + "/log.txt";
  const pid_t child = pd::test_support::start_process({PD_SOLVE_EXECUTABLE, path, "-q", "-o", folder + "/out"}, log);
  REQUIRE(child > 0);
  for (int wait = 0; wait < 6000 && pd::test_support::file_text(log).find("  output:") == std::string::npos; ++wait)
    ::usleep(10000);
  ::kill(child, SIGINT);
  ::waitpid(child, nullptr, 0);
  std::string text = pd::test_support::file_text(log);
  INFO(text);
  CHECK_THAT(text, Catch::Contains("\n  warning:   " + path + ": key 'output.snapshot_interval' = 1: 20000 snapshots "
                                   "of about 0.008 MB each (160 MB) from load step 1 to 20000: that many files\n") &&
                       // (The plan writes the factors exactly since 7 December 2026; 20000
                       // increments of 1e-6 end at 0.02, each factor its place times 1e-6.)
                       Catch::Contains("\n  steps:     20000 load steps, load factor 1e-06 -> 0.02, "
                                       "at least about "));

  // 1e7 snapshots of 20,000 particles (8 TB): refused before the folder changes.
  const std::string refused = folder + "/refused";
  CHECK(pd::test_support::run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + path + " -o " + refused +
                                    " --set particles=" + folder + "/large.pdp --set 'quasi_static.increments=[[10000000, 1e-9]]' "
                                    "--set output.checkpoint_interval=1 > " + log + " 2>&1") == 1);
  text = pd::test_support::file_text(log);
  CHECK_THAT(text, Catch::Contains("pd-solve: error: " + path + ": key 'output.snapshot_interval' = 1: 10000000 "
                                   "snapshots of about 0.8 MB each (8 TB) from load step 1 to 10000000 and a "
                                   "checkpoint of about ") &&
                       Catch::Contains(" free under " + refused + "; raise the interval, give fewer load steps or "
                                       "free disk space\n"));
  CHECK_FALSE(std::filesystem::exists(refused + "/" + pd::results::load_steps_file));
}

// A load factor that scales a nonzero load to 0 or to a subnormal double
// (increments = [[2, 1e-320]] on 1e-7 m): before 7 December 2026 the steps
// applied no load, took 0 iterations, and the run ended as a success with the
// plate at rest, exit 0. Refused at the step, naming the load, its value and
// the key the scene gave the steps by.
TEST_CASE("a quasi-static load factor that scales a load to 0 or a subnormal value is refused",
          "[quasistatic][executable]") {
  const auto plate = small_plate_run("lost-load", head + "[effects]\ndamage = false\n[quasi_static]\n"
                                                         "increments = [[2, 1e-320]]\n" + loads);
  CHECK(plate.run("") == 1);
  // The subnormal factor as written (before 7 December 2026 quoted as the
  // double's first 6 digits, 9.99989e-321).
  CHECK_THAT(pd::test_support::file_text(plate.log),
             Catch::EndsWith("\npd-solve: error: " + plate.folder + "/qs.toml: load step 1 (load factor "
                             "1e-320): the load 'left' has the value -1e-07, which this load factor scales to "
                             "0: the arithmetic loses the load, and the step would run unloaded; check the load "
                             "values and key 'quasi_static.increments'\n") &&
                 !Catch::Contains("step 1: load factor"));
  // No load step done.
  const std::string steps = plate.out + "/" + pd::results::load_steps_file;
  CHECK_THAT(std::filesystem::exists(steps) ? pd::test_support::file_text(steps) : std::string(),
             !Catch::Contains("\n1,"));
  // A subnormal value, at a later step, under load_factors.
  const auto listed = small_plate_run("lost-load-factors", head + "[effects]\ndamage = false\n[quasi_static]\n"
                                                                  "load_factors = [1.0]\n" + loads);
  // A later step removes the load that the one before applied: the plate
  // relaxes, it does not run unloaded (before 7 December 2026 said as at the
  // first step).
  CHECK(listed.run("--set 'quasi_static.load_factors=[1, 1e-302]'") == 1);
  CHECK_THAT(pd::test_support::file_text(listed.log),
             Catch::EndsWith("\npd-solve: error: " + listed.folder + "/qs.toml: load step 2 (load factor 1e-302): the "
                             "load 'left' has the value -1e-07, which this load factor scales to -1e-309, below the "
                             "smallest normal double (2.22507e-308): the arithmetic loses the load, and "
                             "the load would be removed at load step 2, the plate relaxing towards its unloaded "
                             "state from load step 1's load factor 1; check the load values and key "
                             "'quasi_static.load_factors'\n"));
  // A step after one at load factor 0 had no load to remove: as at the first.
  CHECK(listed.run("--set 'quasi_static.load_factors=[0, 1e-320]'") == 1);
  CHECK_THAT(pd::test_support::file_text(listed.log),
             Catch::EndsWith("qs.toml: load step 2 (load factor 1e-320): the load 'left' has the value -1e-07, which "
                             "this load factor scales to 0: the arithmetic loses the load, and the step would run "
                             "unloaded; check the load values and key 'quasi_static.load_factors'\n"));
}

// Keys the scene's other choices leave without effect are warned about in
// the plan and summary.json's warnings, naming the key, its line and value
// (before 7 December 2026 taken without a word): the lattice kernels'
// settings on the energy table, max_breaking_rounds without damage.
TEST_CASE("quasi-static keys that the kernels or damage leave without effect are warned about",
          "[quasistatic][scene]") {
  const std::string keys = "coarse_correction = false\ndamped_rounds = false\nmax_breaking_rounds = 5\n";
  const auto inert = parse_scene(head + "[effects]\ndamage = false\n[quasi_static]\nload_factors = [1.0]\n" + keys +
                                 loads, "qs.toml").quasi_static.inert_keys;
  CHECK(inert == std::vector<std::string>{
                     "qs.toml:9: key 'quasi_static.coarse_correction' = false has no effect with "
                     "quasi_static.kernels = \"lists\": it sets the coarse-space correction of the lattice kernels' "
                     "preconditioner; leave it out, or set kernels = \"lattice\"",
                     "qs.toml:10: key 'quasi_static.damped_rounds' = false has no effect with quasi_static.kernels = "
                     "\"lists\": it sets the lattice kernels' damped Newton rounds after a dropped round; leave it "
                     "out, or set kernels = \"lattice\"",
                     "qs.toml:11: key 'quasi_static.max_breaking_rounds' = 5 has no effect with effects.damage = "
                     "false: no bond breaks, so no load step re-equilibrates; leave it out, or turn damage on"});
  // Where they act, no word; nor for keys left out.
  CHECK(parse_scene(head + "[quasi_static]\nload_factors = [1.0]\nkernels = \"lattice\"\n" + keys + loads, "qs.toml")
            .quasi_static.inert_keys.empty());
  CHECK(parse_scene(head + "[effects]\ndamage = false\n[quasi_static]\nload_factors = [1.0]\n" + loads, "qs.toml")
            .quasi_static.inert_keys.empty());
  // In the plan and summary.json's warnings, from --set too.
  const auto plate = small_plate_run("inert-keys", head + "[effects]\ndamage = false\n[quasi_static]\n"
                                                          "load_factors = [1.0]\n" + loads);
  REQUIRE(plate.run("--set quasi_static.coarse_correction=false") == 0);
  const std::string warning = plate.folder + "/qs.toml, --set: key 'quasi_static.coarse_correction' = false has no "
                              "effect with quasi_static.kernels = \"lists\": it sets the coarse-space correction of "
                              "the lattice kernels' preconditioner; leave it out, or set kernels = \"lattice\"";
  CHECK_THAT(pd::test_support::file_text(plate.log), Catch::Contains("\n  warning:   " + warning + "\n"));
  CHECK_THAT(pd::test_support::file_text(plate.out + "/" + pd::results::summary_file),
             Catch::Contains(pd::json_string(warning)));
}

// A load factor that loses one load while another still acts: the step
// runs without that load, not unloaded, and a later step removes it while
// the other still acts (before 7 December 2026 both said as if no load were
// left: 'the step would run unloaded', 'the plate relaxing towards its
// unloaded state').
TEST_CASE("a quasi-static load factor that loses one load names it and the loads still acting",
          "[quasistatic][executable]") {
  const std::string two_sizes = R"(
[[loads]]
set = "left"
type = "displacement"
x = -1e-7
[[loads]]
set = "right"
type = "displacement"
x = 1e-4
)";
  const auto plate = small_plate_run("lost-one-load", head + "[effects]\ndamage = false\n[quasi_static]\n"
                                                             "load_factors = [1e-302]\n" + two_sizes);
  CHECK(plate.run("") == 1);
  CHECK_THAT(pd::test_support::file_text(plate.log),
             Catch::EndsWith("\npd-solve: error: " + plate.folder + "/qs.toml: load step 1 (load factor 1e-302): the "
                             "load 'left' has the value -1e-07, which this load factor scales to -1e-309, below the "
                             "smallest normal double (2.22507e-308): the arithmetic loses the load, and the step "
                             "would run without the load 'left' while the load 'right' still acts; check the load "
                             "values and key 'quasi_static.load_factors'\n"));
  CHECK(plate.run("--set 'quasi_static.load_factors=[1, 1e-302]'") == 1);
  CHECK_THAT(pd::test_support::file_text(plate.log),
             Catch::EndsWith("qs.toml: load step 2 (load factor 1e-302): the load 'left' has the value -1e-07, which "
                             "this load factor scales to -1e-309, below the smallest normal double (2.22507e-308): "
                             "the arithmetic loses the load, and the load would be removed at load step 2 (from load "
                             "step 1's load factor 1) while the load 'right' still acts; check the load values and "
                             "key 'quasi_static.load_factors'\n"));
}

// Load factors are quoted as the scene gives them, in the shortest text that
// reads back to the same double: before 7 December 2026 the progress lines,
// the step lines, the plan and the non-convergence message printed 6
// significant digits (0.1234567 as 0.123457) and load_steps.csv 12, so that
// two load steps 1e-14 apart showed the same factor.
TEST_CASE("quasi-static load factors are printed round-trip exactly in progress lines and messages and load_steps.csv",
          "[quasistatic][executable]") {
  const auto plate = small_plate_run("exact-load-factors",
                                     head + "[effects]\ndamage = false\n[quasi_static]\n"
                                            "load_factors = [0.1234567, 0.12345670000001]\nmax_iterations = 1\n"
                                            "on_nonconvergence = \"warn\"\nprogress_interval = 0\n" + loads);
  // (Without -q: the progress lines too.)
  REQUIRE(pd::test_support::run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + plate.folder + "/qs.toml -o " +
                                      plate.out + " > " + plate.log + " 2>&1") == 0);
  const std::string text = pd::test_support::file_text(plate.log);
  INFO(text);
  CHECK_THAT(text, Catch::Contains("  steps:     2 load steps, load factor 0.1234567 -> 0.12345670000001, ") &&
                       Catch::Contains("\nload step 2 (load factor 0.12345670000001), minimisation 1: iteration ") &&
                       Catch::Contains("qs.toml: load step 2 (load factor 0.12345670000001), minimisation 1: not "
                                       "converged after 1 iterations") &&
                       Catch::Contains("\nstep 1: load factor 0.1234567, ") &&
                       Catch::Contains("\nstep 2: load factor 0.12345670000001, ") && !Catch::Contains("0.123457"));
  const std::string steps = pd::test_support::file_text(plate.out + "/" + pd::results::load_steps_file);
  CHECK_THAT(steps, Catch::Contains("\n1,0.1234567,1,1,") && Catch::Contains("\n2,0.12345670000001,1,1,"));
  // summary.json's numbers too (before 7 December 2026 with 12 digits: 0.1234567).
  CHECK_THAT(pd::test_support::file_text(plate.out + "/" + pd::results::summary_file),
             Catch::Contains("\"final_load_factor\": 0.12345670000001,"));
}

// The rule is exact: a factor that leaves the value a normal double, however
// small, passes; the next one down that makes it subnormal does not.
TEST_CASE("value_lost_at_factor flags only loads scaled to 0 or to subnormal doubles", "[quasistatic][loads]") {
  pd::solver::ResolvedLoad load;
  load.spec.kind = pd::solver::LoadKind::displacement;
  load.spec.has_x = true;
  load.particles = {0, 1};
  load.value_x = {0.0, 1.0};
  const double smallest = std::numeric_limits<double>::min();
  CHECK(pd::solver::value_lost_at_factor(load, smallest) == 0);
  CHECK(pd::solver::value_lost_at_factor(load, -smallest) == 0);
  CHECK(pd::solver::value_lost_at_factor(load, 0.0) == 0);
  CHECK(pd::solver::value_lost_at_factor(load, std::nextafter(smallest, 0.0)) == 1.0);
  CHECK(pd::solver::value_lost_at_factor(load, 1e-320) == 1.0);
  load.value_x = {0.0, 4.0};
  CHECK(pd::solver::value_lost_at_factor(load, smallest / 4) == 0);
  CHECK(pd::solver::value_lost_at_factor(load, std::nextafter(smallest / 4, 0.0)) == 4.0);
  // y given, x not: only the components the load prescribes.
  load.spec.has_x = false;
  load.spec.has_y = true;
  load.value_y = {1e-300, 0.0};
  CHECK(pd::solver::value_lost_at_factor(load, 1e-7) == 0);
  CHECK(pd::solver::value_lost_at_factor(load, 1e-8) == 1e-300);
  CHECK(pd::solver::value_lost_at_factor(load, 2.3e-8) == 0);
  load.spec.kind = pd::solver::LoadKind::fixed;
  CHECK(pd::solver::value_lost_at_factor(load, 1e-320) == 0);
}

// An existing output folder whose name ends in a space is the user's and is
// taken, with a plan warning that names it quoted, also in summary.json
// (before 7 December 2026 without a word: the space unseen, the run's files
// were looked for in the folder without it).
TEST_CASE("pd-solve warns of an existing output folder whose name ends in a space, and runs into it",
          "[quasistatic][executable]") {
  namespace fs = std::filesystem;
  const auto plate = small_plate_run("spaced-folder", head + "[effects]\ndamage = false\n[quasi_static]\n"
                                                             "load_factors = [1.0]\n" + loads);
  const std::string spaced = plate.out + " ";
  fs::create_directories(spaced);
  CHECK(pd::test_support::run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + plate.folder + "/qs.toml -q -o '" +
                                    spaced + "' > " + plate.log + " 2>&1") == 0);
  const std::string warning = "-o '" + spaced + "': the name ends in a space; the folder of that name exists and is "
                              "used (" + plate.out + ", without it, is another name)";
  const std::string log = pd::test_support::file_text(plate.log);
  CHECK_THAT(log, Catch::Contains("\n  warning:   " + warning + "\n"));
  CHECK_THAT(pd::test_support::file_text(spaced + "/" + pd::results::summary_file), Catch::Contains(warning));
  CHECK_FALSE(fs::exists(plate.out));
}
