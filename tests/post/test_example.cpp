// The documented example (docs/post.md): a 50 x 25 mm plate with pores of
// radius 0.75 mm on the mid-line every W/9 (case C3-A of the reference
// cases, at a coarse 0.1 mm spacing). The crack stops at the first three
// pores for known times, then branches at +-15 degrees between pores 4 and 5.
#include <catch2/catch.hpp>
#include <cmath>

#include "post_pipeline.hpp"
#include "synthetic_output.hpp"

using namespace pd::post;
using namespace pd::post::test;

namespace {
constexpr double dx = 0.1e-3, crack_y = 12.55e-3, a0 = 2e-3, R = 0.75e-3, D = 50e-3 / 9;
constexpr double xb = 24.0e-3, v_branch = 550.0, half_angle = 15.0 * M_PI / 180.0;
const double speeds[4] = {450.0, 520.0, 580.0, 600.0};  // before pore 1, 2, 3 and after pore 3
const double traps[3] = {4e-6, 3e-6, 2e-6};             // at pores 1, 2, 3

// Arrival along the mid-line: constant speed between pores, a pause at each
// of the first three pores (near edge to far edge).
double midline_arrival(double x) {
  double t = 0, from = a0;
  for (int k = 0; k < 3; ++k) {
    const double near_edge = (k + 1) * D - R, far_edge = (k + 1) * D + R;
    if (x < near_edge + 1e-12) return t + (x - from) / speeds[k];
    if (x <= far_edge) return -1;  // inside the pore: no particles anyway
    t += (near_edge - from) / speeds[k] + traps[k];
    from = far_edge;
  }
  return t + (x - from) / speeds[3];
}

double example_arrival(double x, double y) {
  double t = -1;
  if (std::abs(y - crack_y) <= 1.01 * dx && x <= xb) t = x <= a0 ? 0.0 : midline_arrival(x);
  const double tb = midline_arrival(xb);
  for (double sign : {1.0, -1.0}) {
    const double ux = std::cos(half_angle), uy = sign * std::sin(half_angle);
    const double s = (x - xb) * ux + (y - crack_y) * uy, off = -(x - xb) * uy + (y - crack_y) * ux;
    if (s >= 0 && std::abs(off) <= 1.01 * dx && x < 46e-3) {
      const double r = tb + s / v_branch;
      if (t < 0 || r < t) t = r;
    }
  }
  return t;
}
}  // namespace

TEST_CASE("example plate: three pore traps, then one branching", "[example]") {
  std::vector<Hole> holes;
  for (int k = 1; k <= 8; ++k) holes.push_back({k * D, crack_y, R});
  const auto dir = fresh_dir("example");
  write_arrival_output(dir, make_lattice(50e-3, 25e-3, dx, holes), example_arrival, 80e-6, {0.2, 0.35, 0.5});
  PostOptions o;
  o.outdir = dir;
  const PostResult r = analyse(o);

  REQUIRE(r.pores.size() == 8);
  REQUIRE(r.network.branchings.size() == 1);
  CHECK(r.network.branches.size() == 3);
  CHECK(r.network.branchings[0].angle_deg == Approx(30.0).margin(2.0));
  CHECK(std::abs(r.network.branchings[0].time - midline_arrival(xb)) <= r.window_seconds);
  // Pores 1-3 (index 0-2) trap the main crack for the given times.
  int found = 0;
  for (const auto& v : r.pore_visits)
    if (v.branch == 0 && v.pore < 3) {
      ++found;
      CHECK(std::abs(v.trapping_time - traps[v.pore]) <= r.window_seconds);
    }
  CHECK(found == 3);
}
