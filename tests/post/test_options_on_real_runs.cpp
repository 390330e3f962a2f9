// Options that do not fit the run, on small real runs made by pd-mesh and
// pd-solve: pd-post says what it drew instead, or why it cannot, rather
// than draw another state or drop the option without a word.
#include <algorithm>
#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <vtkPolyData.h>

#include "results_format.hpp"
#include "solver_summary.hpp"
#include "synthetic_output.hpp"
#include "vtp_input.hpp"
#include "../test_commands.hpp"

using pd::post::test::fresh_dir;
using pd::test_support::file_text;
using pd::test_support::run_shell;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

struct ToolRun {
  int status = 0;
  std::string out, err;
};

// Runs `tool` with `arguments` (already quoted where needed) in `dir`'s logs.
ToolRun run_tool(const std::string& tool, const std::string& arguments, const std::string& log_dir) {
  const std::string out = log_dir + "/stdout.txt", err = log_dir + "/stderr.txt";
  ToolRun r;
  r.status = run_shell("'" + tool + "' " + arguments + " > '" + out + "' 2> '" + err + "'");
  r.out = file_text(out);
  r.err = file_text(err);
  return r;
}

ToolRun pd_post(const std::string& outdir, const std::string& arguments) {
  const std::string post = outdir + "_post";
  fs::create_directories(post);
  return run_tool(PD_POST_EXECUTABLE, "'" + outdir + "' -o '" + post + "' " + arguments, post);
}

// The centre-cracked plate (500 mm square) at a 10 mm spacing, meshed and
// solved quasi-statically into DIR/run with `options` (--set ...).
ToolRun centre_crack_plate_run(const std::string& dir, const std::string& options) {
  const std::string geometry = std::string(PD_GEOMETRY_DIR);
  const std::string particles = dir + "/plate.pdp";
  REQUIRE(run_tool(PD_MESH_EXECUTABLE, "'" + geometry + "/centre_crack_plate.geo' --grid uniform --spacing 10mm "
                   "--horizon 30mm -o '" + particles + "'", dir).status == 0);
  return run_tool(PD_SOLVE_EXECUTABLE, "'" + geometry + "/centre_crack_plate.toml' -o '" + dir + "/run' --set "
                  "'particles=" + particles + "' " + options + " --threads 1 -q", dir);
}

// That plate's quasi-static run: two load steps, snapshots at load factors 0.1 and 0.2.
std::string quasi_static_run(const std::string& dir, const std::string& extra = "") {
  const ToolRun solve = centre_crack_plate_run(
      dir, "--set model.osb_failure=force_only --set 'quasi_static.increments=[[2, 0.1]]' --set "
           "quasi_static.tolerance=1e-6 --set output.snapshot_interval=1 " + extra);
  INFO(solve.err);
  REQUIRE(solve.status == 0);
  return dir + "/run";
}

// The single-edge-notch strip (20 x 40 mm) at a 0.5 mm spacing, dynamic,
// up to `end_time` (its crack crosses the strip at about 260 us), of
// `scene` (default geometries/sen_strip.toml).
std::string dynamic_run(const std::string& dir, const std::string& end_time, std::string scene = "") {
  const std::string geometry = std::string(PD_GEOMETRY_DIR);
  const std::string particles = dir + "/strip.pdp", outdir = dir + "/run";
  if (scene.empty()) scene = geometry + "/sen_strip.toml";
  REQUIRE(run_tool(PD_MESH_EXECUTABLE, "'" + geometry + "/sen_strip.geo' --spacing 0.5mm --horizon 2mm -o '" +
                   particles + "'", dir).status == 0);
  const ToolRun solve = run_tool(PD_SOLVE_EXECUTABLE, "'" + scene + "' -o '" + outdir +
                                 "' --set 'particles=" + particles + "' --set time.end=" + end_time +
                                 " --set output.checkpoint_interval=100 --threads 1 -q", dir);
  INFO(solve.err);
  REQUIRE(solve.status == 0);
  return outdir;
}

}  // namespace

