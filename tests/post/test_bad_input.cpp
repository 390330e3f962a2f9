// Every rejection of bad input names the path or the array involved.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>

#include "crack_comparison.hpp"
#include "error.hpp"
#include "json_text.hpp"
#include "post_pipeline.hpp"
#include "results_format.hpp"
#include "solver_summary.hpp"
#include "synthetic_output.hpp"
#include "vtk_output.hpp"
#include "../test_commands.hpp"

using namespace pd::post;
using namespace pd::post::test;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
namespace fs = std::filesystem;

namespace {

using pd::test_support::file_text;

PostOptions options_for(const std::string& dir) {
  PostOptions o;
  o.outdir = dir;
  return o;
}
double cracked_row(double x, double y) { return std::abs(y - 1.05e-3) < 1e-5 ? x / 500.0 : -1; }
}  // namespace

TEST_CASE("a missing output directory is reported with its path", "[bad-input]") {
  const std::string dir = std::string(PD_POST_TEST_TMPDIR) + "/does_not_exist";
  std::filesystem::remove_all(dir);
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir) && Contains("directory not found"));
}

TEST_CASE("a directory without arrival.vtp is reported", "[bad-input]") {
  const auto dir = fresh_dir("no_arrival");
  // A folder with none of pd-solve's files is not a run's; its subfolder
  // snapshots/ points to the run above (before the second sitting of 5
  // December 2026 both were said to be runs that stopped before their first step).
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir + ": not a solver output directory") &&
                                                   Contains("give the folder that pd-solve -o wrote"));
  fs::create_directories(dir + "/snapshots");
  std::ofstream(dir + "/summary.json") << "{}";
  CHECK_THROWS_WITH(analyse(options_for(dir + "/snapshots")),
                    Contains("not a solver output directory") && Contains("the folder above it, " + dir + ", is a run's"));
  fs::remove(dir + "/summary.json");
  // A run stopped before its first time step (its lock or energy.csv, no arrival.vtp, no summary.json).
  std::ofstream(dir + "/energy.csv") << "time_s,step\n";
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir + "/arrival.vtp") && Contains("not found") &&
                                                   Contains("before its first time step"));
  write_solver_summary(dir, "stress");
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir + "/arrival.vtp") && Contains("not found"));
}

TEST_CASE("a switching run whose dynamic part has not begun points to its quasi-static part", "[bad-input]") {
  // pd-solve's folder of a scene with quasi_static.then = "dynamic" stopped
  // after its load steps (its [stop] held at the switch, Ctrl-C, a
  // minimisation that did not converge) holds OUTDIR/quasi_static/ alone when
  // the surface correction is off; before, "not a solver output directory ...
  // give the folder that pd-solve -o wrote".
  const auto dir = fresh_dir("switch_without_dynamic_part");
  const std::string part = dir + "/" + pd::results::quasi_static_part_folder;
  fs::create_directories(part);
  std::ofstream(part + "/" + pd::results::load_steps_file) << "step,load_factor\n";
  CHECK_THROWS_WITH(analyse(options_for(dir)),
                    Contains(dir + "/arrival.vtp: file not found: this switching run's dynamic part stopped (or has "
                             "not begun) before its first time step; its quasi-static part is in " + part +
                             ": run pd-post on that folder"));
  // The part's summary.json alone (pd-solve names itself in it) is as good a sign.
  fs::remove(part + "/" + pd::results::load_steps_file);
  std::ofstream(part + "/" + pd::results::summary_file) << "{\n  \"tool\": \"pd-solve 0.1.0\",\n}\n";
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains("this switching run's dynamic part stopped"));
  // pd-post's own summary.json there (pd-post -o DIR/quasi_static) is no
  // switching run's: before 7 December 2026 any summary.json made it one.
  std::ofstream(part + "/" + pd::results::summary_file) << "{\n  \"tool\": \"pd-post 0.1.0\",\n}\n";
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir + ": not a solver output directory"));
}

TEST_CASE("a folder holding only the surface-correction cache is a refused run's, not a stopped one",
          "[bad-input]") {
  // What a run refused after its set-up (a time step above the stable
  // limit) leaves in a folder that existed: before 7 December 2026 pd-post
  // said the run stopped before its first time step.
  const auto dir = fresh_dir("cache_only");
  std::ofstream(dir + "/surface_correction.cache") << "cache";
  CHECK_THROWS_WITH(analyse(options_for(dir)),
                    Contains(dir + ": no run's results: the folder holds pd-solve's surface-correction cache only") &&
                        !Contains("before its first time step"));
  // With a run's lock beside it, the run stopped there before its first
  // step, or, while a process holds the lock, is setting up (before 7
  // December 2026 "stopped (or is still setting up)" for both).
  const std::string lock = dir + "/.pd-solve.lock";
  std::ofstream(lock) << ::getpid() << "\n";
  const std::string missing = dir + "/arrival.vtp: file not found: pd-solve writes it when the time steps start, at "
                              "every checkpoint and at the end, and there is no summary.json either: ";
  CHECK_THROWS_WITH(analyse(options_for(dir)), missing + "the run stopped before its first time step (killed, or failed)");
  const int held = ::open(lock.c_str(), O_RDONLY);
  REQUIRE(held >= 0);
  REQUIRE(::flock(held, LOCK_EX | LOCK_NB) == 0);  // as a running pd-solve holds it
  CHECK_THROWS_WITH(analyse(options_for(dir)), missing + "the run is still running (pd-solve holds " + lock + ", PID " +
                                                   std::to_string(::getpid()) +
                                                   ") and has not reached its first time step: run pd-post again "
                                                   "once it has");
  ::close(held);
}

TEST_CASE("a threshold without its arrival array is reported with the array name", "[bad-input]") {
  const auto dir = fresh_dir("wrong_threshold");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, {0.5});
  CHECK_THROWS_WITH(analyse(options_for(dir)),
                    Contains("arrival_time_0.35") && Contains("arrival_time_0.50") && Contains("arrival.vtp"));
  // The array that exists is accepted.
  PostOptions o = options_for(dir);
  o.threshold = 0.5;
  CHECK_NOTHROW(analyse(o));
}

TEST_CASE("an empty crack is reported", "[bad-input]") {
  const auto dir = fresh_dir("empty_crack");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), [](double, double) { return -1.0; }, 10e-6);
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains("empty crack") && Contains("arrival_time_0.35"));
}

namespace {

struct ToolRun {
  int status = 0;
  std::string out, err;
};

// Runs the pd-post executable on DIR with `arguments`, capturing its output.
ToolRun run_pd_post(const std::string& dir, const std::string& arguments = "") {
  const std::string out = dir + "/stdout.txt", err = dir + "/stderr.txt";
  const std::string command = std::string("'") + PD_POST_EXECUTABLE + "' '" + dir + "' " + arguments + " > '" + out +
                              "' 2> '" + err + "'";
  ToolRun r;
  r.status = std::system(command.c_str());
  r.out = file_text(out);
  r.err = file_text(err);
  return r;
}

// pd-post run on DIR with `arguments`, which it must refuse: exit status 1
// (not a signal) and no summary.json in DIR/post; its output, for the message.
ToolRun refused_run(const std::string& dir, const std::string& arguments = "") {
  const ToolRun r = run_pd_post(dir, arguments);
  REQUIRE(WIFEXITED(r.status));  // not killed by a signal
  CHECK(WEXITSTATUS(r.status) == 1);
  CHECK_FALSE(fs::exists(dir + "/post/summary.json"));
  return r;
}

// The 4 x 2 mm run with its crack along the row at y = 1.05 mm, its
// arrival.vtp as `run` edits it, refused (refused_run).
ToolRun refused_edited_run(const std::string& dir, const SyntheticRun& run) {
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, run);
  return refused_run(dir);
}

// The options that read the 4 x 2 mm run (its crack along the row at
// y = 1.05 mm, `holes` cut out of the lattice), written into a fresh folder
// NAME, with the pore file NAME/pores.csv that the test writes.
PostOptions with_pore_file(const std::string& name, const std::vector<Hole>& holes = {}) {
  const auto dir = fresh_dir(name);
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3, holes), cracked_row, 10e-6);
  PostOptions o = options_for(dir);
  o.pores_file = dir + "/pores.csv";
  return o;
}

// The same run read with no pore file and a box file of the one `row` after
// its header, which is refused at line 2 with `what` before what it expects.
void check_box_row_refused(PostOptions o, const std::string& row, const std::string& what) {
  o.pores_file.clear();
  o.boxes_file = o.outdir + "/boxes.csv";
  std::ofstream(o.boxes_file) << "# x_min_m,x_max_m,y_min_m,y_max_m\n" << row << "\n";
  CHECK_THROWS_WITH(analyse(o), o.boxes_file + ": line 2: " + what + "x_min_m,x_max_m,y_min_m,y_max_m with min < max");
}

void truncate_file(const std::string& path, double fraction) {
  const std::string text = file_text(path);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text.substr(0, static_cast<std::size_t>(text.size() * fraction));
}
}  // namespace

TEST_CASE("a broken .vtp gives one clean error line naming the file, without VTK's log", "[bad-input]") {
  const auto dir = fresh_dir("broken_vtp");
  const std::string arrival = dir + "/arrival.vtp";
  SECTION("truncated arrays") {
    write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
    truncate_file(arrival, 0.6);
  }
  SECTION("not XML at all") { std::ofstream(arrival) << "this is not a VTK file\n"; }
  SECTION("XML cut short") { std::ofstream(arrival) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\""; }
  const ToolRun r = run_pd_post(dir);
  CHECK(r.status != 0);
  // Exactly one line, and it is pd-post's.
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_THAT(r.err, StartsWith("pd-post: error: " + arrival + ": not a readable VTK PolyData (.vtp) file"));
}

namespace {
// DIR/snapshots/NAME: an undamaged snapshot of `lattice` at `time` [s].
void write_plain_snapshot(const std::string& dir, const Lattice& lattice, const std::string& name, double time) {
  fs::create_directories(dir + "/snapshots");
  const std::size_t n = lattice.x.size();
  pd::write_vtp(dir + "/snapshots/" + name, lattice.x, lattice.y,
                {{pd::results::damage, 1, std::vector<double>(n, 0.0)},
                 {pd::results::strain_energy_density, 1, std::vector<double>(n, 1.0)}},
                {{pd::results::field_time, {time}}});
}

// A fresh folder NAME with the 4 x 2 mm run to 10 us (its crack along the row
// at y = 1.05 mm) and one undamaged snapshot at 2 us,
// snapshots/step_00000100.vtp, which snapshots.pvd lists.
std::string run_with_one_snapshot(const std::string& name) {
  const auto dir = fresh_dir(name);
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  write_arrival_output(dir, lattice, cracked_row, 10e-6);
  write_plain_snapshot(dir, lattice, "step_00000100.vtp", 2e-6);
  pd::write_pvd(dir + "/snapshots.pvd", {{2e-6, "snapshots/step_00000100.vtp"}});
  return dir;
}
}  // namespace

TEST_CASE("a broken snapshot is reported the same way, naming the snapshot", "[bad-input]") {
  const auto dir = run_with_one_snapshot("broken_snapshot");
  truncate_file(dir + "/snapshots/step_00000100.vtp", 0.5);
  const ToolRun r = run_pd_post(dir, "--times 2e-6");
  CHECK(r.status != 0);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_THAT(r.err, Contains("step_00000100.vtp: not a readable VTK PolyData (.vtp) file"));
}

// Reference: the run's own record of each snapshot, snapshots.pvd's
// timestep (17 digits, as the snapshot's 'time'), and the final state's
// particle count, which a refined run's sets only grow to. Before 6 December
// 2026 a snapshot copied in from another run was drawn as this run's.
TEST_CASE("a snapshot of another time than its collection entry, or of more particles than the run, is refused",
          "[bad-input]") {
  const auto dir = fresh_dir("other_runs_snapshot");
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  write_arrival_output(dir, lattice, cracked_row, 10e-6);
  pd::write_pvd(dir + "/snapshots.pvd", {{2e-6, "snapshots/step_00000100.vtp"}});
  // Its own time, to the digits written: drawn.
  write_plain_snapshot(dir, lattice, "step_00000100.vtp", 2e-6);
  REQUIRE(run_pd_post(dir, "--times 2e-6").status == 0);
  write_plain_snapshot(dir, lattice, "step_00000100.vtp", 3e-6);
  ToolRun r = run_pd_post(dir, "--times 2e-6");
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: " + dir + "/snapshots/step_00000100.vtp: is of t = 3e-06 s (field 'time'), and " +
                     dir + "/snapshots.pvd lists it at t = 2e-06 s: the two files are from different runs (a folder "
                     "mixed by copying or moving files); give the folder that one pd-solve run wrote whole, or run "
                     "pd-solve again\n");
  // A refined run's snapshot (with cell sizes) of more particles than its final state.
  const Lattice finer = make_lattice(4e-3, 2e-3, 0.05e-3);
  const std::size_t n = finer.x.size();
  pd::write_vtp(dir + "/snapshots/step_00000100.vtp", finer.x, finer.y,
                {{pd::results::damage, 1, std::vector<double>(n, 0.0)},
                 {pd::results::cell_size, 1, std::vector<double>(n, 0.05e-3)}},
                {{pd::results::field_time, {2e-6}}});
  r = run_pd_post(dir, "--times 2e-6");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains(dir + "/snapshots/step_00000100.vtp: has " + std::to_string(n) +
                             " particles, and the run's final state has " + std::to_string(lattice.x.size()) +
                             " (a refined run's particles only grow in number): the two files are from different runs"));
}

// pd-post draws a snapshot of the run's particle count at arrival.vtp's
// positions: one of those particles in another order (saved again by another
// program) put each value at another particle's place. Before 7 December 2026
// it was drawn so, exit 0.
TEST_CASE("a snapshot of the run's particles in another order is refused, naming the first one out of place",
          "[bad-input]") {
  const auto dir = run_with_one_snapshot("snapshot_reordered");
  REQUIRE(run_pd_post(dir, "--times 2e-6").status == 0);
  // The same snapshot with its particles in reverse order.
  Lattice reversed = make_lattice(4e-3, 2e-3, 0.1e-3);
  std::reverse(reversed.x.begin(), reversed.x.end());
  std::reverse(reversed.y.begin(), reversed.y.end());
  write_plain_snapshot(dir, reversed, "step_00000100.vtp", 2e-6);
  const ToolRun r = run_pd_post(dir, "--times 2e-6");
  REQUIRE(WIFEXITED(r.status));
  CHECK(WEXITSTATUS(r.status) == 1);
  CHECK(r.err == "pd-post: error: " + dir + "/snapshots/step_00000100.vtp: particle 0 is at (0.00395, 0.00195) m, "
                 "and in " + dir + "/arrival.vtp at (5e-05, 5e-05) m: its particles are in another order, or of "
                 "another plate (the file saved again by another program, or another run's); give the snapshot "
                 "pd-solve wrote with the run, or run pd-solve again\n");
  // Positions written to single precision (as another program may save them) are the same particles.
  Lattice rounded = make_lattice(4e-3, 2e-3, 0.1e-3);
  for (auto* v : {&rounded.x, &rounded.y})
    for (double& c : *v) c = static_cast<float>(c);
  write_plain_snapshot(dir, rounded, "step_00000100.vtp", 2e-6);
  CHECK(run_pd_post(dir, "--times 2e-6").status == 0);
}

