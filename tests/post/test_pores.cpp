// A crack that stops at a pore and restarts on its far side after a known
// trapping time; pore detection from the particle layout.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>

#include "crack_branches.hpp"
#include "pores.hpp"
#include "post_pipeline.hpp"
#include "synthetic_output.hpp"
#include "tip_tracking.hpp"

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

// The 20 x 10 mm plate with the pore, cracked as `arrival` says, analysed.
PostResult analyse_plate_with_pore(const std::string& name, const std::function<double(double, double)>& arrival,
                                   bool pore_file = false) {
  const auto dir = fresh_dir(name);
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx, {{xp, crack_y, R}}), arrival, 40e-6);
  PostOptions o;
  o.outdir = dir;
  if (pore_file) {
    o.pores_file = dir + "/pores.csv";
    std::ofstream(o.pores_file) << "x_m,y_m,r_m\n" << xp << "," << crack_y << "," << R << "\n";
  }
  return analyse(o);
}

PostResult run_trapped(const std::string& name, bool pore_file) {
  return analyse_plate_with_pore(name, trapped_arrival, pore_file);
}

// Pore of radius 1 mm at the origin with a ring of 0.1 mm, and cracked
// particles placed by hand (cells of 0.05 mm) for find_pore_visits.
const Pore hand_pore = circle_pore(0.0, 0.0, 1e-3);
constexpr double hand_ring = 0.1e-3;
struct HandMadeArrivals {
  ArrivalData data;
  std::uint32_t add(double x, double y, double t) {
    data.x.push_back(x), data.y.push_back(y), data.arrival.push_back(t), data.cell_size.push_back(0.05e-3);
    return static_cast<std::uint32_t>(data.x.size() - 1);
  }
};

// The crack of the fork tests (cells placed by hand): branch 0 runs from
// x = -3 mm to -1.2 mm (outside the ring) until 2 us and ends by branching;
// its child, branch 1, is born in the ring at (-1.05, 0) mm at 2 us and
// waits there to 10 us. `branches` and `tips` hold at least two entries.
void approach_and_fork(HandMadeArrivals& arrivals, std::vector<CrackBranch>& branches, std::vector<TipPath>& tips) {
  for (std::size_t b = 0; b < branches.size(); ++b) branches[b].id = static_cast<int>(b);
  branches[1].parent = 0;
  branches[0].children = {1};
  branches[0].ended_by_branching = true;
  for (int k = 0; k <= 10; ++k) {  // branch 0
    const double t = 0.2e-6 * k, x = -3e-3 + 0.18e-3 * k;
    branches[0].particles.push_back(arrivals.add(x, 0.0, t));
    tips[0].time.push_back(t), tips[0].x.push_back(x), tips[0].y.push_back(0);
  }
  for (int k = 0; k <= 16; ++k) {  // branch 1
    const double t = 2e-6 + 0.5e-6 * k;
    if (k < 3) branches[1].particles.push_back(arrivals.add(-1.05e-3, 0.01e-3 * k, t));
    tips[1].time.push_back(t), tips[1].x.push_back(-1.05e-3), tips[1].y.push_back(0);
  }
}