TEST_CASE("a quasi-static run: load factors it has no snapshot of, dynamic options, a line off the plate",
          "[real-run][quasi-static]") {
  const std::string run = quasi_static_run(fresh_dir("real_quasi_static"));

  SECTION("a load factor between snapshots: a note names the snapshot drawn and its load factor") {
    const ToolRun r = pd_post(run, "--load-factors 0.15,0.2");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Contains("pd-post: note: --load-factors 0.15: no snapshot at that load factor; the maps show "
                               "the nearest, " + run + "/snapshots/step_00000001.vtp, at load factor 0.1"));
    // 0.2 is a snapshot's: nothing to say.
    CHECK(r.err.find("--load-factors 0.2") == std::string::npos);
  }
  SECTION("a load factor given twice: drawn once, with one note") {
    // Before 7 December 2026 drawn twice, its note printed twice and listed
    // twice in summary.json's maps.
    const ToolRun r = pd_post(run, "--load-factors 0.15,0.15,0.2,0.2");
    INFO(r.err);
    CHECK(r.status == 0);
    const auto count = [](const std::string& text, const std::string& part) {
      std::size_t n = 0;
      for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
      return n;
    };
    CHECK(count(r.err, "pd-post: note: --load-factors 0.15: no snapshot at that load factor") == 1);
    const std::string summary = file_text(run + "_post/summary.json");
    CHECK(count(summary, "\"requested_load_factor\": 0.15") == 1);
    CHECK(count(summary, "\"requested_load_factor\": 0.2") == 1);
  }
  SECTION("a snapshot moved over another: its load factor against snapshots.pvd's, refused") {
    // Before 6 December 2026 the map "at 0.1" showed load factor 0.2's state.
    fs::copy_file(run + "/snapshots/step_00000002.vtp", run + "/snapshots/step_00000001.vtp",
                  fs::copy_options::overwrite_existing);
    const ToolRun r = pd_post(run, "--load-factors 0.1");
    CHECK(r.status != 0);
    CHECK(r.err == "pd-post: error: " + run + "/snapshots/step_00000001.vtp: is of load factor 0.2 (field "
                   "'load_factor'), and " + run + "/snapshots.pvd lists it at load factor 0.1: the two files are "
                   "from different runs (a folder mixed by copying or moving files); give the folder that one "
                   "pd-solve run wrote whole, or run pd-solve again\n");
  }
  SECTION("a snapshot of a run of another material at the same load factor: refused by the run identifier") {
    // Same particles, load steps and load factors: before 6 December 2026
    // drawn as this run's map, exit 0.
    const std::string other = fresh_dir("real_quasi_static_other");
    const std::string stiffer = quasi_static_run(other, "--set material.youngs_modulus=2.1e11");
    const std::string id = pd::post::read_solver_summary(run).run_id;
    const std::string other_id = pd::post::read_solver_summary(stiffer).run_id;
    REQUIRE(id.size() == 16);
    CHECK(other_id != id);
    fs::copy_file(stiffer + "/snapshots/step_00000001.vtp", run + "/snapshots/step_00000001.vtp",
                  fs::copy_options::overwrite_existing);
    ToolRun r = pd_post(run, "--load-factors 0.1");
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains("pd-post: error: " + run + "/snapshots/step_00000001.vtp: is of run " + other_id +
                               " (field 'run_id'), and " + run + "/final_state.vtp of run " + id +
                               ": the two files are from different runs"));
    // final_state.vtp against summary.json.
    fs::copy_file(stiffer + "/final_state.vtp", run + "/final_state.vtp", fs::copy_options::overwrite_existing);
    r = pd_post(run, "");
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains("pd-post: error: " + run + "/summary.json: is of run " + id + " (\"run_id\"), and " +
                               run + "/final_state.vtp of run " + other_id + ": the two files are from different runs"));
  }
  SECTION("snapshots.pvd of a run of another material: refused by its run identifier") {
    // The same load factors and files: before 7 December 2026 the collection
    // carried no identifier and was read as this run's, exit 0.
    const std::string stiffer =
        quasi_static_run(fresh_dir("real_quasi_static_other_collection"), "--set material.youngs_modulus=2.1e11");
    const std::string id = pd::post::read_solver_summary(run).run_id;
    const std::string other_id = pd::post::read_solver_summary(stiffer).run_id;
    REQUIRE(id.size() == 16);
    REQUIRE(other_id != id);
    CHECK_THAT(file_text(run + "/snapshots.pvd"), Contains("<Collection run_id=\"" + id + "\">"));
    fs::copy_file(stiffer + "/snapshots.pvd", run + "/snapshots.pvd", fs::copy_options::overwrite_existing);
    const ToolRun r = pd_post(run, "");
    CHECK(r.status == 1);
    CHECK(r.err == "pd-post: error: " + run + "/snapshots.pvd: is of run " + other_id + " (attribute 'run_id' of its "
                   "Collection), and " + run + "/final_state.vtp of run " + id + ": the two files are from different "
                   "runs (a folder mixed by copying or moving files); give the folder that one pd-solve run wrote "
                   "whole, or run pd-solve again\n");
  }
  SECTION("a load factor outside the run's (-0.1 on a run from 0 to 0.2, or 1): a warning") {
    const ToolRun r = pd_post(run, "--load-factors -0.1,1");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Contains("pd-post: warning: --load-factors -0.1 is outside the run's load factors (0 to 0.2): "
                               "the maps show the nearest snapshot, " + run +
                               "/snapshots/step_00000001.vtp, at load factor 0.1"));
    CHECK_THAT(r.err, Contains("pd-post: warning: --load-factors 1 is outside the run's load factors (0 to 0.2): "
                               "the maps show the nearest snapshot, " + run +
                               "/snapshots/step_00000002.vtp, at load factor 0.2"));
    CHECK_THAT(file_text(run + "_post/summary.json"), Contains("--load-factors -0.1 is outside"));
  }
  SECTION("the dynamic runs' crack options: a note that they are not used") {
    const ToolRun r = pd_post(run, "--threshold 0.5 --window 3 --window-time 2us");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Contains("pd-post: note: --threshold, --window and --window-time are for crack tracking in "
                               "dynamic runs: not used"));
  }
  SECTION("pd-post run again into its folder leaves no map of an earlier run's --load-factors") {
    const auto maps = [&] {
      std::vector<std::string> names;
      for (const auto& entry : fs::directory_iterator(run + "_post"))
        if (entry.path().filename().string().rfind("displacement_y_", 0) == 0)
          names.push_back(entry.path().filename().string());
      std::sort(names.begin(), names.end());
      return names;
    };
    REQUIRE(pd_post(run, "--load-factors 0.1").status == 0);
    const auto with_option = maps();
    REQUIRE(pd_post(run, "").status == 0);
    const auto without = maps();
    INFO("with --load-factors 0.1: " << with_option.size() << " maps, then without: " << without.size());
    // The second run draws the final state only; before 5 December 2026 the
    // first run's map at 0.1 stayed beside it.
    CHECK(without.size() == 1);
    CHECK(with_option.size() > without.size());
    CHECK(fs::exists(run + "_post/summary.json"));
  }
  SECTION("a fresh pd-solve run into the folder removes pd-post's files of the earlier run") {
    // pd-post's quasi-static summary.json names its tool as the dynamic one
    // does, by which pd-solve knows OUTDIR/post for pd-post's (before 5
    // December 2026 it did not, and the earlier run's maps stayed).
    const std::string dir = fs::path(run).parent_path().string() + "/again";
    fs::create_directories(dir);
    fs::copy(run, dir + "/run", fs::copy_options::recursive);
    const ToolRun post = run_tool(PD_POST_EXECUTABLE, "'" + dir + "/run'", dir);
    REQUIRE(post.status == 0);
    CHECK_THAT(file_text(dir + "/run/post/summary.json"), Contains("\"tool\": \"pd-post "));
    REQUIRE(fs::exists(dir + "/run/post/reactions.csv"));
    const std::string geometry = std::string(PD_GEOMETRY_DIR);
    const ToolRun solve = run_tool(PD_SOLVE_EXECUTABLE, "'" + geometry + "/centre_crack_plate.toml' -o '" + dir +
                                   "/run' --set 'particles=" + fs::path(run).parent_path().string() +
                                   "/plate.pdp' --set model.osb_failure=force_only --set 'quasi_static.increments=[[1, "
                                   "0.1]]' --set quasi_static.tolerance=1e-6 --threads 1 -q", dir);
    INFO(solve.out + solve.err);
    REQUIRE(solve.status == 0);
    CHECK_THAT(solve.out, Contains("result files of an earlier run in " + dir + "/run"));
    CHECK(!fs::exists(dir + "/run/post/reactions.csv"));
    CHECK(!fs::exists(dir + "/run/post/summary.json"));
  }
  SECTION("a line that meets no particle is refused, one partly off the plate warned about") {
    ToolRun r = pd_post(run, "--line 600mm,100mm,700mm,100mm");
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains("pd-post: error: --line: the line from (600, 100) mm to (700, 100) mm meets no "
                               "particle (the plate's particles span x 5 to 495 mm, y 5 to 495 mm)"));
    r = pd_post(run, "--line 400mm,100mm,600mm,100mm");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Contains("pd-post: warning: --line: ") && Contains("samples of the line from (400, 100) mm to "
                                                                         "(600, 100) mm lie off the plate"));
  }
}

