// A crack that branches into two straight rays at a known time and angle.
#include <catch2/catch.hpp>
#include <algorithm>
#include <fstream>
#include <string>
#include <cmath>

#include "post_pipeline.hpp"
#include "synthetic_output.hpp"

using namespace pd::post;
using namespace pd::post::test;

namespace {
// Trunk along crack_y from the pre-crack tip a0 to the branching point (xb, crack_y),
// reached at tb = (xb - a0) / v; then two rays at +-half_angle from it, each
// growing at v: arrival tb + s / v, s = distance along the ray. Bands are the
// particles within one spacing of the line (three rows).
constexpr double v = 600.0, crack_y = 5.05e-3, a0 = 2e-3, dx = 0.1e-3, xb = 8.05e-3;
constexpr double tb = (xb - a0) / v;

double ray_arrival(double x, double y, double half_angle_deg) {
  const double a = half_angle_deg * M_PI / 180.0;
  const double ux = std::cos(a), uy = std::sin(a);
  const double s = (x - xb) * ux + (y - crack_y) * uy;        // along the ray
  const double off = -(x - xb) * uy + (y - crack_y) * ux;     // across it
  if (s < 0 || std::abs(off) > 1.01 * dx || x > 18e-3) return -1;
  return tb + s / v;
}

double branching_arrival(double x, double y, double half_angle_deg = 15.0) {
  double t = -1;
  if (std::abs(y - crack_y) <= 1.01 * dx && x <= xb) t = x <= a0 ? 0.0 : (x - a0) / v;
  for (double angle : {half_angle_deg, -half_angle_deg}) {
    const double r = ray_arrival(x, y, angle);
    if (r >= 0 && (t < 0 || r < t)) t = r;
  }
  return t;
}
}  // namespace

TEST_CASE("a crack branching at +-15 degrees gives two branches at the right time and angle", "[branching]") {
  const double half_angle = GENERATE(15.0, 25.0);
  const auto dir = fresh_dir("branching_" + std::to_string(static_cast<int>(half_angle)));
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx),
                       [&](double x, double y) { return branching_arrival(x, y, half_angle); }, 40e-6);
  PostOptions o;
  o.outdir = dir;
  const PostResult r = analyse(o);

  // One event: the trunk (branch 0) ends, two children start.
  REQUIRE(r.network.branchings.size() == 1);
  const auto& e = r.network.branchings[0];
  REQUIRE(e.children.size() == 2);
  CHECK(r.network.branches.size() == 3);
  CHECK(e.parent == 0);
  CHECK(std::abs(e.time - tb) <= r.window_seconds);
  CHECK(e.angle_deg == Approx(2 * half_angle).margin(2.0));
  CHECK(std::hypot(e.x - xb, e.y - crack_y) <= 4 * dx);

  // Each child stays on its own ray: its tip never crosses the mid-line and
  // ends at the ray's far end (x = 18 mm, or y = 10 mm / 0 for the wide rays).
  for (int c : e.children) {
    const auto& tip = r.tips[c];
    const double side = tip.y.back() > crack_y ? 1.0 : -1.0;
    for (std::size_t k = 5; k < tip.y.size(); ++k) CHECK(side * (tip.y[k] - crack_y) >= -dx);
    CHECK((tip.x.back() > 17.5e-3 || tip.y.back() > 9.5e-3 || tip.y.back() < 0.5e-3));
    // Speed of a straight ray at v: mean within 2 %.
    CHECK(speed_stats(r.speeds, c).mean == Approx(v).epsilon(0.02));
  }
  CHECK((r.tips[e.children[0]].y.back() - crack_y) * (r.tips[e.children[1]].y.back() - crack_y) < 0);
}

TEST_CASE("manual branch boxes give one branch per box", "[branching]") {
  const auto dir = fresh_dir("branching_boxes");
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx), [](double x, double y) { return branching_arrival(x, y); },
                       40e-6);
  // Upper and lower ray boxes beyond x = 9 mm (past the junction).
  const std::string boxes = dir + "/boxes.csv";
  {
    std::ofstream f(boxes);
    f << "x_min_m,x_max_m,y_min_m,y_max_m\n9e-3,20e-3,5.2e-3,10e-3\n9e-3,20e-3,0,4.9e-3\n";
  }
  PostOptions o;
  o.outdir = dir;
  o.boxes_file = boxes;
  const PostResult r = analyse(o);
  REQUIRE(r.network.branches.size() == 2);
  CHECK(r.tips[0].y.back() > crack_y);
  CHECK(r.tips[1].y.back() < crack_y);
  for (int b = 0; b < 2; ++b) CHECK(speed_stats(r.speeds, b).mean == Approx(v).epsilon(0.03));
}