// A crack of its own on the pore's far side: x from 1.05 mm on, from 5 us on.
void far_side_crack(HandMadeArrivals& arrivals, CrackBranch& branch, TipPath& tip) {
  for (int k = 0; k <= 10; ++k) {
    const double t = 5e-6 + 0.2e-6 * k, x = 1.05e-3 + 0.2e-3 * k;
    branch.particles.push_back(arrivals.add(x, 0.0, t));
    tip.time.push_back(t), tip.x.push_back(x), tip.y.push_back(0);
  }
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

// An elliptical hole (semi-axes 3 and 1 mm): its circle of equal area
// (radius sqrt(3 x 1) = 1.73 mm) would miss a crack at its ends, 3 mm from
// its centre, so it is measured by its own outline: a point at its end is
// within the ring, one 0.3 mm beyond the circle's ring across its narrow
// side is not. A round hole of 1 mm keeps its circle.
TEST_CASE("a hole far from round is measured by its outline, a round one by its circle", "[pores]") {
  const auto plate_without = [](const std::function<bool(double, double)>& hole) {
    ArrivalData d;
    for (int j = 0; j < 100; ++j)
      for (int i = 0; i < 200; ++i) {
        const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
        if (hole(x, y)) continue;
        d.x.push_back(x), d.y.push_back(y), d.cell_size.push_back(dx);
      }
    return d;
  };
  const double ring = 1.5 * dx;
  const auto ellipse = plate_without([](double x, double y) {
    return std::pow((x - 10e-3) / 3e-3, 2) + std::pow((y - 5e-3) / 1e-3, 2) < 1;
  });
  const auto pores = detect_pores(ellipse);
  REQUIRE(pores.size() == 1);
  INFO("radius " << pores[0].radius << " m, reach " << pores[0].reach << " m");
  CHECK(pores[0].radius == Approx(std::sqrt(3.0) * 1e-3).epsilon(0.03));
  CHECK(pores[0].reach == Approx(3e-3).margin(dx));
  REQUIRE(pores[0].has_outline());
  // Distances to the ellipse's edge (exact: 0.1 mm beyond the end of its
  // long axis, 0.5 mm above its top), to within the raster's half cell.
  CHECK(pores[0].edge_distance(13.1e-3, 5e-3) == Approx(0.1e-3).margin(0.5 * dx));
  CHECK(pores[0].edge_distance(10e-3, 6.5e-3) == Approx(0.5e-3).margin(0.5 * dx));
  CHECK(pores[0].edge_distance(10e-3, 5e-3) < 0);
  CHECK(pores[0].within(13.1e-3, 5e-3, ring));
  CHECK_FALSE(pores[0].within(10e-3, 5e-3 + 1.73e-3 + ring + 0.3e-3, ring));
  CHECK(pores[0].enclosing_radius() == Approx(3e-3).margin(dx));

  const auto round = plate_without([](double x, double y) { return std::hypot(x - xp, y - crack_y) < R; });
  const auto round_pores = detect_pores(round);
  REQUIRE(round_pores.size() == 1);
  CHECK(round_pores[0].reach == Approx(R).margin(dx));
  CHECK_FALSE(round_pores[0].has_outline());
  CHECK(round_pores[0].edge_distance(xp + 2 * R, crack_y) == Approx(R).margin(dx));
  // A round hole with a thin spur, a gap one particle wide reaching 0.6 mm
  // beyond its edge (as gaps between free cells next to an NB-NUG hole do):
  // still round once the opening has removed the spur (by its farthest raw
  // cell it was taken for a hole far from round, on the main job's C3-A
  // plate too).
  const auto spur = plate_without([](double x, double y) {
    return std::hypot(x - xp, y - crack_y) < R || (std::abs(y - crack_y) < 0.5 * dx && x > xp && x < xp + R + 0.6e-3);
  });
  const auto spur_pores = detect_pores(spur);
  REQUIRE(spur_pores.size() == 1);
  CHECK(spur_pores[0].reach == Approx(R).margin(dx));
  CHECK_FALSE(spur_pores[0].has_outline());
}

// A crack along y = crack_y that stops at x = near (a hole's near end),
// waits `trap` and restarts at x = far (its far end), on the 20 x 10 mm
// lattice less the particles `in_hole` marks, analysed.
PostResult crack_through_hole(const std::string& name, const std::function<bool(double, double)>& in_hole,
                              double near, double far) {
  const double enter = (near - a0) / v;
  const auto arrival = [&](double x, double y) {
    if (std::abs(y - crack_y) > 1.01 * dx || x > 18e-3) return -1.0;
    if (x <= a0) return 0.0;
    if (x < near + 0.5 * (far - near)) return (x - a0) / v;
    return enter + trap + (x - far) / v;
  };
  const auto dir = fresh_dir(name);
  const Lattice plate = make_lattice(20e-3, 10e-3, dx);
  Lattice holed = plate;
  holed.x.clear(), holed.y.clear();
  for (std::size_t i = 0; i < plate.x.size(); ++i)
    if (!in_hole(plate.x[i], plate.y[i])) holed.x.push_back(plate.x[i]), holed.y.push_back(plate.y[i]);
  write_arrival_output(dir, holed, arrival, 40e-6);
  PostOptions o;
  o.outdir = dir;
  return analyse(o);
}

// A crack along the long axis of a slot-like hole (an ellipse of semi-axes
// 3 and 0.6 mm) stops at its near end and restarts at its far end after
// `trap`; and a crack that meets a round pore (radius 1.5 mm) at the tip of
// a lobe (a disk of 0.5 mm whose centre lies 1.9 mm from the pore's, so the
// lobe reaches 2.4 mm from it), as traced pores have. Measured as their
// circles of equal area (radius 1.34 and 1.55 mm), the near ends lay 1.5 and
// 0.7 mm outside the circles' rings: no visit was seen and the restart was a
// crack of its own (before the fourth sitting of 5 December 2026; the slot
// with a warning, the lobed pore, round by its second moments of area,
// without a word). By their outlines the crack visits each once and the
// trapping time is recovered within a window, as for a round pore.
TEST_CASE("a crack through a hole far from round visits it at its ends", "[pores]") {
  const double slot_a = 3e-3, slot_b = 0.6e-3;
  const auto slot = [&](double x, double y) {
    return std::pow((x - xp) / slot_a, 2) + std::pow((y - crack_y) / slot_b, 2) < 1;
  };
  const double lobe_r = 0.5e-3, body_r = 1.5e-3, lobe_x = xp - 1.9e-3;
  const auto lobed = [&](double x, double y) {
    return std::hypot(x - xp, y - crack_y) < body_r || std::hypot(x - lobe_x, y - crack_y) < lobe_r;
  };
  struct Case {
    const char* name;
    std::function<bool(double, double)> in_hole;
    double near, far;
  };
  for (const Case& c : {Case{"slot_pore", slot, xp - slot_a, xp + slot_a},
                        Case{"lobed_pore", lobed, lobe_x - lobe_r, xp + body_r}}) {
    INFO(c.name);
    const PostResult r = crack_through_hole(c.name, c.in_hole, c.near, c.far);
    REQUIRE(r.pores.size() == 1);
    CHECK(r.pores[0].has_outline());
    for (const auto& w : r.warnings) CHECK_THAT(w, !Catch::Contains("pore"));
    CHECK(r.network.branches.size() == 1);
    REQUIRE(r.pore_visits.size() == 1);
    const auto& visit = r.pore_visits[0];
    CHECK(visit.branch == 0);
    CHECK(visit.jumped);
    CHECK(std::abs(visit.enter_time - (c.near - a0) / v) <= r.window_seconds);
    CHECK(std::abs(visit.trapping_time - trap) <= r.window_seconds);
  }
}

// A crack that meets the slot (semi-axes 3 and 0.6 mm) from below, 2 mm
// right of its centre, and restarts on its top side after `trap`: the
// restart lies on the entry's own half about the centre (the entry and the
// restart both 2 mm to the right), so the far-half rule of a round pore saw
// no restart beyond it, only the tip leaving the ring (before the fourth
// sitting of 5 December 2026, `jumped` false). Measured by its outline, the
// line from the entry to the restart crosses the slot: a restart beyond it.
TEST_CASE("a crack across a slot's short side restarts beyond it", "[pores]") {
  constexpr double a = 3e-3, b = 0.6e-3, x_crack = xp + 2e-3 + 0.05e-3, y0 = 1e-3;
  const double half_width = b * std::sqrt(1 - std::pow((x_crack - xp) / a, 2));
  const double bottom = crack_y - half_width, top = crack_y + half_width;
  const double enter = (bottom - y0) / v;
  const auto arrival = [&](double x, double y) {
    if (std::abs(x - x_crack) > 1.01 * dx || y > 9e-3) return -1.0;
    if (y <= y0) return 0.0;
    if (y < crack_y) return (y - y0) / v;
    return enter + trap + (y - top) / v;
  };
  const auto dir = fresh_dir("slot_short_side");
  const Lattice plate = make_lattice(20e-3, 10e-3, dx);
  Lattice holed = plate;
  holed.x.clear(), holed.y.clear();
  for (std::size_t i = 0; i < plate.x.size(); ++i)
    if (std::pow((plate.x[i] - xp) / a, 2) + std::pow((plate.y[i] - crack_y) / b, 2) >= 1)
      holed.x.push_back(plate.x[i]), holed.y.push_back(plate.y[i]);
  write_arrival_output(dir, holed, arrival, 40e-6);
  PostOptions o;
  o.outdir = dir;
  const PostResult r = analyse(o);
  REQUIRE(r.pores.size() == 1);
  REQUIRE(r.pores[0].has_outline());
  CHECK(r.network.branches.size() == 1);
  REQUIRE(r.pore_visits.size() == 1);
  const auto& visit = r.pore_visits[0];
  CHECK(visit.jumped);
  CHECK(std::abs(visit.enter_time - enter) <= r.window_seconds);
  CHECK(std::abs(visit.trapping_time - trap) <= r.window_seconds);
}

// A hole of four cells of a 0.1 mm lattice (a 2 x 2 block, rasterised to a
// radius of about 1.1 cells) is below the 1.25 cells pores need and above
// the 0.75 of a gap: not counted, with a note that names it (before the
// fourth sitting of 5 December 2026, without a word: a plate of 16 traced
// pores at 0.5 mm reported 13 pores). One hole is "a pore" at its place (at
// first 'is not counted as pores', '(first at ...)').
TEST_CASE("a hole too small to count as a pore gets a note", "[pores]") {
  const auto dir = fresh_dir("small_hole_note");
  // (Centres at 9.95 and 10.05 mm, 6.95 and 7.05 mm lie within 0.075 mm of (10, 7) mm.)
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, dx, {{xp, 7e-3, 0.075e-3}}), trapped_arrival, 40e-6);
  PostOptions o;
  o.outdir = dir;
  const PostResult r = analyse(o);
  CHECK(r.pores.empty());
  bool noted = false;
  for (const auto& n : r.notes)
    noted |= n.find("1 hole of radius 0.1") == 0 && n.find("mm at (10, 7) mm") != std::string::npos &&
             n.find(") mm is not counted as a pore: below 1.25 cell sizes in radius") != std::string::npos &&
             n.find("give --pores FILE to count it, or use a finer grid") != std::string::npos;
  CHECK(noted);
  // Six cells (a 2 x 3 block within 0.12 mm of (10, 7.05) mm), about 1.3
  // cells in radius, as C3's pores of 1.5 spacings rasterise at dx = 0.5 mm
  // (1.47 to 1.49): a pore (below the 1.5 of the fourth sitting of 5
  // December 2026, it was not).
  const auto dir6 = fresh_dir("six_cell_pore");
  write_arrival_output(dir6, make_lattice(20e-3, 10e-3, dx, {{xp, crack_y + 2e-3, 0.12e-3}}), trapped_arrival,
                       40e-6);
  o.outdir = dir6;
  const PostResult r6 = analyse(o);
  REQUIRE(r6.pores.size() == 1);
  CHECK(r6.pores[0].radius > 1.25 * dx);
  CHECK(r6.pores[0].radius < 1.5 * dx);
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