// pd-post's folder inside OUTDIR/quasi_static: refused where a switching
// run's quasi-static part is there (its files would pass for that part's),
// not inside that folder of a plain quasi-static run, which has none (before
// 6 December 2026 -o OUTDIR/quasi_static/post was refused for every run, as a
// folder pd-solve writes).
TEST_CASE("pd-post's folder inside OUTDIR/quasi_static: refused where a switching run's quasi-static part is",
          "[real-run][bad-input]") {
  const std::string plain = quasi_static_run(fresh_dir("real_quasi_static_part_folder"));
  const std::string logs = fs::path(plain).parent_path().string();
  ToolRun r = run_tool(PD_POST_EXECUTABLE, "'" + plain + "' -o '" + plain + "/quasi_static/post'", logs);
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(file_text(plain + "/quasi_static/post/summary.json"), Contains("\"tool\": \"pd-post "));
  // The folder itself stays refused: pd-post's summary.json there would stop
  // the next pd-solve run into OUTDIR.
  r = run_tool(PD_POST_EXECUTABLE, "'" + plain + "' -o '" + plain + "/quasi_static'", logs);
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: -o " + plain + "/quasi_static is the folder where pd-solve writes a switching "
                 "run's quasi-static part: pd-post's summary.json there would stop the next pd-solve run into " +
                 plain + " (a file of a result's name that pd-solve did not write); give a folder of its own "
                 "(default: " + plain + "/post)\n");
  CHECK_FALSE(fs::exists(plain + "/quasi_static/summary.json"));

  // The same plate switching to dynamics after its two load steps.
  const std::string dir = fresh_dir("real_switching_part_folder");
  std::string scene = file_text(std::string(PD_GEOMETRY_DIR) + "/centre_crack_plate.toml");
  for (std::size_t at = scene.find("[[loads]]\n"); at != std::string::npos; at = scene.find("[[loads]]\n", at + 1))
    scene.insert(at + 10, "phase = \"quasi_static\"\n");
  std::ofstream(dir + "/switch.toml") << scene;
  const std::string run = dir + "/run";
  const ToolRun solve = run_tool(PD_SOLVE_EXECUTABLE, "'" + dir + "/switch.toml' -o '" + run + "' --set 'particles=" +
                                 logs + "/plate.pdp' --set model.osb_failure=force_only --set "
                                 "'quasi_static.increments=[[2, 0.1]]' --set quasi_static.tolerance=1e-6 --set "
                                 "quasi_static.then=dynamic --set time.step=auto --set time.end=2e-5 --set "
                                 "material.density=7850 --threads 1 -q", dir);
  INFO(solve.err);
  REQUIRE(solve.status == 0);
  REQUIRE(fs::exists(run + "/quasi_static/load_steps.csv"));
  const std::string message = "pd-post: error: -o " + run + "/quasi_static/post is inside " + run +
                              "/quasi_static, which holds pd-solve's results (" + run + "/quasi_static/" +
                              "load_steps.csv; a switching run writes its quasi-static part there), a run of its own "
                              "for pd-post (pd-post " + run + "/quasi_static writes its files in " + run +
                              "/quasi_static/post): this run's summary.json and pictures would pass for that run's; "
                              "give a folder of its own (default: " + run + "/post)\n";
  r = run_tool(PD_POST_EXECUTABLE, "'" + run + "' -o '" + run + "/quasi_static/post'", dir);
  CHECK(r.status != 0);
  CHECK(r.err == message);
  CHECK_FALSE(fs::exists(run + "/quasi_static/post"));
  // As the message says: that part's own pd-post folder.
  r = run_tool(PD_POST_EXECUTABLE, "'" + run + "/quasi_static'", dir);
  CHECK(r.status == 0);
  CHECK(fs::exists(run + "/quasi_static/post/reactions.csv"));
  r = run_tool(PD_POST_EXECUTABLE, "'" + run + "' -o '" + run + "/quasi_static/post'", dir);
  CHECK(r.err == message);
}

// Another run's load_steps.csv of as many rows passed the row count against
// summary.json, and its reactions were drawn as this run's (before 6 December
// 2026, exit 0). Since 7 December 2026 its column run_id names the other run
// (before, the table carried no identifier and the folder was refused only
// where its last row differs from final_state.vtp); a table of an earlier
// version, without the column, is compared by its last row.
TEST_CASE("a quasi-static run's load_steps.csv replaced by another run's of as many rows is refused",
          "[real-run][bad-input][quasi-static]") {
  const std::string run = quasi_static_run(fresh_dir("real_quasi_static_table_of_another"));
  // Two load steps as well, of 0.15 each.
  const std::string other_dir = fresh_dir("real_quasi_static_table_other");
  const ToolRun solve = centre_crack_plate_run(other_dir, "--set model.osb_failure=force_only --set "
                                                          "'quasi_static.increments=[[2, 0.15]]' --set "
                                                          "quasi_static.tolerance=1e-6");
  INFO(solve.err);
  REQUIRE(solve.status == 0);
  const std::string other = other_dir + "/run";
  ToolRun r = pd_post(run, "");
  INFO(r.err);
  CHECK(r.status == 0);
  const std::string mixed = fs::path(run).parent_path().string() + "/mixed";
  fs::copy(run, mixed, fs::copy_options::recursive);
  fs::remove_all(mixed + "/post");
  fs::copy_file(other + "/load_steps.csv", mixed + "/load_steps.csv", fs::copy_options::overwrite_existing);
  const std::string id = pd::post::read_solver_summary(run).run_id;
  const std::string other_id = pd::post::read_solver_summary(other).run_id;
  REQUIRE(id.size() == 16);
  REQUIRE(other_id != id);
  r = pd_post(mixed, "");
  CHECK(r.status == 1);
  CHECK(r.err == "pd-post: error: " + mixed + "/load_steps.csv: is of run " + other_id + " (column 'run_id', line 2), "
                 "and " + mixed + "/final_state.vtp of run " + id + ": the two files are from different runs (a folder "
                 "mixed by copying or moving files); give the folder that one pd-solve run wrote whole, or run "
                 "pd-solve again\n");
  CHECK_FALSE(fs::exists(mixed + "_post/summary.json"));
  // The same table as an earlier version wrote it (no run_id column): its last row against the state.
  std::string without_id;
  std::istringstream other_rows(file_text(other + "/load_steps.csv"));
  for (std::string line; std::getline(other_rows, line);) without_id += line.substr(0, line.rfind(',')) + "\n";
  REQUIRE(without_id.find("run_id") == std::string::npos);
  std::ofstream(mixed + "/load_steps.csv", std::ios::trunc) << without_id;
  r = pd_post(mixed, "");
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: " + mixed + "/load_steps.csv: ends at load factor 0.3 (column 'load_factor', "
                 "load step 2), and " + mixed + "/final_state.vtp is of load factor 0.2 (field 'load_factor'): the "
                 "two files are from different runs (a folder mixed by copying or moving files); give the folder "
                 "that one pd-solve run wrote whole, or run pd-solve again\n");
  CHECK_FALSE(fs::exists(mixed + "_post/summary.json"));
  // The same load factor with another largest damage (a table of a run with
  // other damage, made here by changing the last row's max_damage by 0.125,
  // far beyond the Float32 rounding the check allows): refused by the damage.
  std::string table = file_text(run + "/load_steps.csv");
  const std::string header = table.substr(0, table.find('\n'));
  const auto column = static_cast<std::size_t>(std::count(header.begin(), header.begin() + header.find("max_damage"), ','));
  std::size_t row_start = table.rfind('\n', table.size() - 2) + 1;  // the last row (the file ends with a newline)
  std::size_t cell = row_start;
  for (std::size_t k = 0; k < column; ++k) cell = table.find(',', cell) + 1;
  const std::size_t cell_end = table.find_first_of(",\n", cell);
  const double recorded = std::stod(table.substr(cell, cell_end - cell));
  const double changed = recorded <= 0.5 ? recorded + 0.125 : recorded - 0.125;
  table.replace(cell, cell_end - cell, std::to_string(changed));
  std::ofstream(mixed + "/load_steps.csv", std::ios::trunc) << table;
  r = pd_post(mixed, "");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("pd-post: error: " + mixed + "/load_steps.csv: ends at max_damage ") &&
                        Contains(" (column 'max_damage', load step 2), and the largest damage of " + mixed +
                                 "/final_state.vtp is ") &&
                        Contains("the two files are from different runs"));
  // The untouched folder still passes.
  CHECK(pd_post(run, "").status == 0);
}

