// The crack-speed window follows from the physics (15 cells at the Rayleigh
// speed), not from a step count, so a small time step on a coarse lattice no
// longer turns the tip's cell-by-cell moves into speeds above c_R.
#include <catch2/catch.hpp>
#include <cmath>

#include "post_pipeline.hpp"
#include "speed_window.hpp"
#include "synthetic_output.hpp"

using namespace pd::post;
using namespace pd::post::test;
using Catch::Matchers::StartsWith;

namespace {
// A coarse lattice (dx = 0.5 mm) with a small step (dt = 0.01 us), as on the
// runs where 30-step windows read up to 1.5 c_R: a straight crack at 600 m/s
// along the row y = 20.25 mm, pre-crack to x = 5 mm; band of three rows.
constexpr double dx = 0.5e-3, dt = 1e-8, v = 600.0, crack_y = 20.25e-3, a0 = 5e-3;
double coarse_arrival(double x, double y) {
  if (std::abs(y - crack_y) > 1.01 * dx || x > 90e-3) return -1;
  return x <= a0 ? 0.0 : (x - a0) / v;
}

PostResult coarse_run(const std::string& name, int window_steps, double window_time = 0) {
  const auto dir = fresh_dir(name);
  SyntheticRun run;
  run.time_step = dt;
  write_arrival_output(dir, make_lattice(100e-3, 40e-3, dx), coarse_arrival, 160e-6, run);
  PostOptions o;
  o.outdir = dir;
  o.window_steps = window_steps;
  o.window_time = window_time;
  return analyse(o);
}

// c_R of the synthetic run (plane stress PMB, nu = 1/3), from Rayleigh's
// closed form for nu' = 1/4: k = sqrt(2 - 2 / sqrt(3)), c_s = sqrt(3E / (8 rho)).
const double rayleigh = std::sqrt(2 - 2 / std::sqrt(3.0)) * std::sqrt(3 * test_youngs / 8 / test_density);
}  // namespace

TEST_CASE("the default window lets a tip at c_R cross 15 cells, whatever the time step", "[window]") {
  const PostResult r = coarse_run("window_coarse", 0);
  // 15 x 0.5 mm / (929.0 m/s x 0.01 us) = 807.3 -> 808 steps.
  const int expected = static_cast<int>(std::ceil(15 * dx / (rayleigh * dt)));
  CHECK(expected == 808);
  CHECK(r.window_steps == expected);
  CHECK_FALSE(r.window.requested);
  CHECK(r.warnings.empty());
  REQUIRE(r.speeds.size() > 1000);
  // The tip moves a column (dx) at a time: each window reads v to within
  // dx / w (here 62 m/s), and none reaches c_R.
  int growth = 0;
  for (const auto& s : r.speeds) {
    if (!s.is_growth()) continue;
    ++growth;
    CHECK(std::abs(s.speed - v) <= dx / r.window_seconds + 1e-6);
    CHECK(s.speed < rayleigh);
  }
  CHECK(growth == static_cast<int>(r.speeds.size()));
}

// A refined run: its particle file's spacing (field `spacing`) is the coarse
// one, its time step and its crack's cells the fine ones. The window counts
// the cells the crack crossed (here every square split: 0.25 mm), so it is
// half the coarse lattice's 808 steps (before the second sitting of 5
// December 2026 it counted 0.5 mm cells: 808 steps, 2^levels times too long).
TEST_CASE("a refined run's window counts the fine cells its crack crossed", "[window]") {
  const auto dir = fresh_dir("window_refined");
  SyntheticRun run;
  run.time_step = dt;
  write_arrival_output(dir, split_right_of(make_lattice(100e-3, 40e-3, dx), 0.0), coarse_arrival, 160e-6, run);
  PostOptions o;
  o.outdir = dir;
  const PostResult r = analyse(o);
  const int expected = static_cast<int>(std::ceil(15 * (dx / 2) / (rayleigh * dt)));
  CHECK(expected == 404);
  CHECK(r.window_steps == expected);
  bool noted = false;
  for (const auto& n : r.notes) noted = noted || n.find("speed window sized by the cells the crack crossed, 0.25 mm") !=
                                                     std::string::npos;
  CHECK(noted);
  // An unrefined lattice keeps its spacing, without a note.
  const PostResult coarse = coarse_run("window_unrefined", 0);
  CHECK(coarse.window_steps == 808);
  for (const auto& n : coarse.notes) CHECK(n.find("speed window sized") == std::string::npos);
}

TEST_CASE("a window shorter than the rule is used as asked, with a warning", "[window]") {
  SECTION("30 steps, the old default") {
    const PostResult r = coarse_run("window_30", 30);
    CHECK(r.window_steps == 30);
    REQUIRE(r.warnings.size() == 1);
    CHECK(r.warnings[0].find("shorter than 808 steps") != std::string::npos);
    // What the warning is about: in 0.3 us the tip crosses a column or not,
    // so windows read 0 or dx / w = 1667 m/s = 1.8 c_R.
    double fastest = 0;
    for (const auto& s : r.speeds)
      if (s.is_growth()) fastest = std::max(fastest, s.speed);
    CHECK(fastest > rayleigh);
  }
  SECTION("in seconds") {
    const PostResult r = coarse_run("window_time_short", 0, 1e-6);
    CHECK(r.window_steps == 100);
    CHECK(r.warnings.size() == 1);
  }
  SECTION("a longer window needs no warning") {
    const PostResult r = coarse_run("window_long", 1000);
    CHECK(r.window_steps == 1000);
    CHECK(r.warnings.empty());
  }
}

// read_arrival_data bounds the wave speed; a c_R of 1e-300 m/s reaching the
// window's rule is refused, naming the file, not cast to an int beyond its range.
TEST_CASE("the speed window's rule refuses a step count beyond an int", "[speed-window]") {
  std::vector<std::string> warnings;
  CHECK_THROWS_WITH(choose_speed_window(2e-8, 1e-4, 1e-300, 0, 0, warnings, "RUN/arrival.vtp"),
                    "RUN/arrival.vtp: field 'time_step' = 2e-08 s makes the speed window's rule, the time a tip at "
                    "c_R = 1e-300 m/s takes to cross 15 cells of 0.1 mm, 7.5e+304 steps, more than an int counts (an "
                    "edited or damaged file)");
  CHECK(choose_speed_window(2e-8, 1e-4, 1000, 0, 0, warnings, "RUN/arrival.vtp").rule_steps == 75);
}