TEST_CASE("a crack that goes on as another branch beyond a pore ends the trapping", "[pores]") {
  // The rule of find_pore_visits on hand-made branches (reference: the
  // definition in post/pores.hpp, trapping = restart - enter [Peng, Chen,
  // Bobaru 2023, Sec. 5]). Pore of radius 1 mm at the origin, ring 0.1 mm.
  // Branch 0 comes from the left and its tip waits at the near edge from
  // t = 2 us to the end. Branch 1 starts within the ring on the far side at
  // 5 us (a fork or a crack nucleated there; the branch analysis decides
  // which, and either way it is another branch) and runs to the right.
  HandMadeArrivals arrivals;
  ArrivalData& data = arrivals.data;
  const auto add = [&](double x, double y, double t) { return arrivals.add(x, y, t); };
  std::vector<CrackBranch> branches(2);
  std::vector<TipPath> tips(2);
  branches[0].id = 0, branches[1].id = 1;
  for (int k = 0; k <= 10; ++k) {  // branch 0: x from -3 mm to -1.05 mm, at 0..2 us, then waits
    const double t = 0.2e-6 * k, x = -3e-3 + 0.195e-3 * k;
    branches[0].particles.push_back(add(x, 0.0, t));
  }
  for (int k = 0; k <= 20; ++k) {  // tip path of branch 0, every 0.5 us to 10 us
    const double t = 0.5e-6 * k;
    tips[0].time.push_back(t), tips[0].x.push_back(std::min(-3e-3 + 0.975e3 * t, -1.05e-3)), tips[0].y.push_back(0);
  }
  for (int k = 0; k <= 10; ++k) {  // branch 1: x from 1.05 mm, from 5 us on
    const double t = 5e-6 + 0.2e-6 * k, x = 1.05e-3 + 0.2e-3 * k;
    branches[1].particles.push_back(add(x, 0.0, t));
    tips[1].time.push_back(t), tips[1].x.push_back(x), tips[1].y.push_back(0);
  }
  const auto visits = find_pore_visits(branches, tips, {hand_pore}, data, hand_ring);
  REQUIRE(visits.size() == 1);  // branch 1 is born at the pore: it does not visit it
  CHECK(visits[0].branch == 0);
  CHECK(visits[0].enter_time == Approx(2e-6));   // tip reaches x = -1.05 mm, within the ring
  CHECK(visits[0].restart_time == Approx(5e-6)); // branch 1's first particle, on the far half
  CHECK(visits[0].trapping_time == Approx(3e-6));
  CHECK(visits[0].jumped);

  // Without branch 1 the tip never leaves the ring: never restarted.
  const auto alone = find_pore_visits({branches[0]}, {tips[0]}, {hand_pore}, data, hand_ring);
  REQUIRE(alone.size() == 1);
  CHECK(alone[0].restart_time == -1);
  CHECK(alone[0].trapping_time == -1);
}