// A quasi-static run with effects.damage = false broke no bond under load:
// its damage maps show the pre-crack's cut bonds only (this plate's centre
// crack: damage up to 0.41 beside it), and pd-post says so. Before 6
// December 2026 it said nothing, and named damage_final.png as where the
// damage of crack-tracking options went.
TEST_CASE("a quasi-static run with damage off: a note says what its damage maps show", "[real-run][quasi-static]") {
  const std::string run = quasi_static_run(fresh_dir("real_quasi_static_damage_off"), "--set effects.damage=false");
  const ToolRun r = pd_post(run, "--threshold 0.5");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Contains("pd-post: note: the run had damage off (the scene's effects.damage = false): no bond "
                             "broke under load; the damage maps show the pre-cracks' cut bonds only"));
  CHECK_THAT(r.err, Contains("--threshold is for crack tracking in dynamic runs: not used (the run had damage off)"));
  CHECK(fs::exists(run + "_post/damage_final.png"));
}

// pd-post's closing line and pd-solve's plan count the load steps in
// words that fit the number (before 6 December 2026: "1 load steps").
TEST_CASE("a quasi-static run of one load step is 'one load step' in pd-post's closing line", "[real-run][quasi-static]") {
  const std::string dir = fresh_dir("real_quasi_static_one_step");
  const ToolRun solve = centre_crack_plate_run(dir, "--set 'quasi_static.increments=[[1, 0.1]]' --set "
                                                    "quasi_static.tolerance=1e-6");
  INFO(solve.err);
  REQUIRE(solve.status == 0);
  // pd-solve's plan too (before the second sitting of 6 December 2026: "1 load steps").
  CHECK_THAT(solve.out + solve.err, Contains("  steps:     1 load step, load factor 0.1 -> 0.1, at least about "));
  const ToolRun post = pd_post(dir + "/run", "");
  INFO(post.err);
  CHECK(post.status == 0);
  CHECK_THAT(post.out, Contains("quasi-static run: 1 load step, max damage at the last step "));
}

// A quasi-static run whose first load step does not converge (one NCG
// iteration allowed) leaves load_steps.csv with its header alone, and
// pd-post says there is no load step yet. Before the fourth sitting of 5
// December 2026 the folder held no load_steps.csv, and pd-post called it a
// run stopped "before its first time step" (or, given a header alone,
// reported "0 load steps" and drew an empty reactions plot).
TEST_CASE("a quasi-static run whose first load step failed: load_steps.csv's header, and pd-post says why it stops",
          "[real-run][quasi-static]") {
  const auto dir = fresh_dir("real_quasi_static_first_step_failed");
  const std::string outdir = dir + "/run";
  const ToolRun solve =
      centre_crack_plate_run(dir, "--set quasi_static.max_iterations=1 --set quasi_static.tolerance=1e-12");
  INFO(solve.err);
  REQUIRE(solve.status != 0);
  CHECK_THAT(solve.err, Contains("load step 1") && Contains("not converged"));
  CHECK_THAT(file_text(outdir + "/load_steps.csv"), Catch::StartsWith("step,load_factor,") && !Contains("\n1,"));
  const ToolRun post = pd_post(outdir, "");
  CHECK(post.status != 0);
  CHECK_THAT(post.err, Contains(outdir + "/load_steps.csv: no load step in it: the quasi-static run stopped before "
                                "its first load step ended"));
}

TEST_CASE("a dynamic run: quasi-static options, thresholds it did not record, a window under a step, a line off "
          "the plate",
          "[real-run]") {
  const std::string dir = fresh_dir("real_dynamic");
  const std::string run = dynamic_run(dir, "4e-4");  // to the stop condition: a crack across the strip

  ToolRun r = pd_post(run, "--load-factors 0.5");
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Contains("pd-post: note: --load-factors is for quasi-static runs; a dynamic run takes --times"));

  // The scene records the solver's default thresholds 0.2, 0.35 and 0.5.
  r = pd_post(run, "--threshold 1.5");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("--threshold 1.5: no point array 'arrival_time_1.50'; the run recorded the damage "
                             "thresholds 0.2, 0.35, 0.5") &&
                        Contains("output.damage_thresholds: give one of them (a damage threshold is in (0, 1])"));
  r = pd_post(run, "--threshold 0.3");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("the run recorded the damage thresholds 0.2, 0.35, 0.5") &&
                        !Contains("a damage threshold is in"));

  r = pd_post(run, "--window-time 1ns");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("--window-time 1e-09 s rounds to 0 solver steps (one step is ") &&
                        Contains("--window 1") && !Contains("0.000000"));

  // 100 mm for a 20 mm wide strip: every sample off the plate.
  r = pd_post(run, "--line 100mm,100mm,120mm,100mm");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("--line: the line from (100, 100) mm to (120, 100) mm meets no particle (the plate's "
                             "particles span x 0.25 to 19.75 mm, y 0.25 to 39.75 mm)"));
  r = pd_post(run, "--line 10mm,30mm,30mm,30mm");
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Contains("pd-post: warning: --line: ") && Contains("lie off the plate"));
  // Off the plate there is no particle to take the damage from either: empty, not 0.
  CHECK_THAT(file_text(run + "_post/line_profile.csv"), Contains(",0.03,,,,,\n"));

  // --particles draws a particle file: a run's options are refused, as OUTDIR is.
  r = run_tool(PD_POST_EXECUTABLE, "--particles '" + dir + "/strip.pdp' -o '" + dir + "/cells' --threshold 0.5", dir);
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("--threshold is for a run's results") && Contains("leave --threshold out"));
  // -o naming a file. Before 5 December 2026: "filesystem error: cannot
  // create directories: Not a directory [PATH]", without the option.
  const std::string file = dir + "/cells.txt";
  std::ofstream(file) << "a file";
  r = run_tool(PD_POST_EXECUTABLE, "--particles '" + dir + "/strip.pdp' -o '" + file + "'", dir);
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: -o " + file + ": a file, not a folder (the folder of the pictures)\n");
}

// Thresholds that two decimals do not name: before 6 December 2026 pd-solve
// named 0.001 and 0.354 "arrival_time_0.00" and "arrival_time_0.35", and
// pd-post's default --threshold 0.35 then tracked the crack at 0.354 as
// 0.35's (exit 0), --threshold 0.004 the one at 0.001.
TEST_CASE("damage thresholds of more than two decimals get arrays of their own names, which pd-post tells apart",
          "[real-run]") {
  const std::string dir = fresh_dir("real_fine_thresholds");
  std::ofstream(dir + "/strip.toml") << file_text(std::string(PD_GEOMETRY_DIR) + "/sen_strip.toml")
                                     << "damage_thresholds = [0.001, 0.354]\n";  // into its last table, [output]
  const std::string run = dynamic_run(dir, "4e-4", dir + "/strip.toml");
  for (const std::string threshold : {"0.35", "0.004"}) {
    const ToolRun r = pd_post(run, "--threshold " + threshold);
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains("--threshold " + threshold + ": no point array 'arrival_time_" + threshold +
                               "'; the run recorded the damage thresholds 0.001, 0.354 (arrays arrival_time_0.001, "
                               "arrival_time_0.354)"));
  }
  const ToolRun r = pd_post(run, "--threshold 0.354");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(file_text(run + "_post/summary.json"), Contains("\"damage_threshold\": 0.354,"));
}