// A folder or a device where the run's arrival.vtp or a snapshot belongs is
// named for what it is; before 7 December 2026 each was "file not found", of
// a path that was there.
TEST_CASE("an arrival.vtp that is a folder, or a snapshot entry naming a device or a folder, is refused saying so",
          "[bad-input]") {
  const auto dir = run_with_one_snapshot("not_regular_vtp");
  const std::string pvd = dir + "/snapshots.pvd";
  for (const auto& [file, kind] : {std::pair<std::string, std::string>{"/dev/zero", "a device"},
                                   {"snapshots", "a folder"}}) {
    INFO(file);
    pd::write_pvd(pvd, {{2e-6, file}});
    const ToolRun r = refused_run(dir, "--times 2e-6");
    const std::string path = file == "/dev/zero" ? file : dir + "/" + file;
    CHECK(r.err == "pd-post: error: " + path + ": " + kind + ", not a file (a snapshot " + pvd +
                       " lists; give the collection pd-solve wrote)\n");
  }
  fs::remove(dir + "/arrival.vtp");
  fs::create_directory(dir + "/arrival.vtp");
  const ToolRun r = refused_run(dir);
  CHECK(r.err == "pd-post: error: " + dir + "/arrival.vtp: a folder, not a file (the run's arrival-time file, which "
                                          "pd-post reads; give the folder that pd-solve -o wrote)\n");
}

// An input that is a device or a FIFO would be read without end (/dev/zero
// grew each tool to gigabytes in seconds before the second sitting of 5
// December 2026) or block: each tool refuses it in one line, naming it.
TEST_CASE("a device or a FIFO given as an input file is refused by every tool", "[bad-input]") {
  const auto dir = fresh_dir("device_inputs");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(dir, "stress");
  const std::string fifo = dir + "/fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  struct Case {
    std::string command, message;
  };
  const std::string err = dir + "/device_err.txt";
  for (const Case& c : std::vector<Case>{
           {"'" + std::string(PD_SOLVE_EXECUTABLE) + "' /dev/zero -o '" + dir + "/z'",
            "pd-solve: error: /dev/zero: a device, not a file (the scene)"},
           {"'" + std::string(PD_SOLVE_EXECUTABLE) + "' '" + fifo + "' -o '" + dir + "/z'",
            "pd-solve: error: " + fifo + ": a FIFO, not a file (the scene)"},
           {"'" + std::string(PD_MESH_EXECUTABLE) + "' /dev/zero --spacing 1mm --horizon 3mm -o '" + dir + "/z.pdp'",
            "pd-mesh: error: /dev/zero: a device, not a file (the geometry file)"},
           {"'" + std::string(PD_POST_EXECUTABLE) + "' '" + dir + "' --pores /dev/zero",
            "pd-post: error: /dev/zero: a device, not a file (the pore file)"},
           {"'" + std::string(PD_POST_EXECUTABLE) + "' '" + dir + "' --boxes '" + fifo + "'",
            "pd-post: error: " + fifo + ": a FIFO, not a file (the branch box file)"}}) {
    // (timeout: a tool that reads the FIFO would wait for a writer forever.)
    const int status = std::system(("timeout 60 " + c.command + " > /dev/null 2> '" + err + "'").c_str());
    INFO(c.command << "\n" << file_text(err));
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    CHECK(file_text(err) == c.message + "\n");
  }
}

// A snapshot collection cut short, or with an entry whose time is no number,
// is refused naming the file (before the second sitting of 5 December 2026
// it was read as a shorter series, and a map at 10 us was drawn from the
// last entry left; a timestep="nan" entry was dropped without a word).
TEST_CASE("a snapshot collection cut short or with a time that is no number is refused", "[bad-input]") {
  const auto dir = fresh_dir("broken_collection");
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  write_arrival_output(dir, lattice, cracked_row, 10e-6);
  write_plain_snapshot(dir, lattice, "step_00000100.vtp", 2e-6);
  write_plain_snapshot(dir, lattice, "step_00000500.vtp", 1e-5);
  const std::string pvd = dir + "/snapshots.pvd";
  pd::write_pvd(pvd, {{2e-6, "snapshots/step_00000100.vtp"}, {1e-5, "snapshots/step_00000500.vtp"}});
  REQUIRE(run_pd_post(dir, "--times 2e-6,1e-5").status == 0);  // whole, it is read
  const std::string whole = file_text(pvd);
  // Cut within the second entry: one DataSet element left.
  std::ofstream(pvd, std::ios::trunc) << whole.substr(0, whole.find("step_00000500"));
  ToolRun r = run_pd_post(dir, "--times 2e-6,1e-5");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains(pvd + ": does not end with </VTKFile>"));
  // The second entry's time (1e-5 s, its only one starting with 1) as nan.
  const std::string nan_time = std::regex_replace(whole, std::regex("timestep=\"1[^\"]*\""), "timestep=\"nan\"");
  REQUIRE(nan_time != whole);
  std::ofstream(pvd, std::ios::trunc) << nan_time;
  INFO(nan_time);
  r = run_pd_post(dir, "--times 2e-6,1e-5");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains(pvd + ": a DataSet's timestep=\"nan\" is not a finite number"));
  // A negative time in a dynamic run's collection (before 7 December 2026
  // read as a snapshot before the start, exit 0); a quasi-static run's load
  // factors may be negative, and are read (test_quasi_static.cpp).
  std::string negative_time = whole;
  const std::size_t value = negative_time.rfind("timestep=\"", negative_time.find("step_00000100")) + 10;
  negative_time.replace(value, negative_time.find('"', value) - value, "-2e-06");
  std::ofstream(pvd, std::ios::trunc) << negative_time;
  r = run_pd_post(dir, "--times 1e-5");
  CHECK(WEXITSTATUS(r.status) == 1);
  CHECK_THAT(r.err, Contains("pd-post: error: " + pvd +
                             ": the DataSet of file=\"snapshots/step_00000100.vtp\" has timestep=\"-2e-06\", a "
                             "negative time: a dynamic run's snapshots are at t >= 0"));
}

namespace {
// A small quasi-static output directory: a uniform stretch, no crack.
QuasiStaticRun stretched_plate(bool finished) {
  QuasiStaticRun run;
  run.load_factors = {0.5, 1.0};
  run.right_reaction_x = {1.0, 2.0};
  run.ux = [](double x, double) { return 1e-4 * x; };
  run.uy = [](double, double) { return 0.0; };
  run.damage = [](double, double) { return 0.0; };
  run.snapshot_factors = {1.0};
  run.final_state = finished;
  run.summary = finished;
  return run;
}
}  // namespace

TEST_CASE("a quasi-static run: a broken final_state.vtp is one clean line, an unfinished run a warning",
          "[bad-input][quasi-static]") {
  const auto dir = fresh_dir("quasi_static_bad");
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  SECTION("final_state.vtp cut short") {
    write_quasi_static_output(dir, lattice, stretched_plate(true));
    const std::string final_state = dir + "/" + pd::results::final_state_file;
    truncate_file(final_state, 0.5);
    const ToolRun r = run_pd_post(dir);
    CHECK(r.status != 0);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_THAT(r.err, StartsWith("pd-post: error: " + final_state + ": not a readable VTK PolyData (.vtp) file"));
  }
  SECTION("load_steps.csv cut or edited: refused by its count against summary.json, or by a gap in its steps") {
    QuasiStaticRun three = stretched_plate(true);
    three.load_factors = {0.5, 1.0, 1.5};
    three.right_reaction_x = {1.0, 2.0, 3.0};
    write_quasi_static_output(dir, lattice, three);
    const std::string table = dir + "/" + pd::results::load_steps_file, summary = dir + "/summary.json";
    std::string text = file_text(summary);
    text.insert(text.find('{') + 1, "\n  \"load_steps\": 99,");
    std::ofstream(summary) << text;
    ToolRun r = run_pd_post(dir);
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains(table + ": has ") && Contains("load steps, " + summary + " says the run made 99"));
    write_quasi_static_output(dir, lattice, three);
    std::istringstream rows(file_text(table));
    std::string kept, row;
    for (int k = 0; std::getline(rows, row); ++k)
      if (k != 2) kept += row + "\n";  // the second load step's row taken out
    std::ofstream(table) << kept;
    r = run_pd_post(dir);
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains("line 3: load step 3 after load step 1: a row is missing or repeated"));
    // A summary of no known kind.
    write_quasi_static_output(dir, lattice, three);
    text = file_text(summary);
    text.replace(text.find("quasi_static"), 12, "weird");
    std::ofstream(summary) << text;
    r = run_pd_post(dir);
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains("\"mode\" is 'weird', expected \"dynamic\" or \"quasi_static\""));
  }
  SECTION("a first load step other than 1: refused, naming the line and the step") {
    // pd-solve writes load_steps.csv whole from step 1, after a restart too.
    // Before 7 December 2026 a table whose first rows were taken out was
    // read, in a run without summary.json, as the run's from its first
    // remaining row, exit 0.
    for (const bool finished : {false, true}) {
      QuasiStaticRun three = stretched_plate(finished);
      three.load_factors = {0.5, 1.0, 1.5};
      three.right_reaction_x = {1.0, 2.0, 3.0};
      write_quasi_static_output(dir, lattice, three);
      const std::string table = dir + "/" + pd::results::load_steps_file;
      std::string text = file_text(table);
      const std::size_t row = text.find('\n') + 1;
      REQUIRE(text.compare(row, 2, "1,") == 0);
      text.erase(row, text.find('\n', row) + 1 - row);  // load step 1's row
      std::ofstream(table, std::ios::trunc) << text;
      const ToolRun r = run_pd_post(dir);
      INFO(r.err);
      CHECK(WEXITSTATUS(r.status) == 1);
      CHECK(r.err == "pd-post: error: " + table + ": line 2: the first load step is 2, and pd-solve numbers them "
                     "from 1: the rows before it are missing (the file was cut or edited)\n");
    }
  }
  SECTION("a row cut short: refused, saying how many values it has") {
    // Before 7 December 2026 "line 2: 3 values for 4 columns".
    write_quasi_static_output(dir, lattice, stretched_plate(true));
    const std::string table = dir + "/" + pd::results::load_steps_file;
    std::string text = file_text(table);
    const std::size_t header_end = text.find('\n'), row_end = text.find('\n', header_end + 1);
    const auto columns = std::count(text.begin(), text.begin() + header_end, ',') + 1;
    text.erase(text.rfind(',', row_end), row_end - text.rfind(',', row_end));  // the row's last value
    std::ofstream(table, std::ios::trunc) << text;
    const ToolRun r = run_pd_post(dir);
    CHECK(WEXITSTATUS(r.status) == 1);
    CHECK(r.err == "pd-post: error: " + table + ": line 2: found " + std::to_string(columns - 1) + " values, expected " +
                       std::to_string(columns) + ", one for each column of the header\n");
  }
  SECTION("a load step number that is no whole number of an int's range: refused, naming the line") {
    // Before 7 December 2026 1.5 was read as load step 1 and 1e20 cast to an
    // int out of its range (reactions.csv then listed -2147483648), exit 0.
    const std::string table = dir + "/" + pd::results::load_steps_file;
    for (const std::string step : {"1.5", "1e20", "-3"}) {
      write_quasi_static_output(dir, lattice, stretched_plate(true));
      std::string text = file_text(table);
      const std::size_t row = text.find('\n') + 1;
      REQUIRE(text.compare(row, 2, "1,") == 0);
      text.replace(row, 1, step);
      std::ofstream(table, std::ios::trunc) << text;
      const ToolRun r = run_pd_post(dir);
      CHECK(WEXITSTATUS(r.status) == 1);
      CHECK(r.err == "pd-post: error: " + table + ": line 2: column 'step' is '" + step + "', not a load step number "
                     "(pd-solve numbers them 1, 2, 3, ...; the file was edited)\n");
      CHECK_FALSE(fs::exists(dir + "/post/reactions.csv"));
    }
  }
  SECTION("no summary.json and no final state: processed, with warnings") {
    write_quasi_static_output(dir, lattice, stretched_plate(false));
    const ToolRun r = run_pd_post(dir);
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Contains("pd-post: warning: incomplete run: " + dir + "/summary.json does not exist"));
    CHECK_THAT(file_text(dir + "/post/summary.json"), Contains("\"complete\": false"));
  }
}

// summary.json and arrival.vtp both say the plane (the Rayleigh speed
// depends on it): files that disagree are of two runs, or edited.
TEST_CASE("a summary.json whose plane contradicts arrival.vtp's is refused", "[bad-input]") {
  const auto dir = fresh_dir("plane_mismatch");
  SyntheticRun run;
  run.plane = "strain";
  run.plane_strain_field = false;
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, run);
  ToolRun r = run_pd_post(dir);
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("\"plane\" is \"strain\" but ") && Contains("has plane_strain = 0"));
  run.plane_strain_field = true;
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, run);
  r = run_pd_post(dir);
  CHECK(r.status == 0);
}

// summary.json's particle count is compared with arrival.vtp's: one that is
// no count was cast unchecked before 7 December 2026 (-5 and 1e30, out of a
// long's range, passed uncompared, exit 0; 2.5 was said to be 2 particles).
TEST_CASE("a summary.json whose particle count is no count is refused, naming the key", "[bad-input]") {
  const auto dir = fresh_dir("particle_count_no_count");
  for (const std::string count : {"1e30", "-5", "2.5"}) {
    write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, SyntheticRun{});
    const std::string summary = dir + "/summary.json";
    std::string text = file_text(summary);
    text.insert(text.find('{') + 1, "\n  \"counts\": {\"particles\": " + count + ", \"loads\": 2},");
    std::ofstream(summary, std::ios::trunc) << text;
    const ToolRun r = run_pd_post(dir);
    CHECK(WEXITSTATUS(r.status) == 1);
    CHECK(r.err == "pd-post: error: " + summary + ": \"counts.particles\" is " + count + ", expected a count\n");
  }
}

// pd-solve writes each member of summary.json as one JSON type. Before 7
// December 2026 a number given as a string was read as the number, and a
// "counts" or "material" that was no object, an "effects.damage" that was no
// true or false, or a "run_id" that was no string was passed over (the
// checks against arrival.vtp and the damage-off note skipped), exit 0.
TEST_CASE("a summary.json member of another type than pd-solve writes is refused, naming the key", "[bad-input]") {
  const auto dir = fresh_dir("summary_member_type");
  struct Case {
    std::string from, to, message;
  };
  const std::string tail = ": pd-solve writes it so (an edited file); give the summary.json that pd-solve wrote\n";
  for (const Case& c : std::vector<Case>{
           {"{", "{\n  \"steps\": \"500\",", "\"steps\" is the string \"500\", expected a number"},
           {"{", "{\n  \"end_time_s\": \"1e-05\",", "\"end_time_s\" is the string \"1e-05\", expected a number"},
           {"{", "{\n  \"counts\": 800,", "\"counts\" is 800, expected an object ({...})"},
           {"{", "{\n  \"run_id\": 5,", "\"run_id\" is 5, expected a string"},
           {"\"material\": {\"youngs_modulus_Pa\": 3.24e9, \"nested\": [1, 2.5e-3, true, null]}", "\"material\": null",
            "\"material\" is null, expected an object ({...})"},
           {"\"effects\": {\"damage\": true", "\"effects\": {\"damage\": \"no\"",
            "\"effects.damage\" is the string \"no\", expected true or false"}}) {
    write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, SyntheticRun{});
    const std::string summary = dir + "/summary.json";
    std::string text = file_text(summary);
    const auto at = text.find(c.from);
    REQUIRE(at != std::string::npos);
    text.replace(at, c.from.size(), c.to);
    std::ofstream(summary, std::ios::trunc) << text;
    INFO(text);
    const ToolRun r = run_pd_post(dir);
    REQUIRE(WIFEXITED(r.status));
    CHECK(WEXITSTATUS(r.status) == 1);
    CHECK(r.err == "pd-post: error: " + summary + ": " + c.message + tail);
  }
}

