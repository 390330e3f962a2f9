// Crack speed of a straight crack at constant speed, and the Rayleigh speed.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "crack_speed.hpp"
#include "post_pipeline.hpp"
#include "synthetic_output.hpp"
#include "tip_tracking.hpp"

using namespace pd::post;
using namespace pd::post::test;

namespace {
// 20 x 10 mm plate, 0.1 mm lattice, pre-crack to x = 2 mm along the row at
// y = 5.05 mm, then growth at v; band of three particle rows (|y - crack_y| <= dx).
constexpr double v = 600.0, crack_y = 5.05e-3, a0 = 2e-3, dx = 0.1e-3;
double straight_arrival(double x, double y) {
  if (std::abs(y - crack_y) > 1.01 * dx || x > 18e-3) return -1;
  return x <= a0 ? 0.0 : (x - a0) / v;
}
}  // namespace

TEST_CASE("a straight crack at constant speed is recovered within 2 %", "[speed]") {
  const auto dir = fresh_dir("straight");
  const double end_time = 30e-6;
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx), straight_arrival, end_time);
  PostOptions o;
  o.outdir = dir;
  const PostResult r = analyse(o);

  REQUIRE(r.network.branches.size() == 1);
  CHECK(r.network.branchings.empty());
  // The default window: 15 cells at c_R (929.0 m/s, test_rayleigh.cpp):
  // 15 x 0.1 mm / (929.0 m/s x 0.02 us) = 80.7 -> 81 steps.
  CHECK(r.window_steps == 81);
  CHECK(r.window_seconds == Approx(81 * test_time_step));
  REQUIRE(r.speeds.size() > 100);
  // The tip moves a whole particle at a time, so one window sees
  // v * w rounded to particles: each sample is within dx / w of v; the
  // average over the run telescopes to (distance / time) and is within 2 %.
  const auto stats = speed_stats(r.speeds);
  CHECK(stats.mean == Approx(v).epsilon(0.02));
  for (const auto& s : r.speeds) CHECK(std::abs(s.speed - v) <= dx / r.window_seconds + 1e-6);
  // The tip ends at the last cracked column (x = 17.95 mm): the farthest
  // particle averaged with its linked cracked neighbours, which lie at most
  // one column (dx) behind it.
  CHECK(r.tips[0].x.back() <= 17.95e-3 + 1e-9);
  CHECK(r.tips[0].x.back() >= 17.95e-3 - dx);
  // The branch starts at the pre-crack (t = 0) and ends at (17.95 - 2) mm / v.
  CHECK(r.network.branches[0].start_time == 0.0);
  CHECK(r.network.branches[0].end_time == Approx((17.95e-3 - a0) / v).margin(test_time_step));
  // Origin: the far end of the pre-crack (x = 0.05 mm), not its tip.
  CHECK(r.network.branches[0].origin_x == Approx(0.05e-3));
}

TEST_CASE("a window given in seconds is rounded to whole steps", "[speed]") {
  const auto dir = fresh_dir("straight_window");
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx), straight_arrival, 30e-6);
  PostOptions o;
  o.outdir = dir;
  o.window_time = 1.01e-6;  // 50.5 steps -> 51 (lround)
  const PostResult r = analyse(o);
  CHECK(r.window_steps == 51);
  // A longer window: samples within dx / w, 1 / 51 of the distance per window.
  CHECK(speed_stats(r.speeds).mean == Approx(v).epsilon(0.02));
}

TEST_CASE("a pre-crack seeds the tip, and tips and speeds start at initiation", "[speed]") {
  // The straight crack, but the pre-crack stands still for 10 us first.
  const double t_init = 10e-6;
  const auto dir = fresh_dir("straight_late");
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx), [&](double x, double y) {
    const double t = straight_arrival(x, y);
    return t > 0 ? t + t_init : t;
  }, 40e-6);
  PostOptions o;
  o.outdir = dir;
  const PostResult r = analyse(o);
  REQUIRE(r.network.branches.size() == 1);
  // The branch (the pre-crack) exists from t = 0 ...
  CHECK(r.network.branches[0].start_time == 0.0);
  // ... its tip from one step before the first particle beyond it cracks,
  // at the pre-crack's tip (x = 1.95 mm, averaged with the column behind).
  const double first_growth = on_step(t_init + (a0 + 0.5 * dx - a0) / v);
  const auto& tip = r.tips[0];
  CHECK(tip.time.front() == Approx(first_growth - test_time_step).margin(1e-12));
  CHECK(tip.x.front() <= 1.95e-3 + 1e-9);
  CHECK(tip.x.front() >= 1.95e-3 - dx);
  // No zero-speed stretch before initiation: every window sees the crack run.
  REQUIRE(!r.speeds.empty());
  CHECK(r.speeds.front().time == Approx(first_growth - test_time_step).margin(1e-12));
  for (const auto& s : r.speeds) CHECK(std::abs(s.speed - v) <= dx / r.window_seconds + 1e-6);
}

TEST_CASE("a tip that jumps over a gap flags its windows instead of reporting a speed", "[speed]") {
  // A tip path by hand: 600 m/s for 100 steps, then 2 mm in one step (a jump
  // onto a separate damage group), then 600 m/s again. Reference: the path itself.
  const double step = 2e-8, speed = 600.0, jump = 2e-3, horizon = 0.25e-3;
  TipPath path;
  for (int k = 0; k < 200; ++k) {
    path.time.push_back(k * step);
    path.x.push_back(speed * k * step + (k >= 100 ? jump : 0.0));
    path.y.push_back(0.0);
  }
  const int window = 30;
  const auto samples = crack_speeds(path, CrackBranch{}, window, horizon);
  REQUIRE(samples.size() == 200 - window);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const bool contains_jump = k < 100 && k + window >= 100;
    INFO("window " << k);
    CHECK(samples[k].tip_jump == contains_jump);
    if (!contains_jump) CHECK(samples[k].speed == Approx(speed).epsilon(1e-9));
  }
  const auto stats = speed_stats(samples);
  CHECK(stats.max == Approx(speed).epsilon(1e-9));
  CHECK(stats.samples == static_cast<int>(samples.size()) - window);
}