TEST_CASE("a crack that forks at a pore's edge visits the pore although no tip entered from outside", "[pores]") {
  // The rule of find_pore_visits (post/pores.hpp) when the branch analysis
  // ends the arriving branch just before the ring and starts its children
  // inside it. Pore of radius 1 mm at the origin, ring 0.1 mm. Branch 0 runs
  // from x = -3 mm to -1.2 mm (outside the ring) until 2 us and ends by
  // branching; its child, branch 1, is born at (-1.05, 0) mm at 2 us and waits
  // there; branch 2 (a crack of its own) starts on the far side at 5 us.
  // Reference: enter at the fork's birth (2 us), restart at branch 2's first
  // particle (5 us), trapping 3 us.
  HandMadeArrivals arrivals;
  ArrivalData& data = arrivals.data;
  std::vector<CrackBranch> branches(3);
  std::vector<TipPath> tips(3);
  approach_and_fork(arrivals, branches, tips);
  far_side_crack(arrivals, branches[2], tips[2]);
  const auto visits = find_pore_visits(branches, tips, {hand_pore}, data, hand_ring);
  REQUIRE(visits.size() == 1);
  CHECK(visits[0].branch == 0);
  CHECK(visits[0].enter_time == Approx(2e-6));
  CHECK(visits[0].enter_x == Approx(-1.05e-3));
  CHECK(visits[0].restart_time == Approx(5e-6));
  CHECK(visits[0].trapping_time == Approx(3e-6));
  CHECK(visits[0].jumped);

  // Without branch 2 nothing restarts beyond the pore; a crack born in the
  // ring that forked off nothing (parent -1) is not a visit.
  const auto waiting = find_pore_visits({branches[0], branches[1]}, {tips[0], tips[1]}, {hand_pore}, data, hand_ring);
  REQUIRE(waiting.size() == 1);
  CHECK(waiting[0].trapping_time == -1);
  CrackBranch nucleated = branches[1];
  nucleated.parent = -1;
  CHECK(find_pore_visits({branches[0], nucleated}, {tips[0], tips[1]}, {hand_pore}, data, hand_ring).empty());
}

