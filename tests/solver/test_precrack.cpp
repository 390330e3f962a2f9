// Pre-crack rule (precrack.hpp): a bond is cut when its particles lie on
// different sides of the crack line and it meets the line on the open
// segment (from, to) (an end point only where several cracks end, see
// included_ends); a particle on the line counts as lying on the left of
// from -> to.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "error.hpp"
#include "lattice.hpp"
#include "precrack.hpp"
#include "bond_setup.hpp"
#include "simulation.hpp"
#include "test_support.hpp"

using namespace pd::solver;
using pd::Vec2;

TEST_CASE("bonds crossing a crack segment are cut, others are not", "[precrack]") {
  const PrecrackSpec crack{{0.0, 1.0}, {2.0, 1.0}};  // runs in +x along y = 1: "left" is above
  // Strictly crossing.
  CHECK(bond_crosses_crack({1.0, 0.5}, {1.2, 1.5}, crack));
  CHECK(bond_crosses_crack({1.2, 1.5}, {1.0, 0.5}, crack));
  // Both on one side, or parallel above.
  CHECK_FALSE(bond_crosses_crack({1.0, 0.5}, {1.5, 0.9}, crack));
  CHECK_FALSE(bond_crosses_crack({1.0, 1.5}, {1.5, 1.1}, crack));
  // Beyond the crack tip.
  CHECK_FALSE(bond_crosses_crack({2.1, 0.5}, {2.1, 1.5}, crack));
  CHECK_FALSE(bond_crosses_crack({-0.1, 0.5}, {-0.2, 1.5}, crack));
  // An end point lying exactly on the bond does not cut it (open segment)...
  CHECK_FALSE(bond_crosses_crack({2.0, 0.5}, {2.0, 1.5}, crack));
  CHECK_FALSE(bond_crosses_crack({1.5, 0.5}, {2.5, 1.5}, crack));
  CHECK(bond_crosses_crack({1.5, 0.5}, {2.5 - 1e-3, 1.5}, crack));
  CHECK_FALSE(bond_crosses_crack({0.0, 0.5}, {0.0, 1.5}, crack));
  CHECK_FALSE(bond_crosses_crack({-0.5, 0.5}, {0.5, 1.5}, crack));
  CHECK(bond_crosses_crack({-0.5 + 1e-3, 0.5}, {0.5 + 1e-3, 1.5}, crack));
  // ... unless the crack includes it.
  CHECK(bond_crosses_crack({0.0, 0.5}, {0.0, 1.5}, crack, {true, false}));
  CHECK(bond_crosses_crack({2.0, 0.5}, {2.0, 1.5}, crack, {false, true}));
  // A particle on the line counts as above: its bonds downwards are cut, upwards and along the line are not.
  CHECK(bond_crosses_crack({1.0, 1.0}, {1.0, 0.8}, crack));
  CHECK(bond_crosses_crack({1.0, 0.8}, {1.0, 1.0}, crack));
  CHECK_FALSE(bond_crosses_crack({1.0, 1.0}, {1.0, 1.2}, crack));
  CHECK_FALSE(bond_crosses_crack({1.0, 1.0}, {1.5, 1.0}, crack));
  // Reversing the crack direction moves on-line particles to the other side.
  const PrecrackSpec reversed{{2.0, 1.0}, {0.0, 1.0}};
  CHECK_FALSE(bond_crosses_crack({1.0, 1.0}, {1.0, 0.8}, reversed));
  CHECK(bond_crosses_crack({1.0, 1.0}, {1.0, 1.2}, reversed));
}