// pd-solve's own summary.json of a run with effects.damage = false (its
// "effects" object). Before 5 December 2026 pd-post said "empty crack", as
// for a load too small.
TEST_CASE("a run with damage off: no crack to track, and the summary.json key that says why", "[real-run][bad-input]") {
  const std::string dir = fresh_dir("real_damage_off");
  // The strip's scene without damage, and so without its stop on the crack (refused without damage).
  std::string scene = file_text(std::string(PD_GEOMETRY_DIR) + "/sen_strip.toml");
  scene.replace(scene.find("damage = true"), 13, "damage = false");
  scene.erase(scene.find("[stop]"), scene.find("[[loads]]") - scene.find("[stop]"));
  std::ofstream(dir + "/strip.toml") << scene;
  const std::string run = dynamic_run(dir, "1e-4", dir + "/strip.toml");
  const ToolRun r = pd_post(run, "");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("pd-post: error: " + run + "/summary.json: \"effects\": {\"damage\": false}: the run "
                             "had damage off") && Contains("no crack to track"));
}

TEST_CASE("a run stopped before its crack started says it is incomplete, not only that the crack is empty",
          "[real-run][bad-input]") {
  // What a killed run leaves: arrival.vtp of its last checkpoint (100 us,
  // before any particle reaches 0.35) and no summary.json, which pd-solve
  // writes only when a run ends.
  const std::string run = dynamic_run(fresh_dir("real_stopped"), "1e-4");
  fs::remove(run + "/summary.json");
  const ToolRun r = pd_post(run, "");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains(run + "/arrival.vtp: no particle has reached the damage threshold yet (array "
                                   "'arrival_time_0.35' is -1 everywhere) in this incomplete run: " +
                             run + "/summary.json does not exist") &&
                        Contains("the run stopped before its end (killed, or failed)") && Contains("t = 100 us"));
}

namespace {

// pd-solve started in the background on the strip into DIR/run, with an end
// of 0.1 s (thousands of times the strip's 300 us) and no checkpoints: it runs
// until killed. Returns its process id once it has written arrival.vtp (or
// after 60 s).
pid_t start_endless_strip_run(const std::string& dir) {
  const std::string geometry = std::string(PD_GEOMETRY_DIR);
  const std::string particles = dir + "/strip.pdp", outdir = dir + "/run";
  REQUIRE(run_tool(PD_MESH_EXECUTABLE, "'" + geometry + "/sen_strip.geo' --spacing 0.5mm --horizon 2mm -o '" +
                   particles + "'", dir).status == 0);
  const pid_t solver = pd::test_support::start_process(
      {PD_SOLVE_EXECUTABLE, geometry + "/sen_strip.toml", "-o", outdir, "--set", "particles=\"" + particles + "\"",
       "--set", "time.end=0.1", "--set", "output.checkpoint_interval=0", "--threads", "1", "-q"},
      dir + "/solve.txt");
  REQUIRE(solver >= 0);
  for (int wait = 0; wait < 6000 && !fs::exists(outdir + "/arrival.vtp"); ++wait) ::usleep(10000);
  return solver;
}

}  // namespace

// A run without summary.json is one still going or one that stopped: the
// lock pd-solve holds while it runs (the kernel releases it however the run
// ends) tells which. Before 7 December 2026 both were "the solver was killed
// or is still running".
TEST_CASE("a run without summary.json is said to be still running while pd-solve holds its lock and stopped once "
          "killed",
          "[real-run][bad-input]") {
  const std::string dir = fresh_dir("real_running_then_killed");
  const std::string outdir = dir + "/run";
  const pid_t solver = start_endless_strip_run(dir);
  const ToolRun running = pd_post(outdir, "");
  ::kill(solver, SIGKILL);
  ::waitpid(solver, nullptr, 0);
  INFO(file_text(dir + "/solve.txt"));
  REQUIRE(fs::exists(outdir + "/arrival.vtp"));
  REQUIRE_FALSE(fs::exists(outdir + "/summary.json"));
  INFO(running.err);
  CHECK(running.status == 1);
  CHECK_THAT(running.err, Contains(outdir + "/summary.json does not exist (pd-solve writes it when a run ends; the run "
                                   "is still running (pd-solve holds " + outdir + "/.pd-solve.lock, PID " +
                                   std::to_string(solver) + ")); arrival.vtp is from t = 0 us, step 0"));
  // Killed: its lock file stays, and nobody holds it.
  REQUIRE(fs::exists(outdir + "/.pd-solve.lock"));
  const ToolRun killed = pd_post(outdir, "");
  INFO(killed.err);
  CHECK(killed.status == 1);
  CHECK_THAT(killed.err, Contains(outdir + "/summary.json does not exist (pd-solve writes it when a run ends; the run "
                                  "stopped before its end (killed, or failed)); arrival.vtp is from t = 0 us, step 0") &&
                             !Contains("still running"));
}

// A run killed before any checkpoint (here: one without checkpoints) leaves
// the arrival.vtp pd-solve writes at the start, at step 0; pd-post says so
// (before: "arrival.vtp is from t = 0 us, step 0 (the last checkpoint)",
// where there was no checkpoint).
TEST_CASE("a run killed before any checkpoint: arrival.vtp is said to be the start's", "[real-run][bad-input]") {
  const std::string dir = fresh_dir("real_killed_at_start");
  const std::string outdir = dir + "/run";
  const pid_t solver = start_endless_strip_run(dir);
  ::kill(solver, SIGKILL);
  ::waitpid(solver, nullptr, 0);
  INFO(file_text(dir + "/solve.txt"));
  REQUIRE(fs::exists(outdir + "/arrival.vtp"));
  REQUIRE_FALSE(fs::exists(outdir + "/summary.json"));
  REQUIRE_FALSE(fs::exists(outdir + "/checkpoint.bin"));
  const ToolRun r = pd_post(outdir, "");
  INFO(r.err);
  CHECK_THAT(r.err, Contains("arrival.vtp is from t = 0 us, step 0 (the start of the run: it stopped before any "
                             "checkpoint)") &&
                        !Contains("the last checkpoint"));
}

