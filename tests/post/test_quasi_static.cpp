// Quasi-static output directories: maps of the final state and of
// snapshots, reactions against load factor, and the jump of displacement
// across a line, on a synthetic field whose jump is known.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "line_profile.hpp"
#include "quasi_static_pipeline.hpp"
#include "results_format.hpp"
#include "synthetic_output.hpp"
#include "../test_commands.hpp"

using namespace pd::post;
using namespace pd::post::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

using pd::test_support::file_text;

// A 20 x 10 mm plate (0.1 mm lattice) cut along y = 5 mm (between two rows of
// particles) from x = 0 to 12 mm. Above the cut the material is displaced
// by an extra jump: opening J(x) = 4 um (1 - x / 20 mm), sliding K = 1.5 um;
// both sides carry the same uniform strain (u_x = 1e-4 x, u_y = 2e-4 (y - 5 mm)).
// The fields are linear on each side of the line, so the one-sided fits
// give the jump exactly.
constexpr double crack_y = 5e-3, crack_end = 12e-3, J0 = 4e-6, K = 1.5e-6;
double jump_opening(double x) { return J0 * (1 - x / 20e-3); }
double above(double x, double y) { return y > crack_y && x < crack_end ? 1.0 : 0.0; }
double ux(double x, double y) { return 1e-4 * x + above(x, y) * K; }
double uy(double x, double y) { return 2e-4 * (y - crack_y) + above(x, y) * jump_opening(x); }
double damage(double x, double y) { return std::abs(y - crack_y) < 0.1e-3 && x < crack_end ? 1.0 : 0.0; }

QuasiStaticRun plate_run() {
  QuasiStaticRun run;
  run.load_factors = {0.25, 0.5, 0.75, 1.0};
  // N: a peak, then the plate separates; the last as pd-solve writes it, 12 digits.
  run.right_reaction_x = {10.0, 20.0, 30.0, 5.00123456789};
  run.ux = ux, run.uy = uy, run.damage = damage;
  run.snapshot_factors = {0.5, 1.0};
  return run;
}

bool mentions(const std::vector<std::string>& list, const std::string& text) {
  for (const auto& s : list)
    if (s.find(text) != std::string::npos) return true;
  return false;
}
}  // namespace

TEST_CASE("the jump across a line is the known one of a field linear on each side", "[quasi-static]") {
  const Lattice l = make_lattice(20e-3, 10e-3, 0.1e-3);
  std::vector<double> vx, vy, d;
  for (std::size_t i = 0; i < l.x.size(); ++i)
    vx.push_back(ux(l.x[i], l.y[i])), vy.push_back(uy(l.x[i], l.y[i])), d.push_back(damage(l.x[i], l.y[i]));
  // Along the cut, left to right: the + side (left of the direction) is above.
  const SampleLine line{1e-3, crack_y, 11e-3, crack_y};
  const auto samples = sample_line({l.x, l.y, vx, vy, d}, line, 0.1e-3, 0.3e-3);
  REQUIRE(samples.size() == 101);  // every spacing over 10 mm, both ends
  for (const auto& s : samples) {
    INFO("s = " << s.s);
    REQUIRE(s.has_jump);
    CHECK(s.opening == Approx(jump_opening(s.x)).epsilon(1e-9));
    CHECK(s.sliding == Approx(K).epsilon(1e-9));
    CHECK(s.damage == 1.0);
    // On the line the fit takes the rows on both sides: half the jump.
    REQUIRE(s.has_u);
    CHECK(s.uy == Approx(0.5 * jump_opening(s.x)).epsilon(1e-9));
  }
  // Reversed, + and - swap and so do n and t: opening and sliding stay.
  const auto reversed = sample_line({l.x, l.y, vx, vy, d}, {11e-3, crack_y, 1e-3, crack_y}, 0.1e-3, 0.3e-3);
  CHECK(reversed.front().opening == Approx(jump_opening(11e-3)).epsilon(1e-9));
  CHECK(reversed.front().sliding == Approx(K).epsilon(1e-9));
  // Across the uncut ligament (x > 12 mm) there is no jump.
  const auto ligament = sample_line({l.x, l.y, vx, vy, d}, {13e-3, crack_y, 19e-3, crack_y}, 0.1e-3, 0.3e-3);
  for (const auto& s : ligament) CHECK(std::abs(s.opening) <= 1e-9 * J0);
  // Beyond the plate's edge there are no particles on one side: no value.
  const auto edge = sample_line({l.x, l.y, vx, vy, d}, {5e-3, 9.9e-3, 6e-3, 9.9e-3}, 0.1e-3, 0.3e-3);
  for (const auto& s : edge) CHECK_FALSE(s.has_jump);
}