TEST_CASE("a pre-crack through a row of particles cuts both directions of each bond", "[precrack]") {
  // 11 rows: the middle row's centres lie exactly on y = 5.5 dx.
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(20 * dx, 11 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.effects.damage = true;
  scene.precracks = {{{0.0, 5.5 * dx}, {8 * dx, 5.5 * dx}}};
  Simulation sim(scene, p);
  // The run's bonds as a table: the cut ones have state 0.
  const auto run_bonds = build_bond_setup(scene, p, compact_families(p), {});
  std::vector<std::uint8_t> intact;
  const auto model = Pmb::constants(scene.material, run_bonds.horizon);
  const auto bonds = bond_table(p, run_bonds, bond_constants_of<Pmb>(p, run_bonds, model), model.critical_stretch, true, &intact);
  const auto cut = static_cast<std::size_t>(std::count(intact.begin(), intact.end(), 0));
  CHECK(cut == sim.precrack_bonds_cut());
  CHECK(cut == run_bonds.precrack_cut);
  CHECK(cut > 0);
  CHECK(cut % 2 == 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      const auto j = bonds.neighbor[b];
      for (auto r = bonds.offsets[j]; r < bonds.offsets[j + 1]; ++r)
        if (bonds.neighbor[r] == i) CHECK(intact[b] == intact[r]);
      // No bond between two particles at or above the line is cut, nor one right of the tip.
      if (p.y[i] >= 5.5 * dx - 1e-12 && p.y[j] >= 5.5 * dx - 1e-12) CHECK(intact[b] == 1);
      if (p.x[i] > 8 * dx && p.x[j] > 8 * dx) CHECK(intact[b] == 1);
    }
  // The cut bonds count as broken: particles along the crack are damaged, far ones are not.
  const auto d = sim.damage();
  double on_line = 0, far = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (std::fabs(p.y[i] - 5.5 * dx) < 1e-12 && p.x[i] < 6 * dx) on_line = std::max(on_line, d[i]);
    if (p.x[i] > 12 * dx) far = std::max(far, d[i]);
  }
  CHECK(on_line > 0.2);
  CHECK(far == 0);
  CHECK(sim.broken_bond_count() == cut);
}

namespace {

// Exact reference for the rule of precrack.hpp, in integers: coordinates in
// units of half a spacing, so that particle centres ((i + 1/2) dx), lattice
// vertices, cell centres and the midpoints of cell edges are whole numbers.
struct Half {
  std::int64_t x, y;
};

// Whether the bond p-q meets the crack's line on (from, to) (with an end
// point when it is included; both: the former closed rule), particles on the
// line counting as left of from -> to.
bool exact_cut(Half p, Half q, Half from, Half to, bool from_included = false, bool to_included = false) {
  const Half d{to.x - from.x, to.y - from.y};
  const auto side = [&](Half r) { return d.x * (r.y - from.y) - d.y * (r.x - from.x); };   // > 0: left
  const auto along = [&](Half r) { return d.x * (r.x - from.x) + d.y * (r.y - from.y); };  // |d| x distance from `from`
  const std::int64_t hp = side(p), hq = side(q), length2 = d.x * d.x + d.y * d.y;
  if ((hp >= 0) == (hq >= 0)) return false;
  // Where the bond meets the line, in units of the crack length: numerator / denominator.
  std::int64_t numerator = 0, denominator = 0;
  if (hp == 0) {
    numerator = along(p), denominator = length2;
  } else if (hq == 0) {
    numerator = along(q), denominator = length2;
  } else {
    numerator = along(p) * (hp - hq) + hp * (along(q) - along(p));
    denominator = length2 * (hp - hq);
  }
  if (denominator < 0) numerator = -numerator, denominator = -denominator;
  return (from_included ? numerator >= 0 : numerator > 0) &&
         (to_included ? numerator <= denominator : numerator < denominator);
}

struct CutCount {
  std::size_t run = 0;            // directed bonds the run's set-up cuts
  std::size_t exact = 0;          // the exact rule over the same bonds
  std::size_t exact_closed = 0;   // the exact rule with both ends included (the former closed rule)
  std::size_t disagreements = 0;  // bonds where bond_crosses_crack and the exact rule differ
};

PrecrackSpec crack_in_metres(Half from, Half to, double dx) {
  return {{0.5 * dx * from.x, 0.5 * dx * from.y}, {0.5 * dx * to.x, 0.5 * dx * to.y}};
}

std::size_t cut_by_run(const pd::ParticleSet& p, const PrecrackSpec& crack) {
  auto scene = test::basic_scene();
  scene.precracks = {crack};
  return build_bond_setup(scene, p, compact_families(p), {}).precrack_cut;
}

CutCount count_cuts(const pd::ParticleSet& p, double dx, Half from, Half to) {
  const auto half = [&](double v) { return static_cast<std::int64_t>(std::llround(2 * v / dx)); };
  const PrecrackSpec crack = crack_in_metres(from, to, dx);
  CutCount c;
  c.run = cut_by_run(p, crack);
  for (std::size_t i = 0; i < p.size(); ++i) {
    // A lattice: the centres lie on the half grid.
    if (std::fabs(0.5 * dx * half(p.x[i]) - p.x[i]) > 1e-9 * dx || std::fabs(0.5 * dx * half(p.y[i]) - p.y[i]) > 1e-9 * dx)
      FAIL("particle " << i << " is not on the half grid");
    for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b) {
      const auto j = p.neighbors[b];
      const Half pi{half(p.x[i]), half(p.y[i])}, pj{half(p.x[j]), half(p.y[j])};
      const bool exact = exact_cut(pi, pj, from, to);
      c.exact += exact;
      c.exact_closed += exact_cut(pi, pj, from, to, true, true);
      c.disagreements += exact != bond_crosses_crack({p.x[i], p.y[i]}, {p.x[j], p.y[j]}, crack);
    }
  }
  return c;
}