TEST_CASE("an unfinished run (no summary.json) is processed with a warning that says so", "[bad-input]") {
  const auto dir = fresh_dir("unfinished");
  SyntheticRun run;
  run.summary = false;  // pd-solve writes summary.json only when a run ends
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, run);
  const ToolRun r = run_pd_post(dir);
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Contains("pd-post: warning: incomplete run: " + dir + "/summary.json does not exist") &&
                        Contains("t = 10 us, step 500"));
  const std::string summary = file_text(dir + "/post/summary.json");
  CHECK_THAT(summary, Contains("\"complete\": false") && Contains("\"warnings\": [\"incomplete run"));

  // The same run once finished: no warning.
  write_solver_summary(dir, "stress");
  const ToolRun finished = run_pd_post(dir);
  CHECK(finished.status == 0);
  CHECK(finished.err.find("warning") == std::string::npos);
  CHECK_THAT(file_text(dir + "/post/summary.json"), Contains("\"complete\": true"));
}

// A killed pd-post leaves at most its temporary files (".tmp.PID.NAME",
// "NAME.tmp.PID": common/atomic_file.hpp) in its folder; the next pd-post
// there removes those of processes that no longer run, and says so. Before,
// they stayed for ever.
TEST_CASE("pd-post removes the temporary files a killed pd-post left in its folder", "[bad-input]") {
  const auto dir = fresh_dir("stale_temporaries");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(dir, "stress");
  // The PID of a killed process: a child that has exited and been reaped.
  const pid_t gone = ::fork();
  REQUIRE(gone >= 0);
  if (gone == 0) ::_exit(0);
  ::waitpid(gone, nullptr, 0);
  const std::string dead = std::to_string(gone), running = std::to_string(::getpid());
  for (const std::string& post : {dir + "/post", dir + "/elsewhere"}) {
    fs::create_directories(post);
    for (const std::string& name : {".tmp." + dead + ".damage_final.png", "crack_tips.csv.tmp." + dead,
                                    ".tmp." + running + ".speed_vs_x.png", std::string("notes.tmp.txt")})
      std::ofstream(post + "/" + name) << "partial";
    const ToolRun r = run_pd_post(dir, post == dir + "/post" ? "" : "-o '" + post + "'");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Contains("pd-post: note: removed 2 temporary files left by a killed run in " + post));
    CHECK_FALSE(fs::exists(post + "/.tmp." + dead + ".damage_final.png"));
    CHECK_FALSE(fs::exists(post + "/crack_tips.csv.tmp." + dead));
    // A running process's (it may be writing it) and a user's file stay.
    CHECK(fs::exists(post + "/.tmp." + running + ".speed_vs_x.png"));
    CHECK(fs::exists(post + "/notes.tmp.txt"));
    CHECK(fs::exists(post + "/damage_final.png"));
  }
}

// A path longer than PATH_MAX is named by its option, clipped (pd::clipped);
// before, "filesystem error: status: File name too long [PATH]".
TEST_CASE("a path longer than PATH_MAX is named by its option", "[bad-input]") {
  const auto dir = fresh_dir("long_path");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(dir, "stress");
  std::string long_path = dir;
  while (long_path.size() <= 4200) long_path += "/" + std::string(200, 'd');
  const std::string shown = long_path.substr(0, 80) + "... (" + std::to_string(long_path.size()) + " characters)";
  const std::string too_long = ": File name too long; give a shorter path\n";
  ToolRun r = run_pd_post(dir, "-o '" + long_path + "'");
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: -o " + shown + too_long);
  // OUTDIR itself (run_pd_post writes its own output beside it).
  const std::string err = dir + "/stderr_long.txt";
  CHECK(pd::test_support::run_shell("'" + std::string(PD_POST_EXECUTABLE) + "' '" + long_path + "' 2> '" + err + "'") ==
        1);
  CHECK(file_text(err) == "pd-post: error: " + shown + too_long);
}

// Two symbolic links that lead to each other: before 7 December 2026 "Too
// many levels of symbolic links" alone, what to do unsaid.
TEST_CASE("a path through a symbolic link that leads back to itself is named by its option, with what to do",
          "[bad-input]") {
  const auto dir = fresh_dir("link_loop");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(dir, "stress");
  const std::string loop = dir + "/loop", back = dir + "/back";
  fs::create_symlink(back, loop);
  fs::create_symlink(loop, back);
  const std::string advice = ": Too many levels of symbolic links: a symbolic link on the path leads back to itself, "
                             "or through more than 40 links (ls -l shows where each leads); mend or remove the link, "
                             "or give a path without it\n";
  ToolRun r = run_pd_post(dir, "-o '" + loop + "/post'");
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: -o " + loop + "/post" + advice);
  const std::string err = dir + "/stderr_loop.txt";
  CHECK(pd::test_support::run_shell("'" + std::string(PD_POST_EXECUTABLE) + "' '" + loop + "' 2> '" + err + "'") == 1);
  CHECK(file_text(err) == "pd-post: error: " + loop + advice);
}

// pd-post's report on stdout that cannot be written (/dev/full) fails it
// with one line on stderr; before, exit 0 with the report lost.
TEST_CASE("pd-post fails when its report cannot be written to stdout", "[bad-input]") {
  const auto dir = fresh_dir("stdout_full");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(dir, "stress");
  const std::string err = dir + "/stderr_full.txt";
  CHECK(pd::test_support::run_shell("'" + std::string(PD_POST_EXECUTABLE) + "' '" + dir + "' > /dev/full 2> '" + err +
                                    "'") == 1);
  CHECK(file_text(err) ==
        "pd-post: error: cannot write to standard output: No space left on device; the report printed there is lost\n");
  CHECK(run_pd_post(dir).status == 0);
}

TEST_CASE("damage is reported from 0 to 1: round-off clamped, anything else an error", "[bad-input]") {
  const auto dir = fresh_dir("damage_range");
  SyntheticRun run;
  SECTION("single-precision round-off above 1") {
    run.cracked_damage = 1.00000003;
    write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, run);
    PostOptions o = options_for(dir);
    const PostResult r = run_post(o);
    CHECK(r.max_damage == 1.0);
    for (double d : r.data.damage) CHECK((d >= 0.0 && d <= 1.0));
    CHECK_THAT(file_text(dir + "/post/summary.json"), Contains("\"max_damage\": 1,"));
  }
  SECTION("a damage of 1.5 is not round-off") {
    run.cracked_damage = 1.5;
    write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, run);
    CHECK_THROWS_WITH(analyse(options_for(dir)),
                      Contains(dir + "/arrival.vtp") && Contains("'damage' is 1.5 at particle") &&
                          Contains("outside [0, 1]"));
  }
}

// pd-solve writes each key once. Before 7 December 2026 a summary.json with
// a key twice (edited, or two files joined) was read with the last of them
// standing for the first, the "plane" of the Rayleigh speed or the "mode"
// of the run included, exit 0.
TEST_CASE("a solver summary.json with a key given twice is refused, naming the key", "[bad-input]") {
  const auto dir = fresh_dir("summary_key_twice");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  std::ofstream(dir + "/summary.json") << "{\"tool\": \"pd-solve 0.1.0\", \"plane\": \"stress\", \"counts\": "
                                          "{\"particles\": 800}, \"plane\": \"strain\"}";
  CHECK(refused_run(dir).err == "pd-post: error: " + dir + "/summary.json: the key \"plane\" is given twice (again "
                                "at byte 76): pd-solve writes each key once (an edited file, or two joined); give the "
                                "summary.json that pd-solve wrote\n");
  // Inside an object too.
  std::ofstream(dir + "/summary.json") << "{\"tool\": \"pd-solve 0.1.0\", \"counts\": {\"particles\": 800, "
                                          "\"particles\": 7}}";
  CHECK_THAT(refused_run(dir).err, Contains("the key \"particles\" is given twice"));
}

TEST_CASE("a summary.json that is not JSON is reported with its path", "[bad-input]") {
  const auto dir = fresh_dir("bad_summary");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  std::ofstream(dir + "/summary.json") << "{\n  \"plane\": \"stress\",\n  \"steps\": 12\n";  // cut short
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir + "/summary.json: not valid JSON"));
  std::ofstream(dir + "/summary.json") << "{\"plane\": \"sideways\"}";
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains("\"plane\" is 'sideways'"));
  // Valid JSON that pd-solve did not write: before 6 December 2026 "{}" (or
  // another tool's summary) made the folder a finished run's, exit 0.
  std::ofstream(dir + "/summary.json") << "{}";
  CHECK_THROWS_WITH(analyse(options_for(dir)),
                    Contains(dir + "/summary.json: has no \"tool\": not a summary.json that pd-solve wrote"));
  std::ofstream(dir + "/summary.json") << "{\"tool\": \"pd-post 0.1.0\", \"complete\": true}";
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains("its \"tool\" is 'pd-post 0.1.0': not a summary.json"));
}

TEST_CASE("options that would end in a silent default or in another run's files are refused", "[bad-input]") {
  const auto dir = fresh_dir("refused_options");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(dir, "stress");
  const std::string solver_summary = file_text(dir + "/summary.json");
  struct Case {
    std::string arguments, message;
  };
  for (const Case& c : std::vector<Case>{
           {"--window-time 0", "--window-time must be a positive number of seconds"},
           // The value named (before 6 December 2026: "--window must be at
           // least 1 solver step", "--angle-length must be a positive length").
           {"--window 0", "--window 0: must be at least 1 solver step"},
           {"--window -3", "--window -3: must be at least 1 solver step"},
           {"--angle-length 0mm", "--angle-length: 0mm is not a positive length"},
           // Before 7 December 2026 taken: a fit over no particle, or over
           // lengths no plate has.
           {"--angle-length 1e-300m", "pd-post: error: --angle-length 1e-297 mm is shorter than the run's particle "
                                      "spacing (0.1 mm): give a length from the spacing to the plate's diagonal, 0.1 "
                                      "to 4.47214 mm, with its unit (e.g. --angle-length 2mm)\n"},
           {"--angle-length 1e300m", "pd-post: error: --angle-length 1e+303 mm is longer than the plate's diagonal "
                                     "(4.47214 mm): give a length from the spacing to the plate's diagonal, 0.1 to "
                                     "4.47214 mm, with its unit (e.g. --angle-length 2mm)\n"},
           {"--angle-length 5mm", "--angle-length 5 mm is longer than the plate's diagonal (4.47214 mm)"},
           {"--window-time -1e-6", "--window-time must be a positive number of seconds"},
           {"--window-time 2furlongs", "--window-time: unknown unit 'furlongs'"},
           // More steps (of 20 ns) than an int counts: before 7 December 2026
           // the count wrapped round, here to a window of 705,032,704 steps,
           // exit 0 (elsewhere below 0: "rounds to 0 solver steps").
           {"--window-time 100", "--window-time 100 s is 5e+09 solver steps (one step is 2e-08 s), more than the "
                                 "2147483647 a window can span: times are in s, or give the unit"},
           {"--times 5us,2ly", "--times 2ly: item 2 of '5us,2ly' is not a time: unknown unit 'ly'"},
           // The example is one word, as the command line takes it (before
           // 7 December 2026 '80 us', a scene's form, which splits in two).
           {"--times abc", "pd-post: error: --times abc: item 1 of 'abc' is not a finite number: give times from 0, "
                           "in s or with their unit, comma-separated, e.g. --times 1.5e-4,300us\n"},
           {"--window-time us", "pd-post: error: --window-time: 'us' is not a number with a unit (e.g. '80us')"},
           {"--band 0mm --reference '" + dir + "'", "--band: 0mm is not a positive length"},
           {"--line 1mm,1mm,3mm,1mm --line-offset -1mm", "--line-offset: -1mm is not a positive length"},
           {"--line-offset 1mm", "--line-offset 1mm needs --line"},
           {"--times nan", "--times nan: item 1 of 'nan' is not a finite number"},
           {"--zoom 1mm,2mm,1mm,2mm", "--zoom is a window of --particles' pictures"},
           {"--particles plate.pdp", "give either OUTDIR (a run's results) or --particles FILE"},
           // pd-post's summary.json would replace the solver's.
           {"-o '" + dir + "'", "is the run's own folder"},
           {"-o '" + dir + "/.'", "is the run's own folder"},
           // Through a folder that does not exist yet: before 7 December 2026
           // it resolved to "OUTDIR/", unequal to OUTDIR, and pd-post made
           // OUTDIR/new and wrote its summary.json over the run's, exit 0.
           {"-o '" + dir + "/new/..'", "-o " + dir + "/new/.. is the run's own folder"},
           {"-o '" + dir + "/new/../snapshots'", "is inside the run's snapshots/ folder"},
           // The subfolders pd-solve writes: before 6 December 2026, -o
           // OUTDIR/snapshots wrote pd-post's summary.json among the
           // snapshots, exit 0.
           {"-o '" + dir + "/snapshots'", "-o " + dir + "/snapshots is inside the run's snapshots/ folder (" + dir +
                                              "/snapshots), which pd-solve writes"},
           {"-o '" + dir + "/snapshots/post'", "is inside the run's snapshots/ folder"},
           {"-o '" + dir + "/post/../snapshots/'", "is inside the run's snapshots/ folder"},
           // (Where pd-solve writes a switching run's quasi-static part: a
           // summary.json of pd-post's there stops the next pd-solve run.)
           {"-o '" + dir + "/quasi_static'", "-o " + dir + "/quasi_static is the folder where pd-solve writes a "
                                             "switching run's quasi-static part"},
           // An empty value (an unset shell variable) read as the option left
           // out: before 6 December 2026 no comparison, the default folder,
           // no maps, exit 0.
           {"--reference ''", "--reference: the value is empty (''; an unset shell variable?): give one, or leave "
                              "--reference out"},
           {"-o ''", "--output: the value is empty"},
           {"--times ''", "--times: the value is empty"},
           {"--boxes ''", "--boxes: the value is empty"},
           // An abbreviated option: before 7 December 2026 Boost took
           // `--thresh` for --threshold (an option added later that begins
           // the same way would change what it means), `--win` was called
           // ambiguous.
           {"--thresh 0.35", "pd-post: error: --thresh: no such option; did you mean --threshold?"},
           {"--win=5", "pd-post: error: --win: no such option; did you mean --window or --window-time?"},
           // A length typed with a space before its unit: before 7 December
           // 2026 Boost's "too many positional options have been specified on
           // the command line", naming neither the 'mm' nor the cause.
           {"--angle-length 2 mm", "pd-post: error: unexpected argument 'mm' after '" + dir +
                                       "', the one argument pd-post takes besides its options: an option's value "
                                       "is one word, with no space before its unit (0.5mm, 80us)"}}) {
    const ToolRun r = run_pd_post(dir, c.arguments);
    INFO(c.arguments << "\n" << r.err);
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains(c.message));
  }
  CHECK(file_text(dir + "/summary.json") == solver_summary);
  CHECK_FALSE(fs::exists(dir + "/new"));
  CHECK_FALSE(fs::exists(dir + "/snapshots/summary.json"));
  CHECK_FALSE(fs::exists(dir + "/snapshots/post"));
  // A folder beside them whose name only begins as theirs is pd-post's to use.
  CHECK(run_pd_post(dir, "-o '" + dir + "/snapshots_post'").status == 0);
  // Another run's folder, or a folder whose summary.json is not pd-post's,
  // given to -o: refused, the files left as they were (before the second
  // sitting of 5 December 2026 pd-post wrote its summary.json over them).
  const auto other = fresh_dir("refused_options_other_run");
  write_arrival_output(other, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(other, "stress");
  const std::string other_summary = file_text(other + "/summary.json");
  ToolRun r = run_pd_post(dir, "-o '" + other + "'");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("-o " + other + " holds a solver run's results (" + other + "/arrival.vtp)"));
  CHECK(file_text(other + "/summary.json") == other_summary);
  // The same through a folder that does not exist yet (before 7 December
  // 2026 its files were looked for through it, not found, and replaced).
  r = run_pd_post(dir, "-o '" + other + "/new/..'");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("-o " + other + "/new/.. holds a solver run's results (" + other + "/new/../arrival.vtp)"));
  CHECK(file_text(other + "/summary.json") == other_summary);
  CHECK_FALSE(fs::exists(other + "/new"));
  const auto users = fresh_dir("refused_options_users_folder");
  std::ofstream(users + "/summary.json") << "{\"mine\": 1}";
  r = run_pd_post(dir, "-o '" + users + "'");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains(users + "/summary.json is not pd-post's"));
  CHECK(file_text(users + "/summary.json") == "{\"mine\": 1}");
  // pd-post's own folder is written again.
  const auto own = fresh_dir("refused_options_own_folder");
  REQUIRE(run_pd_post(dir, "-o '" + own + "'").status == 0);
  CHECK(run_pd_post(dir, "-o '" + own + "'").status == 0);
  // A particle file given for OUTDIR points to --particles (before 5 December
  // 2026: "solver output directory not found").
  const auto plate = dir + "/plate.pdp";
  std::ofstream(plate, std::ios::binary) << std::string("PDPARTS\0", 8) << "(the rest of a particle file)";  // its magic
  const std::string err = dir + "/particle_file_as_outdir.txt";
  const int status = std::system(("'" + std::string(PD_POST_EXECUTABLE) + "' '" + plate + "' 2> '" + err + "'").c_str());
  INFO(file_text(err));
  CHECK(status != 0);
  CHECK_THAT(file_text(err), Contains(plate + ": a particle file, not a solver output directory; for pictures of its grid "
                                     "give it as --particles " + plate));
  // Any other file (a scene) is named as a file (before 5 December 2026: "solver output directory not found").
  const auto scene = dir + "/scene.toml";
  std::ofstream(scene) << "particles = \"plate.pdp\"\n";
  CHECK(std::system(("'" + std::string(PD_POST_EXECUTABLE) + "' '" + scene + "' 2> '" + err + "'").c_str()) != 0);
  CHECK_THAT(file_text(err), Contains(scene + ": a file, not a solver output directory: pd-post reads the folder that "
                                      "pd-solve -o wrote"));
}