// The bands of the one-sided fits lie from d to 2d on each side of the line.
// On the 10 mm high plate a line at y = 5 mm with d = 6 mm has no material
// in them (y 11 to 17 mm and -7 to -1 mm); a line 0.1 mm below the top edge
// none above it at the horizon (0.3 mm). Before 7 December 2026 both wrote
// line_profile.csv with empty opening and sliding columns, no warning.
TEST_CASE("a line with no sample between material on both sides is warned about", "[quasi-static]") {
  const auto dir = fresh_dir("quasi_static_line_without_jump");
  write_quasi_static_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), plate_run());
  PostOptions o;
  o.outdir = dir;
  o.line = SampleLine{1e-3, crack_y, 11e-3, crack_y};
  o.line_offset = 6e-3;
  auto r = run_quasi_static_post(o);
  const std::string empty = ": opening_m and sliding_m in line_profile.csv are empty";
  CHECK(mentions(r.warnings, "--line: no sample of the line has particles on both sides between 6 and 12 mm from it "
                             "(--line-offset 6 mm)" + empty));
  CHECK(std::none_of(r.line.begin(), r.line.end(), [](const LineSample& s) { return s.has_jump; }));
  CHECK_THAT(file_text(dir + "/post/summary.json"), Contains("between 6 and 12 mm from it"));
  // The default offset, one horizon (3 spacings), along the top edge.
  o.line = SampleLine{5e-3, 9.9e-3, 6e-3, 9.9e-3};
  o.line_offset = 0;
  r = run_quasi_static_post(o);
  CHECK(mentions(r.warnings, "between 0.3 and 0.6 mm from it (the offset, one horizon, 0.3 mm)" + empty));
  // Along the cut at that offset every sample has its jump: no such warning.
  o.line = SampleLine{1e-3, crack_y, 11e-3, crack_y};
  r = run_quasi_static_post(o);
  CHECK_FALSE(mentions(r.warnings, "no sample of the line has particles on both sides"));
}

TEST_CASE("a quasi-static output directory gives maps, reactions and the opening profile", "[quasi-static]") {
  const auto dir = fresh_dir("quasi_static");
  write_quasi_static_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), plate_run());
  PostOptions o;
  o.outdir = dir;
  o.map_load_factors = {0.6};
  o.line = SampleLine{1e-3, crack_y, 11e-3, crack_y};
  const auto r = run_quasi_static_post(o);
  const std::string post = dir + "/post";
  for (const char* f : {"displacement_x_final.png", "displacement_y_final.png", "damage_final.png",
                        "displacement_y_lf0.5.png", "damage_lf0.5.png", "reactions.csv", "reactions.png",
                        "line_profile.csv", "line_profile.png", "summary.json"})
    CHECK(fs::is_regular_file(post + "/" + f));
  // No strain energy in quasi-static outputs: no such map, and a note says what is drawn instead.
  CHECK_FALSE(fs::exists(post + "/strain_energy_final.png"));
  CHECK(mentions(r.notes, "no 'strain_energy_density'"));
  CHECK(r.warnings.empty());
  CHECK(r.data.final_state);
  CHECK(r.max_damage == 1.0);
  REQUIRE(r.maps.size() == 1);
  CHECK(r.maps[0].used == 0.5);  // the snapshot nearest 0.6

  // reactions.csv: the load factors and reactions of load_steps.csv, as
  // written (before, rounded to 9 digits: 5.00123457).
  std::ifstream table(post + "/reactions.csv");
  std::string header, row;
  std::getline(table, header);
  CHECK(header == "step,load_factor,left_reaction_x_N,left_reaction_y_N,right_reaction_x_N,right_reaction_y_N");
  const auto run = plate_run();
  for (std::size_t k = 0; k < run.load_factors.size(); ++k) {
    REQUIRE(std::getline(table, row));
    std::ostringstream expected;
    expected.precision(15);
    expected << k + 1 << ',' << run.load_factors[k] << ',' << -run.right_reaction_x[k] << ",0,"
             << run.right_reaction_x[k] << ",0";
    CHECK(row == expected.str());
  }
  // line_profile.csv: the opening at its first sample (x = 1 mm).
  std::ifstream profile(post + "/line_profile.csv");
  std::getline(profile, header);
  CHECK(header == "s_m,x_m,y_m,u_x_m,u_y_m,damage,opening_m,sliding_m");
  std::getline(profile, row);
  std::stringstream fields(row);
  std::vector<double> v;
  for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
  REQUIRE(v.size() == 8);
  CHECK(v[6] == Approx(jump_opening(1e-3)).epsilon(1e-6));
  CHECK(v[7] == Approx(K).epsilon(1e-6));

  const std::string summary = file_text(post + "/summary.json");
  CHECK_THAT(summary, Contains("\"mode\": \"quasi_static\"") && Contains("\"complete\": true") &&
                          Contains("\"peak_N\": 30") && Contains("\"peak_load_factor\": 0.75"));
  // Every file written has one of pd-post's names, which a later pd-solve run removes.
  for (const auto& entry : fs::directory_iterator(post)) {
    INFO(entry.path());
    CHECK(pd::results::is_post_output(entry.path().filename().string()));
  }
}