// The run's count with the tip moved along the crack by `shift` [m].
std::size_t cut_with_tip_moved(const pd::ParticleSet& p, double dx, Half from, Half to, double shift) {
  PrecrackSpec crack = crack_in_metres(from, to, dx);
  const Vec2 along = crack.to - crack.from;
  crack.to = crack.to + (shift / std::sqrt(dot(along, along))) * along;
  return cut_by_run(p, crack);
}

}  // namespace

// Reference: an independent count by brute force over every bond of the
// lattice with exact integer geometry (above), for tips at lattice vertices,
// cell centres and edge midpoints, on cracks between particle rows, along a
// row, slanted (through particle centres and not), starting outside the plate
// and lying inside it. The count must not change when the tip moves by
// +-1e-9 dx: the length of the crack does not depend on round-off.
TEST_CASE("a pre-crack cuts the bonds meeting it before its tip, wherever the tip falls on the grid", "[precrack]") {
  const double dx = 1e-3;
  const auto p = pd::make_rectangle_lattice(20 * dx, 12 * dx, dx, 3.015 * dx, pd::Quadrature::analytic);
  struct Case {
    const char* what;
    Half from, to;  // half spacings
  };
  const Case cases[] = {
      {"between rows, tip at a lattice vertex", {0, 12}, {10, 12}},
      {"between rows, tip at an edge midpoint", {0, 12}, {11, 12}},
      {"along a row of particles, tip at a cell centre", {0, 13}, {11, 13}},
      {"along a row of particles, tip at an edge midpoint", {0, 13}, {10, 13}},
      {"slanted through particle centres, tip at a cell centre", {0, 4}, {13, 17}},
      {"slanted, tip at a lattice vertex", {0, 6}, {12, 14}},
      {"starting outside the plate, tip at a lattice vertex", {-6, 12}, {10, 12}},
      {"inside the plate, from a vertex to a vertex", {10, 12}, {22, 12}},
      {"reversed: from the inside to the left edge", {10, 13}, {0, 13}},
  };
  for (const auto& c : cases) {
    INFO(c.what);
    const auto count = count_cuts(p, dx, c.from, c.to);
    INFO("run " << count.run << ", exact " << count.exact << ", tip included " << count.exact_closed);
    CHECK(count.exact > 0);
    CHECK(count.disagreements == 0);
    CHECK(count.run == count.exact);
    CHECK(count.run % 2 == 0);  // both directions of every pair
    CHECK(cut_with_tip_moved(p, dx, c.from, c.to, 1e-9 * dx) == count.run);
    CHECK(cut_with_tip_moved(p, dx, c.from, c.to, -1e-9 * dx) == count.run);
  }
  // A crack starting outside the plate cuts what the same crack from the edge cuts.
  CHECK(count_cuts(p, dx, {-6, 12}, {10, 12}).run == count_cuts(p, dx, {0, 12}, {10, 12}).run);
  // With the tip on a round number, the former closed rule cut one more row of bonds.
  const auto on_vertex = count_cuts(p, dx, {0, 12}, {10, 12});
  CHECK(on_vertex.exact_closed > on_vertex.exact);
}

// An edge crack of a = 5 mm at mid-height of a 50 mm x 200 mm strip at
// dx = 1 mm, m = 3.015. The tip falls on cell edges; a closed segment also
// cuts the bonds through it (316 directed bonds, the mouth opening under
// 10 MPa 9.5 % above Tada's), the open segment cuts what the crack 1 um
// shorter cuts (296; 3.1 % above Tada's).
TEST_CASE("an edge crack with its tip on cell edges cuts as many bonds as the same crack 1 um shorter", "[precrack]") {
  const double dx = 1e-3;
  const auto strip = pd::make_rectangle_lattice(0.05, 0.2, dx, 3.015 * dx, pd::Quadrature::analytic);
  const Half mouth{0, 200}, tip{10, 200};  // (0, 100 mm) -> (5 mm, 100 mm)
  const auto count = count_cuts(strip, dx, mouth, tip);
  CHECK(count.disagreements == 0);
  CHECK(count.run == count.exact);
  CHECK(count.run == cut_with_tip_moved(strip, dx, mouth, tip, -1e-6));
  CHECK(count.run == 296);
  CHECK(count.exact_closed == 316);
}