TEST_CASE("a tip that left a pore's ring before the crack entered it is no restart", "[pores]") {
  // The full C3-A run (dx = 0.04 mm) had a trapping time of -1.56 us: a crack
  // nucleated at the pore's edge ran out of the ring before the fork that
  // made the visit was born. Rule (post/pores.hpp): a restart is after the
  // entry. Pore of radius 1 mm at the origin, ring 0.1 mm. Branch 0 runs
  // from x = -3 mm to -1.2 mm (outside the ring) until 2 us and ends by
  // branching; its child, branch 1, is born in the ring at (-1.05, 0) mm at
  // 2 us and waits there. Branch 2, a crack of its own, is born in the ring
  // at (-0.75, 0.75) mm at 1 us and leaves the ring at 1.1 us, running away
  // from the pore (before the entry: ignored). Branch 3 starts on the far
  // side at 5 us. Reference: enter 2 us, restart 5 us, trapping 3 us.
  HandMadeArrivals arrivals;
  ArrivalData& data = arrivals.data;
  std::vector<CrackBranch> branches(4);
  std::vector<TipPath> tips(4);
  approach_and_fork(arrivals, branches, tips);
  const double out = std::sqrt(0.5);  // along the diagonal, away from the pore
  for (int k = 0; k <= 10; ++k) {  // branch 2: from 1.06 mm off the centre, 0.1 mm per 0.1 us, from 1 us
    const double t = 1e-6 + 0.1e-6 * k, r = 1.06e-3 + 0.1e-3 * k;
    branches[2].particles.push_back(arrivals.add(-out * r, out * r, t));
    tips[2].time.push_back(t), tips[2].x.push_back(-out * r), tips[2].y.push_back(out * r);
  }
  far_side_crack(arrivals, branches[3], tips[3]);
  // Branch 2's tip is in the ring at 1.0 us and out of it from 1.1 us on.
  REQUIRE(std::hypot(tips[2].x[0], tips[2].y[0]) <= hand_pore.radius + hand_ring);
  REQUIRE(std::hypot(tips[2].x[1], tips[2].y[1]) > hand_pore.radius + hand_ring);
  const auto visits = find_pore_visits(branches, tips, {hand_pore}, data, hand_ring);
  REQUIRE(visits.size() == 1);
  CHECK(visits[0].branch == 0);
  CHECK(visits[0].enter_time == Approx(2e-6));
  CHECK(visits[0].restart_time == Approx(5e-6));
  CHECK(visits[0].trapping_time == Approx(3e-6));
  CHECK(visits[0].jumped);

  // Without branch 3 nothing restarts after the entry: never restarted.
  const auto waiting = find_pore_visits({branches[0], branches[1], branches[2]}, {tips[0], tips[1], tips[2]},
                                        {hand_pore}, data, hand_ring);
  REQUIRE(waiting.size() == 1);
  CHECK(waiting[0].enter_time == Approx(2e-6));
  CHECK(waiting[0].restart_time == -1);
  CHECK(waiting[0].trapping_time == -1);
}