// A particle without bonds (pd-mesh warns of one: a cell that holes cut off
// from the rest at a coarse spacing) has nothing to break: its damage is 0.
// Before 5 December 2026 it was 0/0, NaN in arrival.vtp, which pd-solve
// wrote with exit 0 and pd-post then refused. A plate where no particle has a
// bond is refused by pd-solve with that reason (before: "the run became
// unstable at step 1 (t = inf s)").
TEST_CASE("a particle without bonds has damage 0, and a plate without any bond is refused", "[real-run][bad-input]") {
  const std::string dir = fresh_dir("real_no_bonds");
  const std::string geometry = dir + "/two_holes.geo";
  std::ofstream(geometry) << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 40, 20};\n"
                             "Disk(2) = {15, 13.3, 0, 2};\nDisk(3) = {27, 7.1, 0, 1.2};\n"
                             "BooleanDifference{ Surface{1}; Delete; }{ Surface{2, 3}; Delete; }\n";
  const ToolRun mesh =
      run_tool(PD_MESH_EXECUTABLE, "'" + geometry + "' --spacing 20mm -m 3 -o '" + dir + "/plate.pdp'", dir);
  INFO(mesh.err);
  REQUIRE(mesh.status == 0);
  REQUIRE_THAT(mesh.err, Contains("it takes no part in a run"));  // the case this test is about
  const std::string scene = dir + "/scene.toml";
  std::ofstream(scene) << "particles = \"plate.pdp\"\n[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\n"
                          "fracture_energy = 200\n[time]\nstep = \"auto\"\nend = 5e-5\n"
                          "[[loads]]\nset = \"all\"\ntype = \"initial_velocity\"\nx = 0.1\n";
  const ToolRun solve = run_tool(PD_SOLVE_EXECUTABLE, "'" + scene + "' -o '" + dir + "/run' --threads 1 -q", dir);
  INFO(solve.out + solve.err);
  REQUIRE(solve.status == 0);
  const ToolRun post = run_tool(PD_POST_EXECUTABLE, "'" + dir + "/run'", dir);
  INFO(post.err);
  CHECK_THAT(post.err, !Contains("nan"));
  CHECK_THAT(post.err, !Contains("outside [0, 1]"));
  // One particle, one spacing of horizon: no bond at all.
  const std::string single = dir + "/single.geo";
  std::ofstream(single) << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 1, 1};\n";
  REQUIRE(run_tool(PD_MESH_EXECUTABLE, "'" + single + "' --spacing 1mm -m 1 -o '" + dir + "/single.pdp'", dir).status ==
          0);
  const ToolRun lone = run_tool(PD_SOLVE_EXECUTABLE, "'" + scene + "' -o '" + dir + "/lone' --set " +
                                "'particles=\"" + dir + "/single.pdp\"' --threads 1 -q", dir);
  CHECK(lone.status == 1);
  CHECK_THAT(lone.err, Contains("single.pdp: no particle has a bond") && !Contains("unstable"));
}

// Files of two runs mixed in one folder (a summary.json or an arrival.vtp
// copied over another run's): refused, naming both files and what differs.
// Before 6 December 2026 the folder was read as one run, exit 0.
TEST_CASE("a folder mixing two runs' summary.json and arrival.vtp is refused", "[real-run][bad-input]") {
  const std::string dir = fresh_dir("real_mixed_runs");
  // The strip at a fixed step of 50 ns (the stable limit at 0.5 mm is about
  // 0.3 us), so that two runs to one end time end at one step.
  std::string scene = file_text(std::string(PD_GEOMETRY_DIR) + "/sen_strip.toml");
  scene.replace(scene.find("step = \"auto\""), 13, "step = 5e-8");
  std::ofstream(dir + "/strip.toml") << scene;
  std::string denser = scene;
  denser.replace(denser.find("density = 1190"), 14, "density = 1300");
  std::ofstream(dir + "/denser.toml") << denser;
  fs::create_directories(dir + "/a"), fs::create_directories(dir + "/b"), fs::create_directories(dir + "/c");
  const std::string a = dynamic_run(dir + "/a", "2e-6", dir + "/strip.toml");   // 40 steps
  const std::string b = dynamic_run(dir + "/b", "3e-6", dir + "/strip.toml");   // 60 steps
  const std::string c = dynamic_run(dir + "/c", "2e-6", dir + "/denser.toml");  // 40 steps, another density

  fs::copy_file(b + "/summary.json", a + "/summary.json", fs::copy_options::overwrite_existing);
  ToolRun r = pd_post(a, "");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("pd-post: error: " + a + "/summary.json: the run ended at step 60 (\"steps\"), and " + a +
                             "/arrival.vtp is from step 40: the two files are from different runs"));
  CHECK(!fs::exists(a + "_post/summary.json"));

  fs::copy_file(c + "/summary.json", a + "/summary.json", fs::copy_options::overwrite_existing);
  r = pd_post(a, "");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains(a + "/summary.json: the run's material has E = 3.24e+09 Pa, rho = 1300 kg/m^3 "
                                 "(\"material\"), and " + a + "/arrival.vtp's E = 3.24e+09 Pa, rho = 1190 kg/m^3"));
}

// A run's identifier in every file it writes (docs/formats.md, "Run
// identifier"): a snapshot copied in from a run of another material, of the
// same step, time and particle count, is refused (before 6 December 2026
// drawn as this run's map, exit 0: nothing it recorded differed); a
// restarted run's files keep the identifier, and its folder is read.
namespace {

// In `text`, the first `from` replaced by `to` (which must be there).
void replace_first(std::string& text, const std::string& from, const std::string& to) {
  REQUIRE(text.find(from) != std::string::npos);
  text.replace(text.find(from), from.size(), to);
}

// Three runs of the strip at a fixed step of 50 ns, brittle and pulled fast,
// without its stop region (bonds break within the 40 steps to 2 us), made in
// DIR: a (40 steps), c (the same with another density: another run of the
// same step, time and particle count) and r (a's scene to 1 us, then
// restarted to 2 us: a's run), each with an energy row every 10 steps.
// DIR/strip.toml is a's scene.
struct StripRuns {
  std::string a, c, r;
};
StripRuns strip_runs(const std::string& dir) {
  std::string scene = file_text(std::string(PD_GEOMETRY_DIR) + "/sen_strip.toml");
  replace_first(scene, "step = \"auto\"", "step = 5e-8");
  replace_first(scene, "fracture_energy = 200", "fracture_energy = 0.1");
  replace_first(scene, "[stop]\nset = \"right\"\ndamage = 0.35\n", "");
  for (int load = 0; load < 2; ++load) replace_first(scene, "ramp_time = 2e-4", "ramp_time = 1e-7");
  replace_first(scene, "y = 0.3 ", "y = 3 ");
  replace_first(scene, "y = -0.3 ", "y = -3 ");
  replace_first(scene, "snapshot_interval = 1000", "snapshot_interval = 20");
  replace_first(scene, "energy_interval = 50", "energy_interval = 10");
  std::ofstream(dir + "/strip.toml") << scene;
  replace_first(scene, "density = 1190", "density = 1300");
  std::ofstream(dir + "/denser.toml") << scene;
  for (const char* run : {"a", "c", "r"}) fs::create_directories(dir + "/" + run);
  StripRuns runs;
  runs.a = dynamic_run(dir + "/a", "2e-6", dir + "/strip.toml");
  runs.c = dynamic_run(dir + "/c", "2e-6", dir + "/denser.toml");
  runs.r = dynamic_run(dir + "/r", "1e-6", dir + "/strip.toml");
  const ToolRun restart = run_tool(PD_SOLVE_EXECUTABLE, "'" + dir + "/strip.toml' -o '" + runs.r +
                                   "' --set 'particles=" + dir + "/r/strip.pdp' --set time.end=2e-6 --restart "
                                   "--threads 1 -q", dir + "/r");
  INFO(restart.err);
  REQUIRE(restart.status == 0);
  return runs;
}

}  // namespace