namespace {
// A 2 mm x 1 mm plate at dx = 0.1 mm (m = 3), set up for a run with `cracks`.
Simulation small_plate_with(const std::vector<PrecrackSpec>& cracks) {
  const double dx = 1e-4;
  static const auto plate = pd::make_rectangle_lattice(20 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.precracks = cracks;
  return Simulation(scene, plate);
}
}  // namespace

TEST_CASE("a pre-crack that cuts no bond is an error naming it and the plate", "[precrack]") {
  const double dx = 1e-4;
  const auto error_of = [&](const std::vector<PrecrackSpec>& cracks) {
    try {
      small_plate_with(cracks);
    } catch (const pd::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const PrecrackSpec good{{0, 5 * dx}, {5 * dx, 5 * dx}};
  CHECK(error_of({good}) == "no error");
  // Outside the 2 mm x 1 mm plate, but nearer to it than its size.
  const auto outside = error_of({good, {{0, 1.5e-3}, {1e-3, 1.5e-3}}});
  CHECK_THAT(outside, Catch::Contains("test-scene.toml: precracks[1] from [0, 0.0015] to [0.001, 0.0015] m cuts no bond") &&
                        Catch::Contains("x in [0, 0.002], y in [0, 0.001] m") && Catch::Contains("metres"));
  // Written in mm: an end farther beyond the plate than the plate's size is
  // refused as a unit slip, whether or not the crack cuts bonds.
  const auto in_mm = error_of({good, {{0, 0.5}, {0.5, 0.5}}});
  CHECK_THAT(in_mm, Catch::StartsWith("test-scene.toml: key 'precracks[1].from' = [0, 0.5]: this end lies 0.499 m "
                                      "beyond the plate (x in [0, 0.002], y in [0, 0.001] m)") &&
                        Catch::Contains("is it in mm?"));
  // One end in mm, one in m: the crack cuts the plate from edge to edge.
  CHECK_THAT(error_of({{{0, 5 * dx}, {0.75, 5 * dx}}}),
             Catch::Contains("key 'precracks[0].to' = [0.75, 0.0005]: this end lies 0.748 m beyond the plate"));
  // Below the plate.
  CHECK_THAT(error_of({{{0, -dx}, {20 * dx, -dx}}}), Catch::Contains("precracks[0]") && Catch::Contains("cuts no bond"));
  // Too short to reach a bond: it ends before the first crossing.
  CHECK_THAT(error_of({{{-dx, 5 * dx}, {0, 5 * dx}}}), Catch::Contains("precracks[0]"));
  // Along the bottom row of centres (y = dx / 2), drawn left to right: the row
  // counts as lying on its left (above), and nothing lies below. Inside the
  // plate's box, so the message says so instead of "outside the plate".
  CHECK_THAT(error_of({{{0, 0.5 * dx}, {10 * dx, 0.5 * dx}}}),
             Catch::Contains("inside the plate's box") && Catch::Contains("along the outermost row of particle centres"));
  CHECK(error_of({{{10 * dx, 0.5 * dx}, {0, 0.5 * dx}}}) == "no error");  // drawn right to left: the row lies below it
  // On the plate's edge: a crack 1e-11 m long is named as too short, with
  // ends that print apart; one along the bottom edge as along an edge (before
  // 7 December 2026 both were said to lie outside the plate, the first with
  // two ends printed alike, [0, 0.0005] to [0, 0.0005]).
  CHECK(error_of({{{0, 5 * dx}, {0, 5 * dx + 1e-11}}}) ==
        "test-scene.toml: precracks[0] from [0, 0.0005] to [0, 0.00050000001] m cuts no bond: it is 1e-11 m long, "
        "shorter than half the spacing (0.0001 m): a crack must cross the line between two particles to cut their "
        "bond");
  CHECK_THAT(error_of({{{0, 0}, {10 * dx, 0}}}),
             Catch::Contains("cuts no bond: it runs along an edge of the plate (x in [0, 0.002], y in [0, 0.001] m)"));
}

// Reference: the plate's topology. A crack drawn across the whole plate
// leaves two halves that no bond joins (the rows above and below it); one
// that ends inside leaves one piece; two cracks from either edge that overlap
// by more than a horizon cut the plate apart too. An end inside the plate
// leaves one piece however close to the far edge (the ligament is held by its
// bonds). The count does not depend on which kernel runs the bonds.
TEST_CASE("the set-up counts the pieces the pre-cracks cut the plate into", "[precrack]") {
  const double dx = 1e-4;
  const auto pieces_of = [](const std::vector<PrecrackSpec>& cracks) {
    return small_plate_with(cracks).setup_facts().pieces;
  };
  const auto across = pieces_of({{{-dx, 5 * dx}, {21 * dx, 5 * dx}}});
  CHECK(across.count == 2);
  CHECK(across.largest == std::vector<std::size_t>{100, 100});
  CHECK(pieces_of({{{-dx, 5 * dx}, {19.5 * dx, 5 * dx}}}).count == 1);  // half a spacing of ligament left
  CHECK(pieces_of({{{-dx, 5 * dx}, {12 * dx, 5 * dx}}, {{21 * dx, 5 * dx}, {8 * dx, 5 * dx}}}).count == 2);
  // Along a column: 7 columns left of x = 7 dx, 13 right of it.
  const auto column = pieces_of({{{7 * dx, -dx}, {7 * dx, 11 * dx}}});
  CHECK(column.count == 2);
  CHECK(column.largest == std::vector<std::size_t>{130, 70});
  // Without pre-cracks the plate is one piece (counted too: a grid may
  // leave a neck without a particle, tests/robustness/test_plate_pieces.cpp).
  CHECK(pieces_of({}).count == 1);
}

// Reference: symmetry. A crack between two particle rows of a lattice, from
// one lattice vertex to another, inside the plate and centred on it: the
// plate and the crack are mirror images of themselves about the crack's
// perpendicular bisector, so the cut bonds must be too; drawn the other way,
// or as two halves from its centre (the first of them includes the shared
// centre), it is the same crack and cuts the same bonds (counted in exact
// integer geometry as above).
TEST_CASE("an interior crack cuts a mirror-symmetric set of bonds, drawn either way or as two halves",
          "[precrack]") {
  const double dx = 1e-3;
  const auto p = pd::make_rectangle_lattice(20 * dx, 12 * dx, dx, 3.015 * dx, pd::Quadrature::analytic);
  const Half left{10, 12}, centre{20, 12}, right{30, 12};  // (5, 6) mm to (15, 6) mm, between rows
  const auto whole = count_cuts(p, dx, left, right);
  CHECK(whole.disagreements == 0);
  CHECK(whole.run == whole.exact);
  CHECK(count_cuts(p, dx, right, left).run == whole.run);
  // Mirror symmetry of the cut set about x = 10 mm.
  const PrecrackSpec crack = crack_in_metres(left, right, dx);
  std::size_t cut = 0, mirrored = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b) {
      const auto j = p.neighbors[b];
      if (!bond_crosses_crack({p.x[i], p.y[i]}, {p.x[j], p.y[j]}, crack)) continue;
      ++cut;
      mirrored += bond_crosses_crack({20 * dx - p.x[i], p.y[i]}, {20 * dx - p.x[j], p.y[j]}, crack);
    }
  CHECK(cut == whole.run);
  CHECK(mirrored == cut);
  // As two halves from the centre: the same bonds, the centre's once.
  auto scene = test::basic_scene();
  scene.precracks = {crack_in_metres(centre, left, dx), crack_in_metres(centre, right, dx)};
  const auto ends = included_ends(scene.precracks);
  CHECK((ends[0].from && !ends[0].to && !ends[1].from && !ends[1].to));
  CHECK(build_bond_setup(scene, p, compact_families(p), {}).precrack_cut == whole.run);
  // The former half-open rule [from, to) cut one end's row more than the other's.
  std::size_t half_open = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b) {
      const auto j = p.neighbors[b];
      const auto half = [&](double v) { return static_cast<std::int64_t>(std::llround(2 * v / dx)); };
      half_open += exact_cut({half(p.x[i]), half(p.y[i])}, {half(p.x[j]), half(p.y[j])}, left, right, true, false);
    }
  CHECK(half_open > whole.run);
}