TEST_CASE("a pore file off the plate (mm for m) is refused, an empty one warned about", "[bad-input][pores]") {
  PostOptions o = with_pore_file("pores_off_plate");
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n2,1,0.5\n";  // millimetres
  CHECK_THROWS_WITH(analyse(o), Contains(o.pores_file) && Contains("pore 1 at (2, 1) m lies off the plate"));
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n";
  const auto r = analyse(o);
  CHECK(r.pores.empty());
  CHECK_THAT(r.warnings.back(), Contains("lists no pore"));
}

// Another file given as --pores by mistake is refused as no pore file, naming
// it and what a pore file holds: before 7 December 2026 a geometry whose
// lines all begin with letters was read as a header and no row ("lists no
// pore", exit 0), a scene as a pore file with a row cut short ("line 9:
// found 1 value, expected 3"), a particle file as whatever its bytes made.
// A header alone, or comments alone, is still a pore file without a pore.
TEST_CASE("a file given as --pores that is no pore file is refused as such", "[bad-input][pores]") {
  PostOptions o = with_pore_file("pores_wrong_file");
  const std::string expected = ", not the pore file: expected a text file of lines x_m,y_m,r_m with r_m > 0, one per line";
  std::ofstream(o.pores_file) << "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 4, 2};\n";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 2: 'Rectangle(1) = {0, 0, 0, 4, 2};' is a second line of "
                                               "words after the header (line 1), and no line holds numbers: a text "
                                               "file" + expected);
  std::ofstream(o.pores_file) << "# C3-A\nparticles = \"plate.pdp\"\n\n[material]\nyoungs_modulus = 3.24e9\n";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 4: '[material]' is no row of numbers, and no line before it "
                                               "holds one: a text file" + expected);
  std::ofstream(o.pores_file, std::ios::binary) << std::string("PDPARTS\0", 8) << "(the rest of a particle file)";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": a particle file" + expected);
  std::ofstream(o.pores_file, std::ios::binary) << "x_m,y_m,r_m\n" << std::string("\x01\0\x02", 3) << "\n";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 2: binary data (a NUL byte)" + expected);
  // A pore file without a pore: warned about, as before.
  std::ofstream(o.pores_file, std::ios::trunc) << "# no pores in this plate\nx_m,y_m,r_m\n";
  const auto r = analyse(o);
  CHECK(r.pores.empty());
  CHECK(r.warnings.back() == o.pores_file + " lists no pore: no pore visits are looked for");
}

// A line of words after the rows is no header: a mistyped row (a letter O
// for a zero) or pasted text. Before 7 December 2026 it was skipped without
// a word, its pore or box dropped, exit 0.
TEST_CASE("a pore or box file with a line of words after its rows is refused, naming the line and its text",
          "[bad-input][pores]") {
  PostOptions o = with_pore_file("pores_words_after_rows");
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n\n0.002,0.0016,0.0002\n# a comment\nO.003,0.0004,0.0002\n";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 5: 'O.003,0.0004,0.0002' is a line of words after the rows "
                                               "(the first on line 3): only a header, before the rows, may hold "
                                               "words; make it a row of numbers, a comment ('# ...'), or remove it: "
                                               "expected x_m,y_m,r_m with r_m > 0");
  // Without a header too.
  std::ofstream(o.pores_file) << "0.002,0.0016,0.0002\nend of the pores\n";
  CHECK_THROWS_WITH(analyse(o), Contains(o.pores_file + ": line 2: 'end of the pores' is a line of words after the "
                                         "rows (the first on line 1)"));
  o.pores_file.clear();
  o.boxes_file = o.outdir + "/boxes.csv";
  std::ofstream(o.boxes_file) << "x_min_m,x_max_m,y_min_m,y_max_m\n0,0.004,0,0.002\nx_min_m,x_max_m,y_min_m,y_max_m\n";
  CHECK_THROWS_WITH(analyse(o), Contains(o.boxes_file + ": line 3: 'x_min_m,x_max_m,y_min_m,y_max_m' is a line of "
                                         "words after the rows (the first on line 2)"));
  // A header and comments around the rows still read.
  std::ofstream(o.boxes_file) << "# boxes\nx_min_m,x_max_m,y_min_m,y_max_m\n0,0.004,0,0.002  # the whole plate\n"
                                 "# end\n";
  CHECK_NOTHROW(analyse(o));
}

// "nan" and "inf" begin with a letter, as a header does: before 7 December
// 2026 a row beginning with one was skipped as a header (its pore dropped,
// the file said to list none), and one elsewhere in a row said only what was
// expected.
TEST_CASE("a pore or box file with a value that is not finite is refused, naming the line and the value",
          "[bad-input][pores]") {
  PostOptions o = with_pore_file("pores_not_finite");
  const std::vector<std::pair<std::string, std::string>> rows{{"nan,0.001,0.0002", "nan"},
                                                              {"inf,0.001,0.0002", "inf"},
                                                              {"0.002,NaN,0.0002", "NaN"},
                                                              {"0.002,0.001,1e999", "1e999"}};
  for (const auto& [row, value] : rows) {
    std::ofstream(o.pores_file) << "x_m,y_m,r_m\n" << row << "\n";
    CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 2: '" + value +
                                      "' is not a finite number: expected x_m,y_m,r_m with r_m > 0");
  }
  check_box_row_refused(o, "inf,0.002,0,0.002", "'inf' is not a finite number: expected ");
}

// Before 7 December 2026 a row cut short said only what was expected
// ("line 2: expected x_m,y_m,r_m with r_m > 0"), not what was found.
TEST_CASE("a pore or box file's row cut short is refused, saying how many values it has", "[bad-input][pores]") {
  PostOptions o = with_pore_file("pores_short_row");
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.001\n";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 2: found 2 values, expected 3: x_m,y_m,r_m with r_m > 0");
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.001,0.0005\n  0.003  # radius left out\n";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 3: found 1 value, expected 3: x_m,y_m,r_m with r_m > 0");
  check_box_row_refused(o, "0,0.002,0", "found 3 values, expected 4: ");
}

// A spreadsheet saves "CSV UTF-8" with a byte order mark and CR LF line
// ends: the mark is no character of the table. Before 7 December 2026 such a
// file was refused at line 1 as "no row of numbers" (the mark unseen, the
// text looking like a header), UTF-16 text as "binary data (a NUL byte)",
// and values separated by ';' as "expected ...", the separator unsaid.
TEST_CASE("a pore or box file saved by a spreadsheet: its byte order mark and CR LF read, UTF-16 and semicolons named",
          "[bad-input][pores]") {
  // A hole of radius 0.5 mm at (2, 1) mm.
  PostOptions o = with_pore_file("pores_byte_order_mark", {{2e-3, 1e-3, 0.5e-3}});
  for (const std::string& table : std::vector<std::string>{"\xEF\xBB\xBFx_m,y_m,r_m\r\n0.002,0.001,0.0005\r\n",
                                  "\xEF\xBB\xBF" "0.002,0.001,0.0005\r\n"}) {
    std::ofstream(o.pores_file, std::ios::binary | std::ios::trunc) << table;
    const auto r = analyse(o);
    REQUIRE(r.pores.size() == 1);
    CHECK(r.pores[0].x == 0.002);
    CHECK(r.pores[0].radius == 0.0005);
    CHECK(r.pores[0].line == (table.find('x') != std::string::npos ? 2 : 1));
  }
  // UTF-16 (a spreadsheet's "Unicode text"), little- and big-endian.
  for (const std::string& mark : {std::string("\xFF\xFE"), std::string("\xFE\xFF")}) {
    std::ofstream(o.pores_file, std::ios::binary | std::ios::trunc) << mark << std::string("x\0_\0m\0\n\0", 8);
    CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 1: UTF-16 text (it begins with the byte order mark " +
                                      (mark[0] == '\xFF' ? "FF FE" : "FE FF") + "), and the pore file is plain text "
                                      "or UTF-8: save it as \"CSV UTF-8\" or \"CSV (comma delimited)\", lines "
                                      "x_m,y_m,r_m with r_m > 0, one per line");
  }
  // A spreadsheet's CSV where the decimal point is a comma: ';' between values.
  std::ofstream(o.pores_file, std::ios::binary | std::ios::trunc) << "x_m;y_m;r_m\r\n0,002;0,001;0,0005\r\n";
  CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 2: '0,002;0,001;0,0005' separates its values by ';' (a "
                                               "spreadsheet's CSV where the decimal point is a comma?): separate "
                                               "them by commas or blanks, with '.' as the decimal point: expected "
                                               "x_m,y_m,r_m with r_m > 0");
  // The box file, through the same reader: its box is read.
  o.pores_file.clear();
  o.boxes_file = o.outdir + "/boxes.csv";
  std::ofstream(o.boxes_file, std::ios::binary) << "\xEF\xBB\xBFx_min_m,x_max_m,y_min_m,y_max_m\r\n0,0.004,0,0.002\r\n";
  CHECK(analyse(o).network.branches.size() == 1);
}

// pd-solve writes energy.csv whole, a new file moved over the old one (after
// a restart too, from the checkpoint's rows), never a row at a time: a killed
// run leaves no row cut short. Before 7 December 2026 a row shorter than its
// run_id column was passed over, its identifier unread, and a row cut after
// its last comma (an empty run_id) or with a value more was compared as a
// whole one (exit 0).
TEST_CASE("an energy.csv row cut short, in the middle or at the end, is refused naming the line and the counts",
          "[bad-input]") {
  const auto dir = fresh_dir("energy_row_cut");
  const std::string id = "d36793fa2a3235fa", energy = dir + "/" + pd::results::energy_file;
  SyntheticRun run;
  run.edited_fields = {{pd::results::field_run_id, {}, id}};
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, run);
  const std::string header = "time_s,step,kinetic_J,strain_J,external_work_J,total_minus_work_J,broken_bonds,"
                             "particles,run_id\n";
  const std::string first = "0,0,0,0,0,0,0,800," + id + "\n", last = "1e-05,500,1e-06,2e-06,3e-06,0,12,800," + id + "\n";
  struct Case {
    std::string table, message;
  };
  const std::string length = ", one for each column of the header: pd-solve writes every row whole";
  for (const Case& c : std::vector<Case>{
           {header + "0,0,0\n" + last, "line 2: found 3 values, expected 9" + length},  // in the middle
           {header + first + "1e-05,500,1e-06,2e-06", "line 3: found 4 values, expected 9" + length},  // the last
           {header + "0,0,0,0,0,0,0,800," + id + ",7\n" + last, "line 2: found 10 values, expected 9" + length},
           {header + first + "1e-05,500,1e-06,2e-06,3e-06,0,12,800,",  // cut after its last comma
            "line 3: column 'run_id' is empty: pd-solve writes the run's identifier on every row"}}) {
    std::ofstream(energy, std::ios::trunc) << c.table;
    INFO(c.table);
    CHECK(refused_run(dir).err == "pd-post: error: " + energy + ": " + c.message + " (the file was cut or edited)\n");
  }
  // Whole, the same table is read.
  std::ofstream(energy, std::ios::trunc) << header << first << last;
  const ToolRun r = run_pd_post(dir);
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("map times after the run's end are a warning naming the unit", "[bad-input]") {
  const auto dir = fresh_dir("times_after_end");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);  // ends at 10 us
  write_solver_summary(dir, "stress");
  PostOptions o = options_for(dir);
  o.map_times = {5.0};  // 5 s, meant as 5 us
  const auto r = analyse(o);
  REQUIRE_FALSE(r.warnings.empty());
  CHECK_THAT(r.warnings.back(), Contains("is after the run's end at") && Contains("times are in s, or give the unit"));
  o.map_times = {5e-6};
  for (const auto& w : analyse(o).warnings) CHECK_THAT(w, !Contains("after the run's end"));
}