TEST_CASE("cracks nucleated on both sides of a pore stay two cracks of their own", "[pores]") {
  // The hole plate of docs/refinement.md: a short crack nucleates at the
  // hole's left edge and runs away from it to the left, and later another at
  // its right edge runs to the right; no crack ran into the hole. The right
  // one is no restart of the left one beyond the pore (a crack that started
  // at the pore never entered it): two branches of their own, no branching,
  // no pore visit. Pore as above (radius 1 mm at (10, 5.05) mm); left crack
  // from x = 9 mm at 2 us, 2 mm long; right crack from x = 11 mm at 6 us.
  const auto arrival = [](double x, double y) {
    if (std::abs(y - crack_y) > 1.01 * dx) return -1.0;
    if (x >= 7e-3 && x < xp - R) return 2e-6 + (xp - R - x) / v;
    if (x > xp + R && x <= 18e-3) return 6e-6 + (x - (xp + R)) / v;
    return -1.0;
  };
  const PostResult r = analyse_plate_with_pore("pore_two_nucleated", arrival);
  REQUIRE(r.pores.size() == 1);
  REQUIRE(r.network.branches.size() == 2);
  for (const auto& b : r.network.branches) {
    CHECK(b.parent == -1);
    CHECK(b.pore_restart_times.empty());
  }
  CHECK(r.network.branchings.empty());
  CHECK(r.pore_visits.empty());
  // Each branch holds one side's particles only.
  for (const auto& b : r.network.branches) {
    const bool left = r.data.x[b.particles.front()] < xp;
    for (auto k : b.particles) CHECK((r.data.x[k] < xp) == left);
  }
}