// Reference: docs/post.md ("Output files", branches.csv): a branch's length
// is that of the polyline through its tip's positions with vertices at least
// two horizons apart. Exact values: a straight path's chord, and a circular
// arc's length to the polyline's error (chords of two horizons on a radius
// of 20 horizons: relative error (2 delta)^2 / (24 R^2), about 4e-4). A tip
// hopping between rows a quarter horizon on either side of the line (the
// band's outer rows at m = 4) adds at most sqrt(1 + 1/16) - 1 = 3 %.
TEST_CASE("a crack's length ignores its tip's hops within the damage band", "[crack-speed]") {
  const double horizon = 0.4e-3;
  TipPath straight, jittered, arc;
  // 12 mm along x in steps of a tenth of a horizon; the jittered tip also
  // hops up and down by a quarter horizon and back by 0.15 horizons every fourth step.
  for (int k = 0; k <= 300; ++k) {
    const double x = k * 0.04e-3;
    straight.x.push_back(x), straight.y.push_back(0);
    const double back = (k % 4 == 3) ? -0.06e-3 : 0.0;
    jittered.x.push_back(x + back), jittered.y.push_back((k % 2 ? 0.1e-3 : -0.1e-3) * (k % 300 != 0));
  }
  jittered.y.front() = jittered.y.back() = 0;
  CHECK(tip_path_length(straight, 2 * horizon) == Approx(12e-3).epsilon(1e-12));
  // The sum of the moves counts the hops: over four times the crack.
  double moves = 0;
  for (std::size_t k = 1; k < jittered.x.size(); ++k)
    moves += std::hypot(jittered.x[k] - jittered.x[k - 1], jittered.y[k] - jittered.y[k - 1]);
  CHECK(moves > 3 * 12e-3);
  CHECK(tip_path_length(jittered, 2 * horizon) == Approx(12e-3).epsilon(0.035));
  // A quarter circle of radius 8 mm.
  const double radius = 8e-3;
  for (int k = 0; k <= 1000; ++k) {
    const double a = 0.5 * M_PI * k / 1000;
    arc.x.push_back(radius * std::cos(a)), arc.y.push_back(radius * std::sin(a));
  }
  arc.start_x = radius;
  CHECK(tip_path_length(arc, 2 * horizon) == Approx(0.5 * M_PI * radius).epsilon(1e-3));
}

// A link in a cascade of branchings: a child born at (30, 12.5) mm at 270 us
// branches again one step later, and its two particles, 4 mm on, crack only
// after that (the main job's plate has such links). Its tip has one sample;
// its length is the distance from its branching point, not 0.
TEST_CASE("a branch whose particles crack after it branched again has its length from its branching point",
          "[crack-speed]") {
  ArrivalData data;
  data.time_step = 0.07e-6;
  for (double y : {12.45e-3, 12.55e-3})
    data.x.push_back(34e-3), data.y.push_back(y), data.arrival.push_back(275e-6), data.cell_size.push_back(0.125e-3);
  CrackBranch link;
  link.id = 9, link.parent = 7;
  link.particles = {0, 1};
  link.origin_x = 30e-3, link.origin_y = 12.5e-3;
  link.start_time = 270e-6, link.end_time = 270.07e-6;
  const TipPath tip = track_tip(link, data, data.time_step);
  REQUIRE(tip.x.size() == 1);
  CHECK(tip_path_length(tip, 0.75e-3) == Approx(4e-3).epsilon(1e-9));
  // A pre-crack's length is what it grew: from its tip before it grows.
  CrackBranch pre_crack;
  pre_crack.particles = {0, 1};
  data.arrival = {0, 0};
  CHECK(tip_path_length(track_tip(pre_crack, data, data.time_step), 0.75e-3) == 0);
}

// A run that ends within one speed window of its crack's first growth has no
// speed: summary.json says null (not 0 m/s) and a warning says why and what
// measures it. (Before, a dual-horizon run stopped 131 steps in, with a
// window of 124 steps, reported 0 m/s for a crack that had grown 0.42 mm.)
TEST_CASE("a crack shorter than one speed window has no speed, with a warning", "[speed]") {
  const auto dir = fresh_dir("straight_short");
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx), straight_arrival, 30e-6);
  PostOptions o;
  o.outdir = dir;
  o.window_steps = 100000;  // longer than the run
  const PostResult r = run_post(o);
  REQUIRE(r.network.branches.size() == 1);
  CHECK(r.speeds.empty());
  CHECK(std::count_if(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
          return w.find("no crack speed measured: the longest tip path spans") != std::string::npos &&
                 w.find("fewer than the speed window of 100000 steps") != std::string::npos;
        }) == 1);
  std::ifstream in(dir + "/post/summary.json");
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(summary.find("\"max_speed_m_per_s\": null") != std::string::npos);
  CHECK(summary.find("\"mean_speed_over_rayleigh\": null") != std::string::npos);
  CHECK(summary.find("\"max_speed_m_per_s\": 0") == std::string::npos);
}