TEST_CASE("a reference run of another plate is refused", "[bad-input]") {
  // Reference: the plate's extents; the band comparison means nothing across plates.
  const auto dir = fresh_dir("reference_this"), other = fresh_dir("reference_other");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_arrival_output(other, make_lattice(8e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  PostOptions o = options_for(dir);
  o.reference_dir = other;
  CHECK_THROWS_WITH(analyse(o), Contains("--reference: not the same plate"));
  // The same plate at half the spacing is a reference.
  write_arrival_output(other, make_lattice(4e-3, 2e-3, 0.05e-3), cracked_row, 10e-6);
  CHECK_NOTHROW(analyse(o));
}

// A plate edited to lie 1e16 m from the origin has its cells rounded into
// one point: before 7 December 2026 pd-post crashed in its pore search
// (SIGSEGV), and --reference would have put x / band, beyond 2^63, through
// its buckets' integer cast (undefined behaviour). Refused as the file is
// read, naming it and the particle: the run's, or the reference's alone.
TEST_CASE("a run or reference whose positions are not resolved to their cells is refused, naming the file",
          "[bad-input][comparison]") {
  const auto dir = fresh_dir("far_run"), reference = fresh_dir("far_reference");
  const Lattice near = make_lattice(4e-3, 2e-3, 0.1e-3);
  Lattice far = near;
  for (double& x : far.x) x += 1e16;
  write_arrival_output(dir, far, [](double, double y) { return cracked_row(1e-3, y); }, 10e-6);
  write_arrival_output(reference, far, [](double, double y) { return cracked_row(1e-3, y); }, 10e-6);
  const std::string message = "/arrival.vtp: points: particle 0 is at (1e+16, 5e-05) m, so far from the origin that "
                              "its position's round-off, 2.22 m, is more than a millionth of its cell (0.1 mm): its "
                              "cells cannot be told apart there (an edited or damaged file); pd-mesh writes a plate "
                              "where its geometry file draws it\n";
  CHECK(refused_run(dir).err == "pd-post: error: " + dir + message);
  CHECK(refused_run(dir, "--reference '" + reference + "'").err == "pd-post: error: " + dir + message);
  write_arrival_output(dir, near, cracked_row, 10e-6);
  CHECK(refused_run(dir, "--reference '" + reference + "'").err == "pd-post: error: " + reference + message);
}

// The comparison's buckets are x / band as integers: beyond 2^52 bands
// from the origin a position's round-off is more than the band, and past
// 2^63 the cast is undefined. Before 7 December 2026 two runs 1e9 m from the
// origin, compared with a band of 2e-7 m (positions rounded to 1.2e-7 m),
// had their damage counted within the band.
TEST_CASE("a comparison band that positions are not resolved to is refused, naming the file and the particle",
          "[bad-input][comparison]") {
  ArrivalData run;
  run.path = "RUN/arrival.vtp";
  run.spacing = 1e-4;
  for (int i = 0; i < 4; ++i) {
    run.x.push_back(1e9 + i * 1e-4), run.y.push_back(1e-3);
    run.damage.push_back(1), run.cell_size.push_back(1e-4);
  }
  ArrivalData reference = run;
  reference.path = "REF/arrival.vtp";
  CHECK_THROWS_WITH(compare_damage(run, reference, 2e-7, 0.2),
                    "REF/arrival.vtp: particle 0 is at (1e+09, 0.001) m, 5e+15 bands of 0.0002 mm from the origin: "
                    "beyond 2^52 bands its position's round-off exceeds the band, and no damage can be placed within "
                    "it (an edited or damaged file); give a run whose plate lies near the origin, as pd-mesh writes it");
  // A band of twice that is resolved: the four particles lie within it.
  const auto c = compare_damage(run, reference, 4e-7, 0.2);
  CHECK(c.damaged == 4);
  CHECK(c.outside == 0);
}

// A quasi-static run has no arrival.vtp to compare with: before 7 December
// 2026 "REF/arrival.vtp: file not found (pd-post needs the solver's
// arrival-time file)", without the option or what the folder is.
TEST_CASE("a reference that is a quasi-static run is refused as one", "[bad-input][comparison]") {
  const auto dir = fresh_dir("reference_dynamic"), quasi_static = fresh_dir("reference_quasi_static");
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  write_arrival_output(dir, lattice, cracked_row, 10e-6);
  write_quasi_static_output(quasi_static, lattice, stretched_plate(true));
  PostOptions o = options_for(dir);
  o.reference_dir = quasi_static;
  CHECK_THROWS_WITH(analyse(o), "--reference " + quasi_static + " is a quasi-static run: --reference compares the "
                                "damage of dynamic runs (their arrival.vtp); give a dynamic run of the same plate");
  // Its folder without summary.json (a run still going): known by its load_steps.csv.
  fs::remove(quasi_static + "/summary.json");
  CHECK_THROWS_WITH(analyse(o), Contains("--reference " + quasi_static + " is a quasi-static run"));
}

// Reference: the comparison means "this run's damage against another run's";
// against itself it finds nothing outside the band by construction. Before 6
// December 2026 it reported that 0 with no word, exit 0.
TEST_CASE("a reference that is the run itself is refused, also by another path", "[bad-input][comparison]") {
  const auto dir = fresh_dir("reference_itself");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const std::string link = dir + "_link";
  fs::remove(link);
  fs::create_directory_symlink(dir, link);
  for (const std::string& reference : {dir, dir + "/.", dir + "/../" + fs::path(dir).filename().string(), link}) {
    const ToolRun r = run_pd_post(dir, "--reference '" + reference + "'");
    INFO(reference << "\n" << r.err);
    CHECK(r.status != 0);
    CHECK_THAT(r.err, Contains("pd-post: error: --reference " + reference + " is this run's own folder (OUTDIR " + dir +
                               "): a run compared with itself has no damage outside the band"));
  }
  CHECK_FALSE(fs::exists(dir + "/post/summary.json"));
  // A copy of the run elsewhere is another folder: compared (0 outside).
  const auto copy = fresh_dir("reference_itself_copy");
  fs::copy(dir, copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  PostOptions o = options_for(dir);
  o.reference_dir = copy;
  const auto r = analyse(o);
  REQUIRE(r.comparison);
  CHECK(r.comparison->outside == 0);
}

TEST_CASE("non-finite or impossible fields of arrival.vtp are refused by name", "[bad-input]") {
  const auto dir = fresh_dir("bad_fields");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, std::numeric_limits<double>::infinity());
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir + "/arrival.vtp") && Contains("'end_time' is not finite"));
  // A negative end_time, named as such: before 7 December 2026 refused as the
  // arrival times after it, or, in a plate without a crack, as an empty one.
  const auto no_crack = [](double, double) { return -1.0; };
  SyntheticRun run;
  run.end_time_field = -1e-5;
  for (const bool cracked : {true, false}) {
    write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked ? cracked_row : no_crack, 10e-6, run);
    CHECK_THROWS_WITH(analyse(options_for(dir)),
                      dir + "/arrival.vtp: field 'end_time' = -1e-05 s is negative: pd-solve writes the time the "
                            "run reached, from 0 on (an edited or damaged file)");
  }
}

// pd-solve writes finite values only (an arrival time never reached is -1).
// Before 7 December 2026 a NaN or an infinity in 'cell_size' or
// 'strain_energy_density' reached the pictures, whose colour map indexed its
// table with it (pd-post died of signal 11), a NaN arrival time was read as a
// particle never reached, and a snapshot of time NaN was drawn as
// damage_tnanus.png, exit 0.
TEST_CASE("a non-finite value in a point array of arrival.vtp or a snapshot is refused, naming array and particle",
          "[bad-input]") {
  const auto dir = fresh_dir("non_finite_point_values");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  // The first particle of the cracked row, whose arrival time is recorded.
  std::size_t first_cracked = 0;
  while (cracked_row(lattice.x[first_cracked], lattice.y[first_cracked]) < 0) ++first_cracked;
  std::string arguments, message;
  SECTION("a cell size in arrival.vtp") {
    lattice.cell_size.assign(lattice.x.size(), lattice.spacing);
    lattice.cell_size[7] = nan;
    write_arrival_output(dir, lattice, cracked_row, 10e-6);
    message = dir + "/arrival.vtp: point array 'cell_size' is nan at particle 7";
  }
  SECTION("an arrival time in arrival.vtp") {
    const double x_nan = lattice.x[first_cracked], y_nan = lattice.y[first_cracked];
    const auto arrival = [&](double x, double y) { return x == x_nan && y == y_nan ? nan : cracked_row(x, y); };
    write_arrival_output(dir, lattice, arrival, 10e-6);
    message =
        dir + "/arrival.vtp: point array 'arrival_time_0.35' is nan at particle " + std::to_string(first_cracked);
  }
  SECTION("a strain energy density in a snapshot") {
    write_arrival_output(dir, lattice, cracked_row, 10e-6);
    std::vector<double> energy(lattice.x.size(), 1.0);
    energy[7] = std::numeric_limits<double>::infinity();
    fs::create_directories(dir + "/snapshots");
    pd::write_vtp(dir + "/snapshots/step_00000100.vtp", lattice.x, lattice.y,
                  {{pd::results::damage, 1, std::vector<double>(lattice.x.size(), 0.0)},
                   {pd::results::strain_energy_density, 1, energy}},
                  {{pd::results::field_time, {2e-6}}});
    pd::write_pvd(dir + "/snapshots.pvd", {{2e-6, "snapshots/step_00000100.vtp"}});
    arguments = "--times 2e-6";
    message = dir + "/snapshots/step_00000100.vtp: point array 'strain_energy_density' is inf at particle 7";
  }
  SECTION("a snapshot's time") {
    write_arrival_output(dir, lattice, cracked_row, 10e-6);
    fs::create_directories(dir + "/snapshots");
    pd::write_vtp(dir + "/snapshots/step_00000100.vtp", lattice.x, lattice.y,
                  {{pd::results::damage, 1, std::vector<double>(lattice.x.size(), 0.0)}},
                  {{pd::results::field_time, {nan}}});
    pd::write_pvd(dir + "/snapshots.pvd", {{2e-6, "snapshots/step_00000100.vtp"}});
    arguments = "--times 2e-6";
    message = dir + "/snapshots/step_00000100.vtp: field 'time' is nan";
  }
  CHECK(refused_run(dir, arguments).err ==
        "pd-post: error: " + message + ": not a finite number (pd-solve writes none)\n");
}

TEST_CASE("a speed window longer than the run is warned about", "[bad-input]") {
  const auto dir = fresh_dir("window_longer_than_run");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  PostOptions o = options_for(dir);
  o.window_time = 1.0;  // s, against a 10 us run
  const auto r = analyse(o);
  bool warned = false;
  for (const auto& w : r.warnings) warned |= w.find("longer than the run") != std::string::npos;
  CHECK(warned);
  // --window-time 1 meant as 1 us: the warning names the unit, as --times'
  // does (before 7 December 2026 it did not).
  const auto longer = std::find_if(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
    return w.find("longer than the run") != std::string::npos;
  });
  REQUIRE(longer != r.warnings.end());
  CHECK_THAT(*longer, Contains("the speed window (1e+06 us) is longer than the run (10 us): no tip path spans one") &&
                          Contains("; --window-time is in s, or give the unit (--window-time 2us)"));
  // A window in steps (--window) has no unit to name.
  PostOptions in_steps = options_for(dir);
  in_steps.window_steps = 100000;
  bool warned_in_steps = false;
  for (const auto& w : analyse(in_steps).warnings)
    if (w.find("longer than the run") != std::string::npos) {
      warned_in_steps = true;
      CHECK(w.find("--window-time") == std::string::npos);
    }
  CHECK(warned_in_steps);
}

// Reference: a pore's cells are removed, so no particle centre lies in it
// (make_lattice leaves out the centres inside a hole). Before 5 December
// 2026 a circle in solid material was taken as a pore (made-up visits, speed
// windows dropped), a 4th column was read past without a word and the same
// pore twice counted its visits twice.
TEST_CASE("a pore file's circle in solid material or with a 4th column is refused, a repeated one warned about",
          "[bad-input][pores]") {
  // A hole of radius 0.5 mm at (2, 1) mm.
  PostOptions o = with_pore_file("pores_in_solid", {{2e-3, 1e-3, 0.5e-3}});
  // The real hole, and a circle 20 % too large around it: accepted (0.8 r = 0.48 mm < 0.5 mm).
  for (const char* r : {"0.0005", "0.0006"}) {
    std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.001," << r << "\n";
    INFO(r);
    CHECK(analyse(o).pores.size() == 1);
  }
  // A circle of 0.5 mm at (1, 1) mm, in solid material: the centres within
  // 0.4 mm of it, at odd multiples of 0.05 mm along x and y, (a, b) with
  // a^2 + b^2 < 64 for a, b in {1, 3, 5, 7}: 13 per quadrant, 52.
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.001,0.001,0.0005\n";
  CHECK_THROWS_WITH(analyse(o), Contains(o.pores_file + ": line 2: the circle at (0.001, 0.001) m of radius 0.0005 m "
                                         "holds 52 particle centres within 0.8 r of its centre: a pore of the plate "
                                         "holds none") &&
                                    Contains("the file is in metres"));
  // A 4th column (here a diameter after the radius).
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.001,0.0005,0.001\n";
  CHECK_THROWS_WITH(analyse(o), Contains(o.pores_file + ": line 2: more than 3 values ('0.001' after them): "
                                         "expected x_m,y_m,r_m"));
  // A comment after a row's values, an indented comment and a blank line are
  // no rows (before 5 December 2026 the first was "more than 3 values ('#'
  // after them)", the second "expected x_m,y_m,r_m").
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.001,0.0005  # the hole\n   # nothing more\n \t\n";
  CHECK(analyse(o).pores.size() == 1);
  // The same pore twice, its centres 0.05 mm apart (within the spacing of 0.1 mm).
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.001,0.0005\n0.00205,0.001,0.0005\n";
  const auto r = analyse(o);
  CHECK(r.pores.size() == 2);
  REQUIRE_FALSE(r.warnings.empty());
  CHECK_THAT(r.warnings.back(), Contains(o.pores_file + ": lines 2 and 3 give the same pore (centres 0.05 mm apart"));
}

// Before 5 December 2026: "ARRIVAL: no cracked particle inside branch box 0",
// without the box, the plate or the unit.
TEST_CASE("a branch box without a cracked particle is named with its bounds and the plate's extent",
          "[bad-input][branching]") {
  const auto dir = fresh_dir("boxes_without_crack");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  write_solver_summary(dir, "stress");
  PostOptions o = options_for(dir);
  o.boxes_file = dir + "/boxes.csv";
  // Millimetres for metres: the box lies off the plate.
  std::ofstream(o.boxes_file) << "x_min_m,x_max_m,y_min_m,y_max_m\n1,3,0.9,1.2\n";
  // The plate's particles span 0.05 to 3.95 mm in x, widened by half a cell:
  // the plate's edges (before 5 December 2026 by a whole cell, "x -5e-05 to 0.00405 m").
  const std::string plate = "the plate spans x 0 to 0.004 m, y 0 to 0.002 m";
  CHECK_THROWS_WITH(analyse(o), Contains(o.boxes_file + ": line 2: no cracked particle inside branch box 0 (x 1000 "
                                         "to 3000 mm, y 900 to 1200 mm) in " + dir + "/arrival.vtp; " + plate +
                                         ": the box lies off it, and the file is in metres"));
  // On the plate, beside the crack (the row at y = 1.05 mm): no hint about the unit.
  std::ofstream(o.boxes_file) << "x_min_m,x_max_m,y_min_m,y_max_m\n0.001,0.003,0.0012,0.0019\n";
  CHECK_THROWS_WITH(analyse(o), Contains("line 2: no cracked particle inside branch box 0 (x 1 to 3 mm, y 1.2 to "
                                         "1.9 mm)") &&
                                    Contains(plate) && !Contains("metres"));
  // A 5th column is refused as the pore file's 4th is.
  std::ofstream(o.boxes_file) << "x_min_m,x_max_m,y_min_m,y_max_m\n0.001,0.003,0.0009,0.0012,7\n";
  CHECK_THROWS_WITH(analyse(o), Contains("line 2: more than 4 values ('7' after them)"));
}

// Reference: the solver's summary.json, "effects": {"damage": false}, as
// pd-solve writes it for a scene with effects.damage = false. Before
// 5 December 2026: "empty crack", as if the load had been too small.
TEST_CASE("a run with damage off is said to have no crack because of it", "[bad-input]") {
  const auto dir = fresh_dir("damage_off");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), [](double, double) { return -1.0; }, 10e-6);
  const std::string summary = dir + "/summary.json";
  std::string text = file_text(summary);
  text.replace(text.find("\"damage\": true"), 14, "\"damage\": false");
  std::ofstream(summary) << text;
  const ToolRun r = run_pd_post(dir);
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: " + summary + ": \"effects\": {\"damage\": false}: the run had damage off (the "
                 "scene's effects.damage = false), so no bond broke and there is no crack to track\n");
}