// A run that loads, unloads and pushes: load factors repeat and go below 0.
TEST_CASE("a quasi-static run that unloads: maps at negative and repeated load factors", "[quasi-static]") {
  const auto dir = fresh_dir("quasi_static_unloading");
  QuasiStaticRun run = plate_run();
  run.load_factors = {0.5, 1.0, 0.5, -0.5};
  run.right_reaction_x = {10.0, 20.0, 10.0, -10.0};
  run.snapshot_factors = {0.5, 1.0, 0.5, -0.5};
  write_quasi_static_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), run);
  PostOptions o;
  o.outdir = dir;
  o.map_load_factors = {0.5, -0.5};
  const auto r = run_quasi_static_post(o);
  REQUIRE(r.maps.size() == 2);
  CHECK(r.maps[1].used == -0.5);
  CHECK(fs::is_regular_file(dir + "/post/displacement_y_lf-0.5.png"));
  // 0.5 is in the first and the third snapshot: the note says which is drawn.
  CHECK(mentions(r.notes, "load factor 0.5 is in more than one snapshot: the map shows"));
  CHECK(!mentions(r.notes, "load factor load factor"));  // (said twice before 5 December 2026)
  CHECK(mentions(r.notes, "step_00000001.vtp (the first), not "));
  CHECK(mentions(r.notes, "step_00000003.vtp"));
}

TEST_CASE("an unfinished quasi-static run: the last snapshot stands in, with warnings", "[quasi-static]") {
  const auto dir = fresh_dir("quasi_static_unfinished");
  QuasiStaticRun run = plate_run();
  run.final_state = false;  // written at the end of a run
  run.summary = false;
  run.max_damage = {0, 0, 0.25, 0.438};  // the solver's log: damage grew after the last snapshot
  run.snapshot_factors = {0.5};
  write_quasi_static_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), run);
  PostOptions o;
  o.outdir = dir;
  o.line = SampleLine{1e-3, crack_y, 11e-3, crack_y};
  const auto r = run_quasi_static_post(o);
  REQUIRE(r.warnings.size() == 2);
  CHECK_THAT(r.warnings[0], Contains("incomplete run") && Contains("4 load steps"));
  CHECK_THAT(r.warnings[1], Contains("the maps show the last snapshot") && Contains("load factor 0.5"));
  CHECK_FALSE(r.data.final_state);
  CHECK(fs::is_regular_file(dir + "/post/displacement_y_final.png"));
  // The snapshot at load factor 0.5 holds half the final fields, in single
  // precision: half the jump, to float round-off.
  REQUIRE(!r.line.empty());
  for (const auto& s : r.line) CHECK(s.opening == Approx(0.5 * jump_opening(s.x)).epsilon(1e-5));
  // The state drawn and the run's last step each with their own damage.
  CHECK_THAT(file_text(dir + "/post/summary.json"), Contains("\"complete\": false") &&
                                                        Contains("\"final_state\": false") &&
                                                        Contains("\"last_max_damage\": 0.438") &&
                                                        Contains("\"load_factor\": 0.5"));
}

// A folder where the final state belongs is named for what it is; before 7
// December 2026 it was "file not found", of a path that was there.
TEST_CASE("a quasi-static run's final_state.vtp that is a folder is refused saying so", "[quasi-static]") {
  const auto dir = fresh_dir("quasi_static_state_folder");
  write_quasi_static_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), plate_run());
  const std::string state = dir + "/" + pd::results::final_state_file;
  fs::remove(state);
  fs::create_directory(state);
  PostOptions o;
  o.outdir = dir;
  CHECK_THROWS_WITH(run_quasi_static_post(o), state + ": a folder, not a file (the run's final state, which pd-post "
                                                      "reads; give the folder that pd-solve -o wrote)");
}

// A snapshot is drawn at final_state.vtp's positions: one of its particles in
// another order (saved again by another program) would put each value at
// another particle's place. Before 7 December 2026 it was drawn so.
TEST_CASE("a quasi-static snapshot of the run's particles in another order is refused", "[quasi-static]") {
  const auto dir = fresh_dir("quasi_static_snapshot_reordered");
  const Lattice lattice = make_lattice(20e-3, 10e-3, 0.1e-3);
  write_quasi_static_output(dir, lattice, plate_run());
  // The same run's files with the particles in reverse order: its snapshot at load factor 0.5 copied in.
  const auto reversed_dir = fresh_dir("quasi_static_snapshot_reversed");
  Lattice reversed = lattice;
  std::reverse(reversed.x.begin(), reversed.x.end());
  std::reverse(reversed.y.begin(), reversed.y.end());
  write_quasi_static_output(reversed_dir, reversed, plate_run());
  const std::string snapshot = dir + "/snapshots/step_00000001.vtp";
  fs::copy_file(reversed_dir + "/snapshots/step_00000001.vtp", snapshot, fs::copy_options::overwrite_existing);
  PostOptions o;
  o.outdir = dir;
  o.map_load_factors = {0.5};
  CHECK_THROWS_WITH(run_quasi_static_post(o), snapshot + ": particle 0 is at (0.01995, 0.00995) m, and in " + dir +
                                                  "/" + pd::results::final_state_file + " at (5e-05, 5e-05) m: its "
                                                  "particles are in another order, or of another plate (the file "
                                                  "saved again by another program, or another run's); give the "
                                                  "snapshot pd-solve wrote with the run, or run pd-solve again");
}
