// A crack that stops at a pore and restarts on its far side after a known
// trapping time; pore detection from the particle layout.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "post_pipeline.hpp"
#include "synthetic_output.hpp"

using namespace pd::post;
using namespace pd::post::test;

namespace {
// Pore of radius R at (xp, crack_y) with no particles inside. The crack reaches
// its near edge at t_in = (xp - R - a0) / v, waits `trap`, and restarts at
// the far edge: arrival t_in + trap + (x - (xp + R)) / v.
constexpr double v = 600.0, crack_y = 5.05e-3, a0 = 2e-3, dx = 0.1e-3;
constexpr double xp = 10.0e-3, R = 1.0e-3, trap = 5e-6;
constexpr double t_in = (xp - R - a0) / v;

double trapped_arrival(double x, double y) {
  if (std::abs(y - crack_y) > 1.01 * dx || x > 18e-3) return -1;
  if (x <= a0) return 0.0;
  if (x < xp) return (x - a0) / v;
  return t_in + trap + (x - (xp + R)) / v;
}

PostResult run_trapped(const std::string& name, bool pore_file) {
  const auto dir = fresh_dir(name);
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx, {{xp, crack_y, R}}), trapped_arrival, 40e-6);
  PostOptions o;
  o.outdir = dir;
  if (pore_file) {
    o.pores_file = dir + "/pores.csv";
    std::ofstream(o.pores_file) << "x_m,y_m,r_m\n" << xp << "," << crack_y << "," << R << "\n";
  }
  return analyse(o);
}
}  // namespace

TEST_CASE("a pore is detected from the particle layout", "[pores]") {
  const PostResult r = run_trapped("pore_detect", false);
  REQUIRE(r.pores.size() == 1);
  // The hole is the union of removed cells: its centre is the pore's up to
  // half a spacing, its equal-area radius within one spacing.
  CHECK(std::hypot(r.pores[0].x - xp, r.pores[0].y - crack_y) <= 0.5 * dx);
  CHECK(std::abs(r.pores[0].radius - R) <= dx);
}

TEST_CASE("the trapping time at a pore is recovered within one window", "[pores]") {
  for (bool pore_file : {false, true}) {
    const PostResult r = run_trapped(pore_file ? "pore_file" : "pore_auto", pore_file);
    // The crack that restarts beyond the pore continues the same branch.
    REQUIRE(r.network.branches.size() == 1);
    CHECK(r.network.branchings.empty());
    REQUIRE(r.pore_visits.size() == 1);
    const auto& visit = r.pore_visits[0];
    CHECK(visit.branch == 0);
    CHECK(visit.jumped);
    // Entry is seen when the tip is within 1.5 spacings of the edge, the
    // restart at the first particle beyond it: both within a window of the
    // exact t_in and t_in + trap.
    CHECK(std::abs(visit.enter_time - t_in) <= r.window_seconds);
    CHECK(std::abs(visit.restart_time - (t_in + trap)) <= r.window_seconds);
    CHECK(std::abs(visit.trapping_time - trap) <= r.window_seconds);
    // Windows containing the jump across the pore are flagged, so the
    // speed statistics do not see a 2R jump as crack speed.
    bool flagged = false;
    for (const auto& s : r.speeds) flagged |= s.across_pore;
    CHECK(flagged);
    CHECK(speed_stats(r.speeds).max <= v + dx / r.window_seconds + 1e-6);
  }
}