// Reference: how pd-post tells a finished run (its summary.json) for its own
// input, and the comparison's counts. Before 5 December 2026 none of these
// was said: the counts came out as if the reference were a finished run of
// the same length with a crack.
TEST_CASE("pd-post --reference warns about a reference that is unfinished, undamaged or of another length",
          "[bad-input][comparison]") {
  const auto dir = fresh_dir("reference_warnings_run"), reference = fresh_dir("reference_warnings_reference");
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  write_arrival_output(dir, lattice, cracked_row, 10e-6);
  PostOptions o = options_for(dir);
  o.reference_dir = reference;
  const auto reference_warnings = [&] {
    std::vector<std::string> found;
    for (const auto& w : analyse(o).warnings)
      if (w.rfind("--reference: ", 0) == 0) found.push_back(w);
    return found;
  };
  // A finished reference of the same length with a crack: nothing to say.
  write_arrival_output(reference, lattice, cracked_row, 10.5e-6);
  CHECK(reference_warnings().empty());
  SECTION("unfinished") {
    SyntheticRun run;
    run.summary = false;
    fs::remove(reference + "/summary.json");
    write_arrival_output(reference, lattice, cracked_row, 10e-6, run);
    const auto w = reference_warnings();
    REQUIRE(w.size() == 1);
    CHECK_THAT(w[0], StartsWith("--reference: incomplete run: " + reference + "/summary.json does not exist") &&
                         Contains("arrival.vtp is from t = 10 us, step 500") &&
                         Contains("so its damage is compared as it was then"));
    // Printed and in pd-post's summary.json, as every warning.
    const ToolRun printed = run_pd_post(dir, "--reference '" + reference + "'");
    CHECK(printed.status == 0);
    CHECK_THAT(printed.err, Contains("pd-post: warning: --reference: incomplete run: " + reference));
    CHECK_THAT(file_text(dir + "/post/summary.json"), Contains("\"--reference: incomplete run: " + reference));
  }
  SECTION("without a damaged particle") {
    write_arrival_output(reference, lattice, [](double, double) { return -1.0; }, 10e-6);
    const auto w = reference_warnings();
    REQUIRE(w.size() == 1);
    CHECK(w[0] == "--reference: no particle of " + reference + "/arrival.vtp has damage 0.2 or more (its largest is "
                  "0): every damaged particle of this run counts as outside the band");
  }
  SECTION("ending more than 10 % later") {
    write_arrival_output(reference, lattice, cracked_row, 11.5e-6);
    const auto w = reference_warnings();
    REQUIRE(w.size() == 1);
    CHECK(w[0] == "--reference: " + reference + "/arrival.vtp ends at t = 11.5 us, this run at 10 us (more than "
                  "10 % apart): the two cracks are compared at different times");
  }
}

// Reference: the message of a run's -o that names a file (pd-solve's, "-o
// PATH: a file, not a folder"). Before 5 December 2026 the -o of a run's
// post directory said "cannot create the post directory: Not a directory".
TEST_CASE("pd-post -o that names a file, or a path through one, is refused naming -o", "[bad-input]") {
  const auto dir = fresh_dir("output_is_a_file");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const std::string file = dir + "/notes.txt";
  std::ofstream(file) << "a file";
  ToolRun r = run_pd_post(dir, "-o '" + file + "'");
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: -o " + file + ": a file, not a folder (the post directory)\n");
  r = run_pd_post(dir, "-o '" + file + "/post'");
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: -o " + file + "/post: cannot create the post directory: Not a directory\n");
  // The default, OUTDIR/post, taken by a file.
  std::ofstream(dir + "/post") << "a file";
  r = run_pd_post(dir);
  CHECK(r.status != 0);
  CHECK(r.err == "pd-post: error: " + dir + "/post: a file, not a folder (the post directory)\n");
  CHECK(file_text(file) == "a file");
}

// Reference: snapshots at 0, 2 and 4 us of a run to 10 us. Far beyond the
// run every |t_i - t| rounds to the same number: before 7 December 2026
// --times 1e300 drew the first snapshot, at 0 us.
TEST_CASE("a map time far beyond the run draws the last snapshot and is warned about with the run's end",
          "[bad-input]") {
  const auto dir = fresh_dir("times_far_beyond");
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  write_arrival_output(dir, lattice, cracked_row, 10e-6);
  std::vector<std::pair<double, std::string>> entries;
  for (const int step : {0, 100, 200}) {
    const std::string name = "step_00000" + std::to_string(100 + step) + ".vtp";
    write_plain_snapshot(dir, lattice, name, step * test_time_step);
    entries.emplace_back(step * test_time_step, "snapshots/" + name);
  }
  pd::write_pvd(dir + "/snapshots.pvd", entries);
  PostOptions o = options_for(dir);
  o.map_times = {1e300};
  PostResult r = run_post(o);
  REQUIRE(r.maps.size() == 1);
  CHECK(r.maps[0].used == 4e-6);
  CHECK(fs::exists(dir + "/post/damage_t4us.png"));
  CHECK_FALSE(fs::exists(dir + "/post/damage_t0us.png"));
  CHECK(std::count(r.warnings.begin(), r.warnings.end(),
                   "--times 1e+306 us is after the run's end at 10 us: times are in s, or give the unit (--times "
                   "5us)") == 1);
  // Nearest as before, between two snapshots and before the first.
  for (const auto& [asked, drawn] : {std::pair{2.9e-6, 2e-6}, {3.1e-6, 4e-6}, {1e-300, 0.0}}) {
    o.map_times = {asked};
    r = run_post(o);
    INFO(asked);
    REQUIRE(r.maps.size() == 1);
    CHECK(r.maps[0].used == drawn);
  }
}

// Before 7 December 2026 each time given twice was drawn twice, its note
// printed twice and listed twice in summary.json's "maps".
TEST_CASE("a map time given twice is drawn once, with one note", "[bad-input]") {
  const auto dir = run_with_one_snapshot("times_twice");
  const ToolRun r = run_pd_post(dir, "--times 1us,1us,1e-6,1000ns");
  INFO(r.err);
  CHECK(r.status == 0);
  const std::string note = "pd-post: note: maps for 1 us show the nearest snapshot, at 2 us\n";
  const auto count = [](const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
  };
  CHECK(count(r.err, note) == 1);
  CHECK(count(file_text(dir + "/post/summary.json"), "\"requested_time_s\"") == 1);
}

// This run without a particle at --damage-level: before 7 December 2026
// "0 of 0 damaged particles (damage >= 0.8) lie farther than ...", as if the
// two cracks had been compared and agreed.
TEST_CASE("a comparison where this run has no particle at --damage-level says there is nothing to compare",
          "[bad-input][comparison]") {
  const auto dir = fresh_dir("comparison_nothing_run"), reference = fresh_dir("comparison_nothing_reference");
  const Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  SyntheticRun faint;
  faint.cracked_damage = 0.5;
  write_arrival_output(dir, lattice, cracked_row, 10e-6, faint);
  write_arrival_output(reference, lattice, cracked_row, 10e-6);
  PostOptions o = options_for(dir);
  o.reference_dir = reference;
  o.damage_level = 0.8;
  const PostResult result = analyse(o);
  REQUIRE(result.comparison);
  CHECK(result.comparison->damaged == 0);
  CHECK(std::count(result.warnings.begin(), result.warnings.end(),
                   "--reference: no particle of this run (" + dir + "/arrival.vtp) has damage 0.8 or more (its "
                   "largest is 0.5): there is nothing to compare; a lower --damage-level counts its fainter "
                   "damage") == 1);
  const ToolRun r = run_pd_post(dir, "--reference '" + reference + "' --damage-level 0.8");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.out, Contains("against " + reference + "/arrival.vtp: nothing to compare, no particle of this run has "
                             "damage >= 0.8 (its largest is 0.5)\n") && !Contains("0 of 0"));
  // At a level it reaches, the count as before.
  o.damage_level = 0.4;
  const PostResult reached = analyse(o);
  CHECK(reached.comparison->damaged > 0);
  for (const auto& w : reached.warnings) CHECK_THAT(w, !Contains("nothing to compare"));
}

// Lengths far beyond the plate (4 x 2 mm): before 7 December 2026 a --line
// end at 1e300 m made a sample count a double far beyond any int, cast to
// one (undefined; the line was said to meet no particle), --band 1e-300m
// put coordinate / band through an integer cast, and --band 1e300m counted
// nothing outside, exit 0.
TEST_CASE("a line, offset or band many plate sizes long is refused before any count is made of it", "[bad-input]") {
  const auto dir = fresh_dir("lengths_far_beyond");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const auto reference = fresh_dir("lengths_far_beyond_reference");
  write_arrival_output(reference, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  struct Case {
    std::string arguments, message;
  };
  for (const Case& c : std::vector<Case>{
           {"--line 1mm,1mm,1e300m,1mm",
            "pd-post: error: --line: the line from (1, 1) mm to (1e+303, 1) mm reaches 2.56e+302 times the plate's "
            "size (3.9 mm) beyond its particles (x 0.05 to 3.95 mm, y 0.05 to 1.95 mm), more than the 100 a line "
            "may: give a line across the plate, lengths with their unit (e.g. --line 10mm,12.5mm,40mm,12.5mm)\n"},
           {"--line 1mm,1mm,3mm,1mm --line-offset 1e300m",
            "pd-post: error: --line-offset 1e+303 mm is 2.56e+302 times the plate's size (3.9 mm), more than the 100 "
            "it may be: the one-sided fits 1e+303 to 2e+303 mm from the line would find no particle; give it with "
            "its unit (e.g. --line-offset 1mm)\n"},
           {"--band 1e-300m --reference '" + reference + "'",
            "pd-post: error: --band 1e-297 mm is less than a thousandth of the spacing (0.1 mm): only damage at the "
            "very same place lies within it; give the band with its unit (e.g. --band 1mm)\n"},
           {"--band 1e300m --reference '" + reference + "'",
            "pd-post: error: --band 1e+303 mm is more than 100 times the plate's size (3.9 mm): the whole plate "
            "lies within it, and no damage outside; give the band with its unit (e.g. --band 1mm)\n"}}) {
    const ToolRun r = run_pd_post(dir, c.arguments);
    INFO(c.arguments);
    REQUIRE(WIFEXITED(r.status));
    CHECK(WEXITSTATUS(r.status) == 1);
    CHECK(r.err == c.message);
  }
  CHECK_FALSE(fs::exists(dir + "/post/summary.json"));
  // Within reach: a line partly off the plate is drawn with a warning, as before.
  const ToolRun r = run_pd_post(dir, "--line 1mm,1mm,300mm,1mm");
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Contains("pd-post: warning: --line: ") && Contains("lie off the plate"));
}

// pd-solve writes a plate's particles side by side, cell sizes above 0 and
// the arrival times its run reached. Before 7 December 2026 a point edited
// to 1e30 m ended pd-post with a message naming no file, and a cell size of
// 0 and an arrival time after the run's end passed without a word (exit 0).
TEST_CASE("an edited arrival.vtp: a point far off the plate, a cell size of 0, an arrival after the end, refused",
          "[bad-input]") {
  const auto dir = fresh_dir("edited_arrival");
  Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  std::string message, ending;
  SECTION("a point at 1e30 m") {
    lattice.x[5] = 1e30;
    write_arrival_output(dir, lattice, cracked_row, 10e-6);
    message = dir + "/arrival.vtp: points: particle 5 is at (1e+30, 5e-05) m, ";
    ending = "than the 0.00117 m within which half its particles lie: not a plate's particle (an edited or damaged "
             "file)\n";
  }
  SECTION("a cell size of 0") {
    lattice.cell_size.assign(lattice.x.size(), lattice.spacing);
    lattice.cell_size[7] = 0;
    write_arrival_output(dir, lattice, cracked_row, 10e-6);
    message = dir + "/arrival.vtp: point array 'cell_size' is 0 at particle 7: not a positive size";
    ending = "(pd-solve writes every particle's; an edited or damaged file)\n";
  }
  SECTION("an arrival time after the run's end") {
    SyntheticRun run;
    run.end_time_field = 5e-6;  // the crack's arrivals run to 8 us
    write_arrival_output(dir, lattice, cracked_row, 10e-6, run);
    // The first of the cracked row (y = 1.05 mm, row 10 of 40 particles)
    // past 5 us: x = 2.55 mm, 5.1 us.
    message = dir + "/arrival.vtp: point array 'arrival_time_0.35' is 5.1";
    ending = " at particle 425: after the run's end at 5e-06 s (field 'end_time'); pd-solve records the times a run "
             "reached (an edited file, or another run's array)\n";
  }
  const ToolRun r = refused_run(dir);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_THAT(r.err, StartsWith("pd-post: error: " + message) && Catch::Matchers::EndsWith(ending));
}

// pd-post follows each crack tip at every solver step. Before 7 December
// 2026 a time_step edited to 1e-300 s (the field 'step' left at 500) made
// the speed window's and the tip paths' step counts doubles far beyond int
// and long, cast to them.
TEST_CASE("an arrival.vtp whose time_step makes the run more steps than a tip can be followed through is refused",
          "[bad-input]") {
  const auto dir = fresh_dir("time_step_tiny");
  SyntheticRun run;
  run.time_step_field = 1e-300;
  CHECK(refused_edited_run(dir, run).err ==
        "pd-post: error: " + dir + "/arrival.vtp: field 'time_step' = 1e-300 s makes the run to its end at 1e-05 s "
        "1e+295 steps, more than the 1e+09 pd-post follows a crack tip through, one step at a time (an edited or "
        "damaged file)\n");
}

// Before 7 December 2026 a youngs_modulus of 1e-300 Pa (or a density of
// 1e300 kg/m^3) made the speed window's step count, cells over c_R times the
// step, a double far beyond an int, cast to one; pd-post went on, exit 0.
TEST_CASE("an arrival.vtp whose material gives no solid's wave speed is refused naming the fields",
          "[bad-input]") {
  const auto dir = fresh_dir("wave_speed");
  SyntheticRun run;
  // An unfinished run: no summary.json whose material would disagree.
  run.summary = false;
  std::string message;
  SECTION("a Young's modulus of 1e-300 Pa") {
    run.youngs_field = 1e-300;
    message = "fields 'youngs_modulus' = 1e-300 Pa and 'density' = 1190 kg/m^3 give, with a Poisson ratio of "
              "0.3333 (field 'poisson_ratio'), a shear wave speed of 1.78e-152 m/s";
  }
  SECTION("a density of 1e300 kg/m^3") {
    run.density_field = 1e300;
    message = "fields 'youngs_modulus' = 3.24e+09 Pa and 'density' = 1e+300 kg/m^3 give, with a Poisson ratio of "
              "0.3333 (field 'poisson_ratio'), a shear wave speed of 3.49e-146 m/s";
  }
  SECTION("a Young's modulus of 1e30 Pa, without the model's Poisson ratio") {
    run.youngs_field = 1e30;
    run.model_poisson_ratio = std::nullopt;
    message = "fields 'youngs_modulus' = 1e+30 Pa and 'density' = 1190 kg/m^3 give, with a Poisson ratio of "
              "0.3333 (the PMB model's), a shear wave speed of 1.78e+13 m/s";
  }
  CHECK(refused_edited_run(dir, run).err ==
        "pd-post: error: " + dir + "/arrival.vtp: " + message + ", outside the 1 to 100000 m/s of solids (about 1 "
        "m/s in the softest gels, 1.3e4 m/s in diamond): an edited or damaged file; pd-solve writes the scene's "
        "material\n");
}

// pd-solve writes -1 for a particle never reached. Before 7 December 2026
// any negative time (-5 s, an edited file) was read as never reached, exit 0.
TEST_CASE("an arrival time below 0 other than -1 is refused naming array and particle", "[bad-input]") {
  const auto dir = fresh_dir("negative_arrival");
  SyntheticRun run;
  run.edited_times = {{12, -5.0}};
  CHECK(refused_edited_run(dir, run).err ==
        "pd-post: error: " + dir + "/arrival.vtp: point array 'arrival_time_0.35' is -5 at particle 12: a time "
        "before the run's start; pd-solve writes -1 for a particle never reached and times from 0 otherwise (an "
        "edited or damaged file)\n");
}