TEST_CASE("a snapshot of another run of the same step, time and count is refused by the run identifier",
          "[real-run][bad-input]") {
  const std::string dir = fresh_dir("real_run_identifier");
  const StripRuns runs = strip_runs(dir);
  const std::string &a = runs.a, &c = runs.c, &r = runs.r;
  const auto replace = [](std::string& text, const std::string& from, const std::string& to) {
    replace_first(text, from, to);
  };

  const auto summary_id = [](const std::string& run) { return pd::post::read_solver_summary(run).run_id; };
  const auto vtp_id = [](const std::string& path) {
    return pd::post::read_field_text(pd::post::read_vtp_quietly(path), pd::results::field_run_id);
  };
  const std::string id_a = summary_id(a), id_c = summary_id(c);
  CHECK(id_a.size() == 16);
  CHECK(id_c.size() == 16);
  CHECK(id_a != id_c);  // another density: another run
  // The same scene and particle file (pd-mesh writes the same file again) to
  // another end time: a restart could make one of the other, so one run.
  CHECK(summary_id(r) == id_a);
  // Every file of the restarted run: the snapshots before the restart (steps
  // 0 and 20) and after it (40), and arrival.vtp.
  for (const std::string file : {"snapshots/step_00000000.vtp", "snapshots/step_00000020.vtp",
                                 "snapshots/step_00000040.vtp", "arrival.vtp"}) {
    INFO(file);
    CHECK(vtp_id(r + "/" + file) == id_a);
    CHECK(vtp_id(c + "/" + file) == id_c);
  }
  ToolRun post = pd_post(r, "--times 0,1us,2us");
  INFO(post.err);
  CHECK(post.status == 0);

  // The same step, time and particle count: only the identifiers differ.
  fs::copy_file(c + "/snapshots/step_00000020.vtp", a + "/snapshots/step_00000020.vtp",
                fs::copy_options::overwrite_existing);
  post = pd_post(a, "--times 1us");
  CHECK(post.status != 0);
  CHECK_THAT(post.err, Contains("pd-post: error: " + a + "/snapshots/step_00000020.vtp: is of run " + id_c +
                                " (field 'run_id'), and " + a + "/arrival.vtp of run " + id_a +
                                ": the two files are from different runs"));
  // arrival.vtp and summary.json of the other run: its snapshot fits them
  // now, the run's own first snapshot does not.
  for (const char* file : {"arrival.vtp", "summary.json", "energy.csv", "snapshots.pvd"})
    fs::copy_file(c + "/" + file, a + "/" + file, fs::copy_options::overwrite_existing);
  post = pd_post(a, "--times 0,1us");
  CHECK(post.status != 0);
  CHECK_THAT(post.err, Contains(a + "/snapshots/step_00000000.vtp: is of run " + id_a + " (field 'run_id'), and " +
                                a + "/arrival.vtp of run " + id_c + ": the two files are from different runs"));
  // arrival.vtp of a run pulled at another speed, of the same material,
  // step, time and particle count, against this run's summary.json.
  const std::string slower = file_text(dir + "/strip.toml");
  std::string text = slower;
  replace(text, "y = 3 ", "y = 2 ");
  std::ofstream(dir + "/slower.toml") << text;
  fs::create_directories(dir + "/v");
  const std::string v = dynamic_run(dir + "/v", "2e-6", dir + "/slower.toml");
  fs::copy_file(v + "/arrival.vtp", r + "/arrival.vtp", fs::copy_options::overwrite_existing);
  post = pd_post(r, "");
  CHECK(post.status != 0);
  CHECK_THAT(post.err, Contains("pd-post: error: " + r + "/summary.json: is of run " + id_a + " (\"run_id\"), and " +
                                r + "/arrival.vtp of run " + summary_id(v) + ": the two files are from different runs"));
}

// pd-post --particles on a file pd-mesh wrote: a --zoom window in --line's
// order, and one in metres, are warned about on stderr (before 7 December
// 2026 both were drawn without a word, the second the plate as a dot).
TEST_CASE("pd-post --particles warns about a zoom window typed in --line's order, and clips a far larger one",
          "[real-run][pictures]") {
  const std::string dir = fresh_dir("real_zoom_windows");
  // A 50 x 25 mm plate from (0, 100) mm.
  std::ofstream(dir + "/raised.geo") << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 100, 0, 50, 25};\n";
  const ToolRun mesh = run_tool(PD_MESH_EXECUTABLE, "'" + dir + "/raised.geo' --grid uniform --spacing 1mm "
                                "--horizon 3mm -o '" + dir + "/raised.pdp'", dir);
  INFO(mesh.err);
  REQUIRE(mesh.status == 0);
  ToolRun r = run_tool(PD_POST_EXECUTABLE, "--particles '" + dir + "/raised.pdp' --zoom 10mm,105mm,40mm,120mm -o '" +
                       dir + "/swapped'", dir);
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Catch::StartsWith("pd-post: warning: --zoom 10, 105, 40, 120 mm is read as x0,x1,y0,y1: ") &&
                        Contains("for that window give --zoom 10mm,40mm,105mm,120mm\n"));
  CHECK_THAT(r.out, Contains("wrote " + dir + "/swapped/raised_region.png"));
  r = run_tool(PD_POST_EXECUTABLE, "--particles '" + dir + "/raised.pdp' --zoom -1m,1m,-1m,1m -o '" + dir + "/metres'",
               dir);
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Contains("pd-post: warning: --zoom: the window x in [-1000, 1000] mm, y in [-1000, 1000] mm is more "
                             "than 10 times as wide and as tall as the part of the plate it holds"));
  // The plate fills the plot (1000 x 500 px), drawn as the whole plate is.
  CHECK(run_tool(PD_POST_EXECUTABLE, "--particles '" + dir + "/raised.pdp' -o '" + dir + "/whole'", dir).status == 0);
  CHECK(file_text(dir + "/metres/raised_region.png") == file_text(dir + "/whole/raised_region.png"));
}