TEST_CASE("a tip first seen just outside a pore's ring that then steps into it was born there", "[pores]") {
  // A crack nucleated at a pore's edge is first seen where its damage first
  // reaches the threshold, which may lie just beyond the ring; its tip can
  // then step into the ring before it runs away. It never approached the
  // pore: no visit. Pore of radius 1 mm at the origin, ring 0.1 mm; the tip
  // at 1.12, 1.08 (inside), then 1.3 to 3.1 mm from the centre. A crack that
  // came from 0.5 mm beyond the ring (more than a ring away) does visit.
  for (const double from : {1.12e-3, 1.6e-3}) {
    HandMadeArrivals arrivals;
    std::vector<CrackBranch> branches(1);
    std::vector<TipPath> tips(1);
    std::vector<double> radii = {from, 1.08e-3};
    for (int k = 0; k < 10; ++k) radii.push_back(1.3e-3 + 0.2e-3 * k);
    for (std::size_t k = 0; k < radii.size(); ++k) {
      const double t = 1e-6 + 0.1e-6 * static_cast<double>(k);
      branches[0].particles.push_back(arrivals.add(radii[k], 0.0, t));
      tips[0].time.push_back(t), tips[0].x.push_back(radii[k]), tips[0].y.push_back(0);
    }
    const auto visits = find_pore_visits(branches, tips, {hand_pore}, arrivals.data, hand_ring);
    INFO("first seen " << from * 1e3 << " mm from the centre");
    CHECK(visits.size() == (from > hand_pore.radius + 2 * hand_ring ? 1u : 0u));
  }
}