// Holes are found on a raster of half the median cell size; one of more than
// 2e8 cells is not laid. Before 7 December 2026 such a plate (a few
// particles far apart for their cells) reported "pores: 0" without a word.
TEST_CASE("a plate too sparse for the pore raster is warned about: pores were not looked for",
          "[bad-input][pores]") {
  const auto dir = fresh_dir("sparse_pores");
  Lattice sparse;
  sparse.spacing = 0.1e-3;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) sparse.x.push_back(0.25 * i), sparse.y.push_back(0.25 * j);
  // A crack along the middle row, at 2e5 m/s from its left end.
  write_arrival_output(dir, sparse, [](double x, double y) { return y == 0.5 ? x / 2e5 : -1; }, 10e-6);
  const ToolRun r = run_pd_post(dir);
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.err, Contains("pd-post: warning: pores were not looked for: the plate, 1000 x 1000 mm, is 4e+08 "
                             "raster cells of 0.05 mm (half the median cell size), more than the 2e+08 pd-post lays "
                             "over it to find holes (particles far apart for their cells); give --pores FILE to "
                             "count pore visits\n"));
}

// pd-solve writes the scene's material Poisson ratio, in (0, 0.5), or -1
// for none. Before 7 December 2026 any negative value (-5, an edited file)
// was read as none: no Rayleigh speed of the material, without a word.
TEST_CASE("a material Poisson ratio below 0 other than -1 is refused by name", "[bad-input]") {
  const auto dir = fresh_dir("material_poisson");
  SyntheticRun run;
  run.material_poisson_field = -5;
  CHECK(refused_edited_run(dir, run).err ==
        "pd-post: error: " + dir + "/arrival.vtp: field 'material_poisson_ratio' = -5 is not a Poisson ratio "
        "pd-solve writes, in (0, 0.5) (an edited or damaged file)\n");
}

// pd-solve writes the model's Poisson ratio, 1/3 or 1/4 (PMB) or the
// material's (OSB), and the material's as the scene gives it: both in
// (0, 0.5), which its scene reader requires. Before 7 December 2026 a value
// in (-1, 0] (an edited file), an isotropic solid's but no run's, was taken:
// c_R computed with it, exit 0.
TEST_CASE("a Poisson ratio from -1 to 0, which pd-solve never writes, is refused by name", "[bad-input]") {
  const auto dir = fresh_dir("poisson_not_written");
  SyntheticRun run;
  std::string message;
  SECTION("the model's poisson_ratio -0.5") {
    run.model_poisson_ratio = -0.5;
    message = "field 'poisson_ratio' = -0.5";
  }
  SECTION("the model's poisson_ratio 0") {
    run.model_poisson_ratio = 0.0;
    message = "field 'poisson_ratio' = 0";
  }
  SECTION("material_poisson_ratio -0.5") {
    run.material_poisson_field = -0.5;
    message = "field 'material_poisson_ratio' = -0.5";
  }
  CHECK(refused_edited_run(dir, run).err == "pd-post: error: " + dir + "/arrival.vtp: " + message +
                                                " is not a Poisson ratio pd-solve writes, in (0, 0.5) (an edited or "
                                                "damaged file)\n");
}

// A run that ends at its start (field end_time 0, a crack of pre-cut
// particles reached at t = 0) passes the bound on the steps to its end with
// any time_step. Before 7 December 2026 one of 1e-300 s (an edited file)
// reached the speed window's rule and was refused in a message that named
// no file.
TEST_CASE("a time_step that makes the speed window's rule no int is refused naming the file", "[bad-input]") {
  const auto dir = fresh_dir("time_step_window");
  SyntheticRun run;
  run.time_step_field = 1e-300;
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3),
                       [](double, double y) { return std::abs(y - 1.05e-3) < 1e-5 ? 0.0 : -1.0; }, 0.0, run);
  CHECK_THAT(refused_run(dir).err, StartsWith("pd-post: error: " + dir + "/arrival.vtp: field 'time_step' = 1e-300 s makes the "
                               "speed window's rule, the time a tip at c_R = ") &&
                        Contains(" m/s takes to cross 15 cells of 0.1 mm, ") &&
                        Catch::Matchers::EndsWith(" steps, more than an int counts (an edited or damaged file)\n"));
}

// pd-solve writes the particle file's spacing (1e-9 to 1e3 m, the cells
// following it), a horizon of 1/64 to 64 spacings and plane_strain 1 or 0,
// as numbers. Before 7 December 2026 arrival.vtp's spacing of 1e-300 m made
// the speed window 1 step, one of 0.5 m and a horizon of 1e300 m were taken
// as they were, a horizon written as a text was read as none (3 spacings,
// with a note that the field was missing), and a plane_strain of 0.5 or NaN
// was read as plane strain: exit 0 each (an unfinished run: no summary.json
// says the plane).
TEST_CASE("an arrival.vtp whose spacing, horizon or plane_strain no run writes is refused naming the field",
          "[bad-input]") {
  const auto dir = fresh_dir("edited_length_fields");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SyntheticRun run;
  run.summary = false;
  std::string message;
  SECTION("a spacing of 1e-300 m") {
    run.edited_fields = {{pd::results::field_spacing, {1e-300}}};
    message = "field 'spacing' = 1e-300 m is no particle file's spacing (1e-09 to 1000 m): an edited or damaged file";
  }
  SECTION("a spacing of 0.5 m beside cells of 0.1 mm") {
    run.edited_fields = {{pd::results::field_spacing, {0.5}}};
    message = "field 'spacing' = 0.5 m is more than 1000 times larger than the particles' median cell size, 0.0001 m "
              "(point array 'cell_size'): pd-solve writes the particle file's spacing, which its cells follow (an "
              "edited or damaged file)";
  }
  SECTION("a horizon of 1e300 m") {
    run.edited_fields = {{pd::results::field_horizon, {1e300}}};
    message = "field 'horizon' = 1e+300 m is 1e+304 times the spacing (field 'spacing'), 0.0001 m: a run's horizon "
              "is 1/64 to 64 times it (an edited or damaged file)";
  }
  SECTION("a horizon written as a text") {
    run.edited_fields = {{pd::results::field_horizon, {}, "0.3mm"}};
    message = "field 'horizon' is 0.3mm, a text: pd-solve writes a number there (an edited or damaged file)";
  }
  SECTION("a plane_strain of 0.5") {
    run.edited_fields = {{pd::results::field_plane_strain, {0.5}}};
    message = "field 'plane_strain' = 0.5 is neither 1 (plane strain) nor 0 (plane stress), the values pd-solve "
              "writes (an edited or damaged file)";
  }
  SECTION("a plane_strain of NaN") {
    run.edited_fields = {{pd::results::field_plane_strain, {nan}}};
    message = "field 'plane_strain' is nan: not a finite number (pd-solve writes none)";
  }
  CHECK(refused_edited_run(dir, run).err == "pd-post: error: " + dir + "/arrival.vtp: " + message + "\n");
}

// Before 7 December 2026 final_state.vtp's load factor of NaN passed the
// comparison with load_steps.csv's last row and titled every map "load
// factor nan", and a spacing of 0 or a horizon of NaN was said to be
// missing, a fallback taken (exit 0).
TEST_CASE("a quasi-static final_state.vtp whose load factor, spacing or horizon no run writes is refused by name",
          "[bad-input][quasi-static]") {
  const auto dir = fresh_dir("edited_final_state_fields");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  QuasiStaticRun run = stretched_plate(true);
  std::string message;
  SECTION("a load factor of NaN") {
    run.edited_state_fields = {{pd::results::field_load_factor, {nan}}};
    message = "field 'load_factor' is nan: not a finite number (pd-solve writes none)";
  }
  SECTION("a spacing of 0") {
    run.edited_state_fields = {{pd::results::field_spacing, {0.0}}};
    message = "field 'spacing' = 0 m is no particle file's spacing (1e-09 to 1000 m): an edited or damaged file";
  }
  SECTION("a horizon of NaN") {
    run.edited_state_fields = {{pd::results::field_horizon, {nan}}};
    message = "field 'horizon' is nan: not a finite number (pd-solve writes none)";
  }
  write_quasi_static_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), run);
  CHECK(refused_run(dir).err ==
        "pd-post: error: " + dir + "/" + pd::results::final_state_file + ": " + message + "\n");
}

// A circle smaller than a cell holds no particle centre wherever it lies.
// Before 7 December 2026 one of 1e-300 m (or 1 um: a radius in another unit)
// on the crack's path passed the check of centres within 0.8 r, and the
// crack was said to visit it, with a trapping time (exit 0).
TEST_CASE("a pore file's circle smaller than a cell, centred in solid material, is refused", "[bad-input][pores]") {
  PostOptions o = with_pore_file("pores_tiny_in_solid");
  // On the cracked row (y = 1.05 mm), 0.03 and 0.02 mm off particle (2.05,
  // 1.05) mm, the 420th (row 10 of 40 particles, column 20): in its cell,
  // no centre within 0.8 r.
  for (const char* r : {"1e-300", "1e-6"}) {
    std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.00208,0.00107," << r << "\n";
    INFO(r);
    CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 2: the circle at (0.00208, 0.00107) m of radius " +
                                      (std::string(r) == "1e-6" ? "1e-06" : r) +
                                      " m has its centre in the cell of particle 420, at (0.00205, 0.00105) m, 0.1 mm "
                                      "across: a pore's centre lies in no cell (its cells are removed); the file is "
                                      "in metres (x_m,y_m,r_m)");
  }
}

// A circle centred on the corner of four cells lies in none of them, and a
// small one holds no centre: before 7 December 2026 one of 1e-6 m there, on
// the crack's path, passed, and the crack was said to visit it (exit 0).
TEST_CASE("a pore file's circle far smaller than the cells about it, centred between them, is refused",
          "[bad-input][pores]") {
  PostOptions o = with_pore_file("pores_tiny_on_corner");
  // (2.0, 1.1) mm: the corner of the cells of particles (1.95, 1.05) and
  // (2.05, 1.05) mm on the cracked row and the two above them; the first
  // of them found is particle 419 (row 10 of 40 particles, column 19).
  for (const char* r : {"1e-6", "2.4e-5"}) {
    std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.0011," << r << "\n";
    INFO(r);
    CHECK_THROWS_WITH(analyse(o), o.pores_file + ": line 2: the circle at (0.002, 0.0011) m of radius " +
                                      (std::string(r) == "1e-6" ? "1e-06 m is 0.01" : "2.4e-05 m is 0.24") +
                                      " times the cells about it (0.1 mm across, particle 419's, the nearest): a pore "
                                      "below 0.25 of a cell takes too little of one for the particles to show it; give "
                                      "the pore's radius in metres (x_m,y_m,r_m), or leave it out");
  }
  // A quarter of a cell is taken (the rule's bound, not a pore the layout shows).
  std::ofstream(o.pores_file) << "x_m,y_m,r_m\n0.002,0.0011,2.5e-5\n";
  CHECK_NOTHROW(analyse(o));
}

// An unfinished quasi-static run (no final_state.vtp) is drawn from its last
// snapshot. Before 7 December 2026 that snapshot's load factor went
// unchecked against snapshots.pvd: one moved over it from an earlier step
// was drawn as the last state, at its own load factor, with only the
// warning that the last snapshot stands in (exit 0).
TEST_CASE("a quasi-static run's last snapshot, drawn for want of final_state.vtp, of another load factor is refused",
          "[bad-input][quasi-static]") {
  const auto dir = fresh_dir("last_snapshot_moved");
  QuasiStaticRun run = stretched_plate(false);
  run.snapshot_factors = {0.5, 1.0};
  write_quasi_static_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), run);
  fs::copy_file(dir + "/snapshots/step_00000001.vtp", dir + "/snapshots/step_00000002.vtp",
                fs::copy_options::overwrite_existing);
  CHECK(refused_run(dir).err == "pd-post: error: " + dir + "/snapshots/step_00000002.vtp: is of load factor 0.5 "
                                "(field 'load_factor'), and " + dir + "/snapshots.pvd lists it at load factor 1: the "
                                "two files are from different runs (a folder mixed by copying or moving files); give "
                                "the folder that one pd-solve run wrote whole, or run pd-solve again\n");
}

// pd-solve's cells follow the particle file's spacing (refined squares down
// to 1/64 of it). Before 7 December 2026 a cell_size edited to 1e30 m made
// the plate's extent that cell: the damage map drew one cell 2e33 mm wide,
// and the pore raster was said to be too large, exit 0.
TEST_CASE("a cell size far larger than the plate's other cells is refused naming the array and the particle",
          "[bad-input]") {
  const auto dir = fresh_dir("cell_far_larger");
  Lattice lattice = make_lattice(4e-3, 2e-3, 0.1e-3);
  lattice.cell_size.assign(lattice.x.size(), lattice.spacing);
  std::string message;
  SECTION("1e30 m") {
    lattice.cell_size[7] = 1e30;
    message = "point array 'cell_size' is 1e+30 at particle 7, 1e+34 times";
  }
  SECTION("0.5 m, a plate of 4 mm") {
    lattice.cell_size[7] = 0.5;
    message = "point array 'cell_size' is 0.5 at particle 7, 5e+03 times";
  }
  write_arrival_output(dir, lattice, cracked_row, 10e-6);
  CHECK(refused_run(dir).err == "pd-post: error: " + dir + "/arrival.vtp: " + message + " the particles' median cell "
                                "size, 0.0001 m: pd-solve's cells follow the particle file's spacing, none more than "
                                "1000 times the median (an edited or damaged file)\n");
}