// energy.csv and snapshots.pvd carry the run's identifier too (docs/formats.md,
// "Run identifier", since 7 December 2026): one copied in from a run of
// another material, of the same steps, times and particle count, is refused,
// naming the line of the table (before, neither carried one and pd-post read
// the folder as one run, exit 0). A restarted run writes the identifier once
// on each row of its continued energy.csv, as the uninterrupted run does;
// an energy.csv of an earlier version, without the column, is not compared.
TEST_CASE("energy.csv or snapshots.pvd of another run copied into a run's folder is refused by the run identifier",
          "[real-run][bad-input]") {
  const std::string dir = fresh_dir("real_run_identifier_tables");
  const StripRuns runs = strip_runs(dir);
  const std::string &a = runs.a, &c = runs.c, &r = runs.r;
  const std::string id_a = pd::post::read_solver_summary(a).run_id, id_c = pd::post::read_solver_summary(c).run_id;
  REQUIRE(id_a.size() == 16);
  REQUIRE(id_c != id_a);

  // The last column, the same on every row (40 steps, a row every 10 and the header).
  const std::string energy = file_text(a + "/energy.csv");
  CHECK(energy.substr(0, energy.find('\n')) ==
        "time_s,step,kinetic_J,strain_J,external_work_J,total_minus_work_J,broken_bonds,reaction_x_top_N,"
        "reaction_y_top_N,reaction_x_bottom_N,reaction_y_bottom_N,particles,run_id");
  std::size_t rows = 0;
  for (std::size_t at = energy.find('\n') + 1; at < energy.size(); at = energy.find('\n', at) + 1, ++rows)
    CHECK(energy.substr(at, energy.find('\n', at) - at).rfind("," + id_a) ==
          energy.find('\n', at) - at - id_a.size() - 1);
  CHECK(rows == 5);
  CHECK_THAT(file_text(a + "/snapshots.pvd"), Contains("  <Collection run_id=\"" + id_a + "\">\n"));
  // The restarted run: the same files, so the identifier once on each row.
  CHECK(file_text(r + "/energy.csv") == energy);
  CHECK(file_text(r + "/snapshots.pvd") == file_text(a + "/snapshots.pvd"));

  const std::string tail = ": the two files are from different runs (a folder mixed by copying or moving files); give "
                           "the folder that one pd-solve run wrote whole, or run pd-solve again\n";
  const auto mixed = [&](const std::string& name, const std::string& file_of_c) {
    const std::string m = dir + "/" + name;
    fs::copy(a, m, fs::copy_options::recursive);
    fs::remove_all(m + "/post");
    fs::copy_file(c + "/" + file_of_c, m + "/" + file_of_c, fs::copy_options::overwrite_existing);
    return m;
  };
  std::string m = mixed("energy_of_c", "energy.csv");
  ToolRun post = pd_post(m, "");
  CHECK(post.status == 1);
  CHECK(post.err == "pd-post: error: " + m + "/energy.csv: is of run " + id_c + " (column 'run_id', line 2), and " +
                        m + "/arrival.vtp of run " + id_a + tail);
  CHECK_FALSE(fs::exists(m + "_post/summary.json"));
  // Rows of the two runs spliced: the first of the other run's is named.
  const auto after_third_line = [](const std::string& text) {
    return text.find('\n', text.find('\n', text.find('\n') + 1) + 1) + 1;
  };
  const std::string energy_c = file_text(c + "/energy.csv");
  const std::string spliced = energy.substr(0, after_third_line(energy)) + energy_c.substr(after_third_line(energy_c));
  std::ofstream(m + "/energy.csv", std::ios::trunc) << spliced;
  post = pd_post(m, "");
  CHECK(post.status == 1);
  CHECK_THAT(post.err, Contains(m + "/energy.csv: is of run " + id_c + " (column 'run_id', line 4), and "));
  // The other run's table of an earlier version (no run_id column): not compared.
  std::string old_table;
  std::istringstream lines(energy_c);
  for (std::string line; std::getline(lines, line);) old_table += line.substr(0, line.rfind(',')) + "\n";
  REQUIRE(old_table.find("run_id") == std::string::npos);
  std::ofstream(m + "/energy.csv", std::ios::trunc) << old_table;
  post = pd_post(m, "");
  INFO(post.err);
  CHECK(post.status == 0);

  m = mixed("collection_of_c", "snapshots.pvd");
  post = pd_post(m, "");
  CHECK(post.status == 1);
  CHECK(post.err == "pd-post: error: " + m + "/snapshots.pvd: is of run " + id_c + " (attribute 'run_id' of its "
                    "Collection), and " + m + "/arrival.vtp of run " + id_a + tail);
  // The run's own folder still passes.
  post = pd_post(a, "--times 1us");
  INFO(post.err);
  CHECK(post.status == 0);
}

// A run with adaptive refinement ([refinement], docs/refinement.md): the
// particles ahead of the crack split into four children of half the
// spacing, so arrival.vtp holds cells of 0.25 mm beside the file's 0.5 mm
// and its field 'spacing' stays the file's. Its bounds (a spacing within
// 1000 times the median cell, a horizon within 1/64 to 64 spacings, points
// within the plate's reach) take such a run as it is, and its crack is
// tracked in its fine cells.
TEST_CASE("a run refined ahead of its crack is read as it is: one crack from the notch across the refined band",
          "[real-run][refinement]") {
  const std::string dir = fresh_dir("real_refined");
  // The strip's scene with dual horizons (refinement needs them, and they
  // take no surface correction) and one halving in a band around the
  // crack's path (the notch ends at x = 5 mm, y = 20 mm).
  std::string scene = file_text(std::string(PD_GEOMETRY_DIR) + "/sen_strip.toml");
  scene.replace(scene.find("surface_correction = true"), 25, "surface_correction = false");
  std::ofstream(dir + "/strip.toml") << scene << "\n[model]\ndual_horizon = true\n\n[refinement]\nlevels = 1\n"
                                                 "region = [0.004, 0.017, 0.020, 0.023]\n";
  const std::string run = dynamic_run(dir, "4e-4", dir + "/strip.toml");  // to the stop condition
  // Refined: squares of half the file's spacing beside its own.
  const auto arrival = pd::post::read_vtp_quietly(run + "/arrival.vtp");
  const auto cells = pd::post::read_point_array(arrival, run + "/arrival.vtp", pd::results::cell_size, true);
  const std::string solver_summary = file_text(run + "/summary.json");
  REQUIRE_THAT(solver_summary, Contains("\"refinement\": {\"events\": "));
  INFO(solver_summary.substr(solver_summary.find("\"refinement\"")));
  const auto squares_of = [&](double side) {
    return std::count_if(cells.begin(), cells.end(), [side](double c) { return std::abs(c - side) < 1e-9 * side; });
  };
  // Children of squares come in fours; the band holds 32 x 12 squares, and the
  // crack's path through it splits more than a hundred of them.
  CHECK(squares_of(0.25e-3) % 4 == 0);
  CHECK(squares_of(0.25e-3) > 400);
  CHECK(squares_of(0.5e-3) > static_cast<std::ptrdiff_t>(cells.size() / 2));  // the median cell: the file's
  CHECK(pd::post::read_field_number(arrival, run + "/arrival.vtp", pd::results::field_spacing) == 0.5e-3);

  // With the maps at the start, whose snapshot holds the file's particles, not arrival.vtp's.
  const ToolRun r = pd_post(run, "--times 0");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.err, !Contains("warning") && !Contains("error"));
  CHECK(fs::exists(run + "_post/damage_t0us.png"));
  CHECK_THAT(r.err, Contains("pd-post: note: speed window sized by the cells the crack crossed, 0.25 mm (their "
                             "median), not the particle file's spacing 0.5 mm: a refined run's crack runs in its fine "
                             "cells"));
  CHECK_THAT(r.out, Contains("branches: 1, branching events: 0, pores: 0, pore visits: 0, "));
  // branch,parent,start_time_s,start_x_m,start_y_m,end_time_s,end_x_m,end_y_m,length_m: one crack of its own
  // from the notch's tip to the stop set's edge (x = 18 mm and beyond), along y = 20 mm.
  std::istringstream branches(file_text(run + "_post/branches.csv"));
  std::string header, row, extra;
  std::getline(branches, header);
  std::getline(branches, row);
  CHECK_FALSE(std::getline(branches, extra));
  std::vector<double> v;
  std::istringstream cells_of_row(row);
  for (std::string cell; std::getline(cells_of_row, cell, ',');) v.push_back(std::stod(cell));
  REQUIRE(v.size() == 9);
  CHECK(v[1] == -1);
  CHECK(v[3] == Approx(5.25e-3).margin(0.5e-3));
  CHECK(v[4] == Approx(20e-3).margin(0.5e-3));
  CHECK(v[6] >= 18e-3);
  CHECK(v[7] == Approx(20e-3).margin(0.5e-3));
  CHECK(v[8] >= 12e-3);
}