TEST_CASE("a crack that forks beyond a pore keeps growing in its children, never in the parent that ended", "[pores]") {
  // C3-A at dx = 0.0625 mm: a crack restarted beyond a pore and forked at
  // its far edge; later damage appearing at that pore belongs to the crack
  // that ran in, through its children born there, not to the parent that
  // ended at the fork (whose tip is frozen: that crack's growth went
  // untracked). The pore above (radius 1 mm at (10, 5.05) mm): the crack
  // of run_trapped reaches it at t_in, restarts at x = 11 mm after `trap`
  // and forks there into two cracks at +-45 degrees; 5 us after the restart
  // a crack appears on the pore's top edge and runs upwards.
  const double restart = t_in + trap, late = restart + 5e-6;
  const auto arrival = [&](double x, double y) {
    const double dy = y - crack_y;
    if (x < xp - R) return std::abs(dy) <= 1.01 * dx ? (x <= a0 ? 0.0 : (x - a0) / v) : -1.0;
    if (x > xp + R && x <= 16e-3) {  // the fork's two children, from (11, 5.05) mm
      const double along = x - (xp + R);
      if (std::abs(std::abs(dy) - along) <= 1.01 * dx * std::sqrt(2.0)) return restart + std::sqrt(2.0) * along / v;
    }
    if (std::abs(x - xp) <= 1.01 * dx && y > crack_y + R && y <= 9e-3)  // the crack on the top edge
      return late + (y - (crack_y + R)) / v;
    return -1.0;
  };
  const PostResult r = analyse_plate_with_pore("pore_fork_then_top", arrival);
  REQUIRE_FALSE(r.network.branchings.empty());  // the fork beyond the pore
  const ArrivalData& d = r.data;
  bool top_tracked = false;
  for (const auto& b : r.network.branches) {
    for (auto k : b.particles) {
      // A branch that ended at a fork takes no later particle.
      if (b.ended_by_branching) CHECK(d.arrival[k] <= b.end_time + 1e-12);
      if (d.y[k] > crack_y + R + 0.5e-3 && std::abs(d.x[k] - xp) < 2 * dx) top_tracked |= !b.ended_by_branching;
    }
  }
  CHECK(top_tracked);  // the top crack's particles are in a branch that still grows
}

TEST_CASE("a crack that restarts beyond a pore as two cracks branches there, not at its pre-crack", "[pores]") {
  // C3-A with OSB at dx = 0.125 mm: the crack ran along the mid-line into a
  // pore and left its far side as two cracks, whose fronts no older particle
  // links (the pore lies between them and the crack that ran in). The split
  // was dated at the parent's oldest particle, the pre-crack's (t = 0), and
  // the crack that ran in ended there, without a tip path. Reference: the
  // arrival field below, the crack of run_trapped restarting after `trap`
  // as two parallel cracks from the pore's far edge at y = crack_y +- 0.6 mm
  // (x_far = xp + 0.8 mm): the branching is at the restart, where a child
  // begins, and the crack that ran in keeps its particles up to the pore.
  const double restart = t_in + trap, offset = 0.6e-3, x_far = xp + std::sqrt(R * R - offset * offset);
  const auto arrival = [&](double x, double y) {
    const double dy = y - crack_y;
    if (x < xp - R) return std::abs(dy) <= 1.01 * dx ? (x <= a0 ? 0.0 : (x - a0) / v) : -1.0;
    if (x >= x_far && x <= 16e-3 && std::abs(std::abs(dy) - offset) <= 0.51 * dx) return restart + (x - x_far) / v;
    return -1.0;
  };
  const PostResult r = analyse_plate_with_pore("pore_two_restarts", arrival);
  REQUIRE(r.network.branchings.size() == 1);
  const auto& fork = r.network.branchings[0];
  const double step = dx / v;  // the crack crosses a cell in one such time
  CHECK(fork.time == Approx(restart).margin(2 * step));
  CHECK(fork.x == Approx(x_far).margin(2 * dx));
  CHECK(std::abs(fork.y - crack_y) == Approx(offset).margin(2 * dx));
  const auto& in = r.network.branches[static_cast<std::size_t>(fork.parent)];
  CHECK(in.parent == -1);
  CHECK(in.end_time == Approx(restart).margin(2 * step));
  double reach = 0;  // the farthest particle of the crack that ran in
  for (auto k : in.particles) reach = std::max(reach, r.data.x[k]);
  CHECK(reach == Approx(xp - R).margin(2 * dx));
}