// A pore given twice is warned about (its visits counted twice); before 7
// December 2026 a box given twice, or two boxes around the same cracked
// particles, made one crack two branches without a word, its speeds counted
// twice.
TEST_CASE("two branch boxes around the same cracked particles are warned about: one crack counted twice",
          "[bad-input][branching]") {
  PostOptions o = options_for(fresh_dir("boxes_same_crack"));
  write_arrival_output(o.outdir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  o.boxes_file = o.outdir + "/boxes.csv";
  const auto warnings_about_boxes = [&](const std::string& rows) {
    std::ofstream(o.boxes_file, std::ios::trunc) << "x_min_m,x_max_m,y_min_m,y_max_m\n" << rows;
    const PostResult r = analyse(o);
    std::vector<std::string> found;
    for (const auto& w : r.warnings)
      if (w.rfind(o.boxes_file, 0) == 0) found.push_back(w);
    return found;
  };
  // The cracked row (y = 1.05 mm) from x = 1 to 3 mm: particles at x = 1.05 ... 2.95 mm, 20 of them.
  const std::vector<std::string> twice{o.boxes_file + ": lines 2 and 3 hold the same 20 cracked particles: branches "
                                       "0 and 1 are one crack, its speeds counted twice"};
  CHECK(warnings_about_boxes("0.001,0.003,0.0008,0.0012\n0.001,0.003,0.0008,0.0012\n") == twice);
  // Another box around the same particles (taller): the same crack.
  CHECK(warnings_about_boxes("0.001,0.003,0.0008,0.0012\n0.001,0.003,0.0002,0.0019\n") == twice);
  // Boxes that share some particles (overlapping halves) are two branches, as meant.
  CHECK(warnings_about_boxes("0.001,0.0025,0.0008,0.0012\n0.0015,0.003,0.0008,0.0012\n").empty());
}

// summary.json names the run's folder: JSON readers take UTF-8 text with its
// control characters escaped. Before 7 December 2026 a tab in the folder's
// name was dropped (another path) and a byte of another encoding (é in
// Latin-1, 0xE9) written as it was, which Python's json refuses to read.
TEST_CASE("a run folder named with a tab or a byte of another encoding is written to summary.json as JSON text",
          "[bad-input]") {
  const auto dir = fresh_dir("json_path_a\tb\xe9" "c");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const ToolRun r = run_pd_post(dir);
  INFO(r.err);
  REQUIRE(r.status == 0);
  const std::string summary = file_text(dir + "/post/summary.json");
  const std::string folder = dir.substr(0, dir.size() - 5) + "a\\tb\\ufffdc";
  CHECK_THAT(summary, Contains("  \"input\": \"" + folder + "/arrival.vtp\",\n"));
  // Only line ends below 0x20, and no byte that begins no UTF-8 sequence (0xE9 before 'c').
  CHECK(std::none_of(summary.begin(), summary.end(),
                     [](char c) { return static_cast<unsigned char>(c) < 0x20 && c != '\n'; }));
  CHECK(summary.find('\xe9') == std::string::npos);
}

// Before 7 December 2026 these were Boost's "the argument ('1e10') for option
// '--window' is invalid": neither what the option takes nor what to do.
TEST_CASE("a number option's value that is no number of its kind names what the option takes", "[bad-input]") {
  const auto dir = fresh_dir("number_options");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const std::string window = "e.g. --window 30, or the window as a time, e.g. --window-time 2us\n";
  struct Case {
    std::string arguments, message;
  };
  for (const Case& c : std::vector<Case>{
           {"--window 1e10", "--window 1e10: not a whole number of solver steps from 1 to 2147483647: " + window},
           {"--window 2.5", "--window 2.5: not a whole number of solver steps from 1 to 2147483647: " + window},
           // In the words of every tool's number options (before 7 December
           // 2026's later change "--window: 'abc' is not a number: give ...").
           {"--window abc", "--window abc: give a whole number of solver steps, " + window},
           {"--threshold 0.35x", "--threshold 0.35x: give one of the run's damage thresholds (its "
                                 "output.damage_thresholds), e.g. --threshold 0.35\n"},
           {"--threshold nan", "--threshold nan: give one of the run's damage thresholds (its "
                               "output.damage_thresholds), e.g. --threshold 0.35\n"},
           {"--damage-level abc --reference '" + dir + "'",
            "--damage-level abc: give a damage in (0, 1], e.g. --damage-level 0.2\n"}}) {
    INFO(c.arguments);
    CHECK(refused_run(dir, c.arguments).err == "pd-post: error: " + c.message);
  }
  // A whole number in any form is a window (1e3: 1000 steps).
  const ToolRun r = run_pd_post(dir, "--window 1e3");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.out, Contains("window 1000 steps"));
}

// A run folder whose name begins with '-' reads as an option: before 7
// December 2026 "-run: no such option" alone.
TEST_CASE("pd-post tells a run folder named with a leading dash to be written with ./", "[bad-input]") {
  const auto parent = fresh_dir("dash_named");
  fs::create_directories(parent + "/-run");
  write_arrival_output(parent + "/-run", make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const std::string err = parent + "/stderr_dash.txt";
  CHECK(pd::test_support::run_shell("cd '" + parent + "' && '" + PD_POST_EXECUTABLE + "' -run 2> '" + err +
                                    "' > /dev/null") == 1);
  CHECK(file_text(err) == "pd-post: error: -run: no such option (pd-post --help lists them); for the folder -run "
                          "write ./-run (a name that begins with '-' reads as an option)\n");
  CHECK_FALSE(fs::exists(parent + "/-run/post"));
}

// A name with a space at its end: before 7 December 2026 `-o "post "` wrote
// into a folder "post " without a word.
TEST_CASE("pd-post refuses an output or input name that ends in a space and names nothing", "[bad-input]") {
  const auto dir = fresh_dir("spaced_names");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  CHECK(refused_run(dir, "-o '" + dir + "/post '").err ==
        "pd-post: error: -o '" + dir + "/post ': the name ends in a space, and no file or folder has that name: give "
        "it without, -o " + dir + "/post\n");
  CHECK_FALSE(fs::exists(dir + "/post "));
  CHECK(refused_run(dir, "--pores 'pores.csv '").err ==
        "pd-post: error: --pores 'pores.csv ': the name ends in a space, and no file or folder has that name: give it "
        "without, --pores pores.csv\n");
}

// Such a name that exists is the user's and is taken, with a warning that
// names it quoted (before 7 December 2026 without a word: the space unseen,
// its pictures were looked for in "post").
TEST_CASE("pd-post warns of an existing output folder whose name ends in a space, and writes into it", "[bad-input]") {
  const auto dir = fresh_dir("spaced_existing");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  fs::create_directories(dir + "/post ");
  const ToolRun r = run_pd_post(dir, "-o '" + dir + "/post '");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK_THAT(r.err, StartsWith("pd-post: warning: -o '" + dir + "/post ': the name ends in a space; the folder of "
                               "that name exists and is used (" + dir + "/post, without it, is another name)\n"));
  CHECK(fs::exists(dir + "/post /summary.json"));
  CHECK_FALSE(fs::exists(dir + "/post"));
}

// summary.json's strings as pd-solve writes them (json_string: control
// characters as \u00XX, a byte that begins no UTF-8 character as \ufffd),
// and the escapes any JSON writer may use (upper-case digits, a surrogate
// pair for a character beyond U+FFFF): before 7 December 2026 every \u
// escape read as '?'.
TEST_CASE("summary.json's unicode escapes read back as the UTF-8 text pd-solve wrote", "[summary]") {
  const auto dir = fresh_dir("unicode_escapes");
  const std::string written = std::string("stop \x01 \x1f \x7f caf\xC3\xA9 \xff \xE2\x82\xAC end");
  const auto read_back = [&](const std::string& json_text_of_reason) {
    std::ofstream(dir + "/summary.json") << "{\"tool\": \"pd-solve 0.1.0\", \"stop_reason\": " << json_text_of_reason
                                         << "}";
    return read_solver_summary(dir).stop_reason;
  };
  CHECK(pd::json_string(written) == "\"stop \\u0001 \\u001f \\u007f caf\xC3\xA9 \\ufffd \xE2\x82\xAC end\"");
  CHECK(read_back(pd::json_string(written)) ==
        "stop \x01 \x1f \x7f caf\xC3\xA9 \xEF\xBF\xBD \xE2\x82\xAC end");
  CHECK(read_back("\"\\u00E9\\u20ac \\ud83d\\ude00 \\u0041\"") == "\xC3\xA9\xE2\x82\xAC \xF0\x9F\x98\x80 A");
  // A surrogate without its pair is no character: U+FFFD, as json_string
  // writes a byte that begins none; the escape after it is read on its own.
  CHECK(read_back("\"\\ud800x \\udc00 \\ud83d\\u0041\"") == "\xEF\xBF\xBDx \xEF\xBF\xBD \xEF\xBF\xBD" "A");
  CHECK_THROWS_WITH(read_back("\"\\u00g1\""), Contains("summary.json: not valid JSON at byte") &&
                                                 Contains("bad \\u escape"));
}

// A folder of the path with a space at its end (`-o "DIR/new /post"`):
// before 7 December 2026 only the ends of the whole name were looked at,
// and pd-post wrote into a new folder "new " without a word.
TEST_CASE("pd-post refuses an output path through a folder name that ends in a space and names nothing",
          "[bad-input]") {
  const auto dir = fresh_dir("spaced_folder");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  CHECK(refused_run(dir, "-o '" + dir + "/new /post'").err ==
        "pd-post: error: -o '" + dir + "/new /post': its part 'new ' ends in a space, and no folder or file has that "
        "name: give it without, -o " + dir + "/new/post\n");
  CHECK_FALSE(fs::exists(dir + "/new "));
}

// A short option takes the rest of its word for its value: `pd-post -out`
// with a folder "-out" was read as -o ut, and ended in "missing OUTDIR"
// (before 7 December 2026).
TEST_CASE("pd-post names a folder that begins with a short option's dash and letter", "[bad-input]") {
  const auto dir = fresh_dir("dash_folder");
  write_arrival_output(dir + "/-out", make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const std::string err = dir + "/stderr.txt";
  const auto run_in_dir = [&](const std::string& arguments) {
    return pd::test_support::run_shell("cd '" + dir + "' && '" + PD_POST_EXECUTABLE + "' " + arguments + " 2> '" +
                                       err + "' > /dev/null");
  };
  CHECK(run_in_dir("-out") == 1);
  CHECK(file_text(err) == "pd-post: error: -out: read as -o ut (a short option takes the rest of its word for its "
                          "value); for the folder -out write ./-out (a name that begins with '-' reads as an "
                          "option)\n");
  CHECK_FALSE(fs::exists(dir + "/ut"));
  // A long option's name after one dash.
  CHECK(run_in_dir("./-out -output post") == 1);
  CHECK(file_text(err) == "pd-post: error: -output: read as -o utput (a short option takes the rest of its word "
                          "for its value); a long option takes two dashes: --output\n");
  CHECK_FALSE(fs::exists(dir + "/utput"));
  // As written: the folder, and -o joined to a folder's name that is none.
  CHECK(run_in_dir("./-out -opost") == 0);
  CHECK(fs::exists(dir + "/post/summary.json"));
}

// The items of --times and --load-factors are read as every number option
// is, and a bad one is named by its place and text (before 7 December 2026
// in words of their own, "--load-factors: 'abc' is not a decimal number",
// the place unsaid, and an empty item after the last comma dropped without
// a word).
TEST_CASE("pd-post names a bad item of --times or --load-factors by its place in the number options words",
          "[bad-input]") {
  const auto dir = fresh_dir("list_items");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const std::string factors = ": give load factors, comma-separated, e.g. --load-factors 0.5,1";
  const std::string times = ": give times from 0, in s or with their unit, comma-separated, e.g. --times 1.5e-4,300us";
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {"--load-factors 0.5,abc", "--load-factors abc: item 2 of '0.5,abc' is not a finite number" + factors},
           {"--load-factors 0.5,1,inf", "--load-factors inf: item 3 of '0.5,1,inf' is not a finite number" + factors},
           {"--load-factors 0x10", "--load-factors 0x10: item 1 of '0x10' is not a finite number" + factors},
           {"--load-factors 0.5,", "--load-factors 0.5,: item 2 of '0.5,' is empty" + factors},
           {"--load-factors 0.5,,1", "--load-factors 0.5,,1: item 2 of '0.5,,1' is empty" + factors},
           {"--times 1us,2us,abc", "--times abc: item 3 of '1us,2us,abc' is not a finite number" + times},
           {"--times 1e-6,-2e-6", "--times -2e-6: item 2 of '1e-6,-2e-6' is negative" + times},
           {"--times 1us,", "--times 1us,: item 2 of '1us,' is empty" + times},
           // The unit's fault in the list's words and with its ending (before
           // 7 December 2026 parse_time's own, "...: unknown unit 'ly' in
           // '2ly' (use s, ms, us, µs, ns)", without what to give).
           {"--times 1us,2ly", "--times 2ly: item 2 of '1us,2ly' is not a time: unknown unit 'ly' in '2ly' (use s, ms, "
                               "us, \xC2\xB5s, ns)" + times},
           {"--times 1e999us", "--times 1e999us: item 1 of '1e999us' is not a time: '1e999us' is not a finite "
                               "number" + times},
           // Blanks around an item are not part of it.
           {"--times '1us, 2ly '", "--times 2ly: item 2 of '1us, 2ly ' is not a time: unknown unit 'ly' in '2ly' (use "
                                   "s, ms, us, \xC2\xB5s, ns)" + times},
           {"--load-factors '0.5, abc'", "--load-factors abc: item 2 of '0.5, abc' is not a finite number" + factors},
           {"--load-factors '0.5, ,1'", "--load-factors 0.5, ,1: item 2 of '0.5, ,1' is empty" + factors}}) {
    INFO(arguments);
    CHECK(refused_run(dir, arguments).err == "pd-post: error: " + message + "\n");
  }
  // Good lists still read, a time with or without its unit.
  CHECK(run_pd_post(dir, "--times 2e-6,4us").status == 0);
}

// Blanks around the items of a list option are not part of them, whether
// the item is a plain number or carries its unit. Before 7 December 2026
// `--times '1e-6, 2e-6'` was refused ("--times  2e-6: item 2 of ... is not a
// finite number") while `--times '1us, 2us'` was read, `--load-factors
// '0.5, 1'` was refused, and a blank before a comma was refused in every list
// (`--line '1mm ,1mm,3mm,1mm'`: "'1mm ' has characters after the length").
TEST_CASE("pd-post reads the items of its list options alike with blanks around them", "[bad-input]") {
  const auto dir = fresh_dir("list_blanks");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  const auto maps_of = [&](const std::string& arguments) {
    const ToolRun r = run_pd_post(dir, arguments);
    INFO(arguments << "\n" << r.err);
    CHECK(r.status == 0);
    const std::string summary = file_text(dir + "/post/summary.json");
    return summary.substr(std::min(summary.find("\"maps\""), summary.size()));
  };
  const std::string maps = maps_of("--times 1e-6,2e-6");
  CHECK_THAT(maps, Contains("\"requested_time_s\": 1e-06") && Contains("\"requested_time_s\": 2e-06"));
  for (const std::string list : {"'1e-6, 2e-6'", "' 1e-6 ,2e-6 '", "'1e-6,\t2e-6'", "'1us, 2e-6'", "'1e-6 , 2 us'"})
    CHECK(maps_of("--times " + list) == maps);
  // A dynamic run notes the load factors and draws no map of them.
  const ToolRun factors = run_pd_post(dir, "--load-factors '0.5, 1'");
  CHECK(factors.status == 0);
  CHECK_THAT(factors.err, Contains("pd-post: note: --load-factors is for quasi-static runs"));
  const ToolRun line = run_pd_post(dir, "--line '1mm ,1mm, 3mm,1mm '");
  INFO(line.err);
  CHECK(line.status == 0);
  CHECK(fs::exists(dir + "/post/line_profile.csv"));
}

// A command line the frame would misread, refused naming the option and what
// to do, before 7 December 2026: an option given twice, or OUTDIR given as the
// argument and as --outdir (Boost's "option '--threshold' cannot be specified
// more than once" named neither the values nor what to do); an option left
// without its value before another (`--pores --threshold 0.35` took
// --threshold for the pore file, then "unexpected argument '0.35'"), or empty
// after '=' (`--pores=`: Boost's "the argument for option '--pores' should
// follow immediately after the equal sign").
TEST_CASE("pd-post names an option given twice or left without its value, and what to do", "[bad-input]") {
  const auto dir = fresh_dir("option_given_twice");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6);
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {"--threshold 0.35 --threshold=0.5", "--threshold given twice ('--threshold 0.35', then '--threshold=0.5'): "
                                                "give it once, with the value you mean"},
           {"--outdir other", "OUTDIR given twice ('" + dir + "', then '--outdir other'): give it once, as the "
                              "command's first argument (--outdir is another name for it)"},
           {"--pores --threshold 0.35", "--pores: no value after it ('--threshold', the word after it, is an option): "
                                        "give one (--pores VALUE, pd-post --help says what it takes), or leave --pores "
                                        "out"},
           {"--pores=", "--pores: the value is empty (''; an unset shell variable?): give one, or leave --pores out"},
           // A negative number is a value, not an option.
           {"--times -1us", "--times -1us: item 1 of '-1us' is negative: give times from 0, in s or with their unit, "
                            "comma-separated, e.g. --times 1.5e-4,300us"}}) {
    INFO(arguments);
    CHECK(refused_run(dir, arguments).err == "pd-post: error: " + message + "\n");
  }
}
