// Refinement regions (docs/mesher.md, "Refinement regions"): a plate with a
// band of squares dx / f (f = 2, 4, 8), each particle with the horizon m x its
// own side. Reference: for a particle whose horizon disk lies inside the
// plate, the cells tile the disk, so the own cell plus the partial volumes of
// the family cover exactly pi delta_i^2 (theory.md Sec. 2.2), whatever the
// sizes of the cells the disk cuts: at the interface too.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "pd_mesh_run.hpp"

using namespace pd::test_support;

namespace {

// 24 x 16 mm; the right half, x in [12, 24] mm, is refined.
const std::string plate_24_16 =
    "Point(1) = {0, 0, 0}; Point(2) = {24, 0, 0}; Point(3) = {24, 16, 0}; Point(4) = {0, 16, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n";

// A disk of radius 10 mm about the origin: every boundary off the lattice lines.
const std::string disk_10 =
    "Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {-10, 0, 0};\n"
    "Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 2}; Curve Loop(1) = {1, 2}; Plane Surface(1) = {1};\n";

pd::ParticleSet refined_plate(int factor, const std::string& region = "12mm,0mm,24mm,16mm",
                              const std::string& extra = "") {
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("refined_" + std::to_string(factor) + ".pdp");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --grid uniform --refine-region " + region +
                               " --refine-factor " + std::to_string(factor) + " " + extra + " -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  return pd::read_particle_file(out);
}

}  // namespace

TEST_CASE("refinement: squares of dx/f in the region, horizons m x own side", "[refinement]") {
  for (int factor : {2, 4, 8}) {
    const auto p = refined_plate(factor);
    const double dx = 1e-3, fine = dx / factor;
    std::size_t coarse = 0, refined = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const bool in_region = p.x[i] > 12e-3;
      const double side = in_region ? fine : dx;
      CHECK(p.cell_size[i] == Approx(side).epsilon(1e-12));
      CHECK(p.volume[i] == Approx(side * side).epsilon(1e-12));
      CHECK(p.horizon[i] == Approx(3 * side).epsilon(1e-12));
      (in_region ? refined : coarse) += 1;
    }
    // 12 x 16 coarse cells on each side of x = 12 mm, the right ones split f x f.
    CHECK(coarse == 12u * 16u);
    CHECK(refined == 12u * 16u * factor * factor);
    CHECK(p.horizon_nominal == Approx(3e-3).epsilon(1e-12));
  }
  // A region reaching far beyond the plate (1e300 mm: before, its cell index
  // overflowed and the region was said not to meet the plate) is the same region.
  const auto far = refined_plate(2, "12mm,0mm,1e300mm,16mm");
  CHECK(far.size() == refined_plate(2).size());
}

TEST_CASE("refinement: sum of phi V over a horizon is pi delta_i^2 at every level, at the interface too",
          "[refinement]") {
  for (int factor : {2, 4, 8}) {
    const auto p = refined_plate(factor);
    double worst = 0;
    std::size_t checked_coarse = 0, checked_fine = 0, at_interface = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double delta = p.horizon[i];
      const bool interior = p.x[i] - delta >= 0 && p.x[i] + delta <= 24e-3 && p.y[i] - delta >= 0 &&
                            p.y[i] + delta <= 16e-3;
      if (!interior) continue;
      double area = p.volume[i];  // the own cell, which no family contains
      for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b)
        area += p.partial_volume[b] * p.volume[p.neighbors[b]];
      const double exact = M_PI * delta * delta;
      worst = std::max(worst, std::fabs(area - exact) / exact);
      (p.cell_size[i] < 1e-3 * (1 - 1e-9) ? checked_fine : checked_coarse) += 1;
      // The disk crosses x = 12 mm: it holds cells of both sizes.
      if (std::fabs(p.x[i] - 12e-3) < delta) ++at_interface;
    }
    INFO("factor " << factor << ": largest relative error " << worst);
    CHECK(checked_coarse > 0);
    CHECK(checked_fine > 0);
    CHECK(at_interface > 0);
    CHECK(worst < 1e-12);
  }
}

TEST_CASE("refinement: a family is the cells that meet the particle's own disk", "[refinement]") {
  // Reference: the definition (theory.md Sec. 2.1). A fine particle next to
  // the interface has a coarse neighbour only where a coarse cell meets its
  // small disk; a coarse particle sees the fine cells its large disk meets.
  const auto p = refined_plate(4);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double delta = p.horizon[i];
    for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b) {
      const auto j = p.neighbors[b];
      // Nearest point of j's square to x_i.
      const double h = 0.5 * p.cell_size[j];
      const double ex = std::max(0.0, std::fabs(p.x[j] - p.x[i]) - h);
      const double ey = std::max(0.0, std::fabs(p.y[j] - p.y[i]) - h);
      REQUIRE(std::hypot(ex, ey) < delta);
    }
  }
  // Family sizes far from the interface: the interior family of m = 3
  // (28 whole squares and 8 cut ones at each side), the same at both levels.
  std::size_t coarse_size = 0, fine_size = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto size = p.family_offsets[i + 1] - p.family_offsets[i];
    if (std::fabs(p.x[i] - 4.5e-3) < 1e-9 && std::fabs(p.y[i] - 8.5e-3) < 1e-9) coarse_size = size;
    if (std::fabs(p.x[i] - 18.125e-3) < 1e-9 && std::fabs(p.y[i] - 8.125e-3) < 1e-9) fine_size = size;
  }
  CHECK(coarse_size > 0);
  CHECK(coarse_size == fine_size);
}

TEST_CASE("horizon smoothing: the horizon ramps over L_s, partial volumes exact for each own horizon",
          "[refinement][smoothed_horizon]") {
  // References: the rule of theory.md Sec. 7.1 (Imachi et al. 2021, Sec. 4:
  // the horizon varies linearly over the smoothing length), evaluated here
  // from the region's edges; the exact neighbourhood area pi delta_i^2 of
  // theory.md Sec. 2.2 for every particle's own disk.
  struct Case {
    std::string region;
    double x0, y0, x1, y1;  // the region [m]; its edges on the plate's edges face no coarse cells
    std::size_t in_band;    // fine squares within L_s = 10 fine spacings of the edges that face coarse cells
  };
  // The right half: 10 columns of 64 fine squares. A 12 x 8 mm box inside:
  // 48 x 32 fine squares less the 28 x 12 beyond the band.
  for (const Case& c : {Case{"12mm,0mm,24mm,16mm", 12e-3, 0, 24e-3, 16e-3, 10 * 64},
                        Case{"6mm,4mm,18mm,12mm", 6e-3, 4e-3, 18e-3, 12e-3, 48 * 32 - 28 * 12}}) {
    const int factor = 4;
    const double smoothing = 2.5e-3, coarse_horizon = 3e-3, fine_horizon = 3e-3 / factor;
    const auto p = refined_plate(factor, c.region, "--horizon-smoothing 2.5mm");
    std::size_t smoothed = 0, checked_smoothed = 0;
    double worst_rule = 0, worst_area = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const bool in_region = p.x[i] > c.x0 && p.x[i] < c.x1 && p.y[i] > c.y0 && p.y[i] < c.y1;
      double expected = coarse_horizon;
      if (in_region) {
        double d = 1e9;
        if (c.x0 > 0) d = std::min(d, p.x[i] - c.x0);
        if (c.x1 < 24e-3) d = std::min(d, c.x1 - p.x[i]);
        if (c.y0 > 0) d = std::min(d, p.y[i] - c.y0);
        if (c.y1 < 16e-3) d = std::min(d, c.y1 - p.y[i]);
        expected = fine_horizon + (coarse_horizon - fine_horizon) * std::max(0.0, 1 - d / smoothing);
      }
      worst_rule = std::max(worst_rule, std::fabs(p.horizon[i] - expected) / expected);
      const bool is_smoothed = in_region && p.horizon[i] > fine_horizon * (1 + 1e-9);
      smoothed += is_smoothed ? 1 : 0;
      const double delta = p.horizon[i];
      if (!(p.x[i] - delta >= 0 && p.x[i] + delta <= 24e-3 && p.y[i] - delta >= 0 && p.y[i] + delta <= 16e-3))
        continue;
      double area = p.volume[i];  // the own cell, which no family contains
      for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b)
        area += p.partial_volume[b] * p.volume[p.neighbors[b]];
      const double exact = M_PI * delta * delta;
      worst_area = std::max(worst_area, std::fabs(area - exact) / exact);
      checked_smoothed += is_smoothed ? 1 : 0;
    }
    INFO(c.region << ": " << smoothed << " smoothed horizons (" << checked_smoothed
                  << " with the disk inside the plate); largest relative deviation from the rule " << worst_rule
                  << ", from pi delta_i^2 " << worst_area);
    CHECK(smoothed == c.in_band);
    CHECK(checked_smoothed > 0);
    CHECK(worst_rule < 1e-12);
    CHECK(worst_area < 1e-12);
  }
}

TEST_CASE("refinement: a smoothing length beyond the region's depth is warned about", "[refinement][smoothed_horizon]") {
  // The right half refined 2x: only its left edge, x = 12 mm, faces coarse
  // squares, and its innermost squares (centres at x = 23.75 mm) lie 11.75 mm
  // from it. With L_s = 20 mm the rule of theory.md Sec. 7.1 gives them
  // 1.5 + (3 - 1.5)(1 - 11.75 / 20) = 2.119 mm, not the fine 1.5 mm; before,
  // pd-mesh said nothing.
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("smoothed_long.pdp");
  const std::string base =
      geo + " --spacing 1mm --horizon-factor 3 --grid uniform --refine-region 12mm,0mm,24mm,16mm --refine-factor 2";
  const auto long_ramp = run_pd_mesh(base + " --horizon-smoothing 20mm -o " + out);
  INFO(long_ramp.err);
  REQUIRE(long_ramp.status == 0);
  CHECK_THAT(long_ramp.err,
             Catch::Contains("--horizon-smoothing 20mm is longer than the 11.75 mm from the refinement region's "
                             "innermost square to its edges that face coarse squares: no refined square keeps the "
                             "fine horizon 1.5 mm (the smallest is 2.119 mm, the coarse one 3 mm)"));
  const auto p = pd::read_particle_file(out);
  const double smallest = *std::min_element(p.horizon.begin(), p.horizon.end());
  CHECK(smallest == Approx(1.5e-3 + 1.5e-3 * (1 - 11.75 / 20)).epsilon(1e-12));
  // A ramp shorter than the depth leaves the middle fine and is not warned about.
  const auto short_ramp = run_pd_mesh(base + " --horizon-smoothing 11mm -o " + out);
  REQUIRE(short_ramp.status == 0);
  CHECK_THAT(short_ramp.err, !Catch::Contains("--horizon-smoothing"));
}

TEST_CASE("refinement: smoothing with no coarse square beside the region is warned about", "[refinement][smoothed_horizon]") {
  // A region over the whole plate leaves no square of side dx for the ramp to
  // reach: nothing is smoothed. Before 6 December 2026 pd-mesh said nothing.
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("smoothed_everywhere.pdp");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --grid uniform --refine-region "
                                     "-1mm,-1mm,30mm,20mm --refine-factor 2 --horizon-smoothing 2mm -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  CHECK_THAT(run.err, Catch::Contains("--horizon-smoothing 2mm smooths no refined square: the refinement region "
                                      "covers the plate's bounding box, so no refined square has a square of side "
                                      "dx beside it; their horizons stay m x their own size"));
  const auto p = pd::read_particle_file(out);
  CHECK(*std::max_element(p.horizon.begin(), p.horizon.end()) == Approx(1.5e-3).epsilon(1e-12));
}

TEST_CASE("refinement: bad options get a message naming the option and the value", "[refinement]") {
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("refused.pdp");
  const std::string base = geo + " --spacing 1mm --horizon-factor 3 -o " + out;
  const std::string region = " --refine-region 12mm,0mm,24mm,16mm --refine-factor 2";
  struct Case {
    const char* what;
    std::string arguments;
    std::vector<std::string> message;  // what stderr must contain
  };
  const std::vector<Case> cases = {
      {"a factor that is not a power of two", " --refine-region 12mm,0mm,24mm,16mm --refine-factor 3",
       {"--refine-factor 3: expected a power of two from 2 to 64"}},
      // Before 7 December 2026: "the argument ('2.5') for option '--refine-factor' is invalid", no factor named.
      {"a factor that is no whole number", " --refine-region 12mm,0mm,24mm,16mm --refine-factor 2.5",
       {"pd-mesh: error: --refine-factor 2.5: expected a power of two from 2 to 64\n"}},
      {"a factor beyond an int", " --refine-region 12mm,0mm,24mm,16mm --refine-factor 99999999999",
       {"pd-mesh: error: --refine-factor 99999999999: expected a power of two from 2 to 64\n"}},
      {"a malformed rectangle", " --refine-region 12mm,0mm,24mm --refine-factor 2",
       {"--refine-region '12mm,0mm,24mm': expected X0,Y0,X1,Y1"}},
      {"a rectangle outside the plate", " --refine-region 30mm,0mm,40mm,16mm --refine-factor 2",
       {"--refine-region: the rectangle", "does not meet the plate's bounding box"}},
      {"a negative smoothing length", region + " --horizon-smoothing=-1mm",
       {"--horizon-smoothing '-1mm': expected a length >= 0"}},
      {"a smoothing length without a unit", region + " --horizon-smoothing 2", {"--horizon-smoothing: '2' has no unit"}},
      {"a smoothing length without a region", " --horizon-smoothing 2mm",
       {"--horizon-smoothing 2mm needs --refine-region and --refine-factor"}},
      {"a factor without a region", " --refine-factor 2", {"--refine-region and --refine-factor go together"}},
      {"a region on a free mesh", region + " --grid free", {"needs --grid nbnug or uniform (it splits lattice squares"}},
      {"smoothing boxes at dx (no finer region)", " --box-spacing 1mm --horizon-smoothing 2mm",
       {"--horizon-smoothing 2mm with --box-spacing 1mm (= the spacing: no finer boxes) needs --refine-region"}},
  };
  for (const auto& c : cases) {
    INFO(c.what);
    const auto run = run_pd_mesh(base + c.arguments);
    CHECK(run.status != 0);
    for (const auto& text : c.message) CHECK_THAT(run.err, Catch::Contains(text));
  }
}

// --refine-region is split as every tool splits its lists: blanks around an
// item are not part of it, and an empty item is refused by its place in the
// rectangle's words (before 7 December 2026 a trailing comma was dropped
// without a word, '12mm ,0mm,24mm,16mm' was "' 12mm ' has characters after
// the length", and '12mm,,24mm,16mm' was "'' is not a length").
TEST_CASE("refinement: blanks around the region's items are not part of them and an empty item is named by its place",
          "[refinement][cli]") {
  const auto as_typed = refined_plate(2, "12mm,0mm,24mm,16mm");
  const auto blanks = refined_plate(2, "'12mm , 0mm,24mm ,16mm '");
  CHECK(blanks.size() == as_typed.size());
  CHECK(blanks.x == as_typed.x);
  CHECK(blanks.horizon == as_typed.horizon);
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("refused_item.pdp");
  const std::string base = geo + " --spacing 1mm --horizon-factor 3 --grid uniform --refine-factor 2 --refine-region ";
  const std::string expected = ": expected X0,Y0,X1,Y1 with units (e.g. 10mm,0mm,20mm,5mm)";
  expect_pd_mesh_refusal_alone(base + "12mm,0mm,24mm,16mm,", out,
                               "--refine-region '12mm,0mm,24mm,16mm,': item 5 is empty" + expected);
  expect_pd_mesh_refusal_alone(base + "12mm,,24mm,16mm", out, "--refine-region '12mm,,24mm,16mm': item 2 is empty" +
                                                                  expected);
  expect_pd_mesh_refusal_alone(base + "'12mm, ,24mm,16mm'", out,
                               "--refine-region '12mm, ,24mm,16mm': item 2 is empty" + expected);
  expect_pd_mesh_refusal_alone(base + "12mm,0mm,24mm", out, "--refine-region '12mm,0mm,24mm'" + expected);
}

// A region of more than ten plates across is most likely in another unit
// (0m,0m,24m,16m for mm): clipped to the plate it refines all of it. Before 7
// December 2026 without a word; a region a little beyond the plate, a way
// to say "all of it", is not warned about.
TEST_CASE("refinement: a region of more than ten plates across is warned about as another unit", "[refinement]") {
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("refined_unit.pdp");
  const std::string base = geo + " --spacing 1mm --horizon-factor 3 -o " + out + " --refine-factor 2 --refine-region ";
  expect_pd_mesh_warning_alone(base + "0m,0m,24m,16m",
                               geo + ": --refine-region 0m,0m,24m,16m is more than ten times the plate's larger side "
                                     "(24 mm) across: is it in another unit? Clipped to the plate it refines all the "
                                     "plate it covers; a region is the part of the plate to refine (the plate spans x "
                                     "0 mm to 24 mm, y 0 mm to 16 mm)");
  expect_pd_mesh_warning_alone(base + "-1mm,-1mm,25mm,17mm", "");
  // A refusal for memory, which the warning explains, comes after it.
  const auto refused = run_pd_mesh(geo + " --spacing 0.1mm --horizon-factor 3 -o " + out +
                                   " --refine-factor 4 --refine-region 0m,0m,24m,16m --max-memory 10MB");
  CHECK(refused.status == 1);
  CHECK_THAT(refused.err, Catch::StartsWith("pd-mesh: warning: " + geo + ": --refine-region 0m,0m,24m,16m is more "
                                            "than ten times the plate's larger side"));
  CHECK_THAT(refused.err, Catch::Contains("\npd-mesh: error: " + geo + ": this grid needs about 6.14e+05 particles"));
}

// A region both far too large and off the plate is refused alone: before 7
// December 2026 the warning that it is likely in another unit came first,
// then the refusal of the same region.
TEST_CASE("refinement: a region far too large that misses the plate gets its refusal alone", "[refinement]") {
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  expect_pd_mesh_refusal_alone(geo + " --spacing 1mm --horizon-factor 3 --refine-factor 2 --refine-region "
                                     "100m,100m,300m,300m",
                               mesher_temp("refined_missing.pdp"),
                               "--refine-region: the rectangle [100000 mm, 300000 mm] x [100000 mm, 300000 mm] does "
                               "not meet the plate's bounding box");
}

// A region that meets the plate's bounding box but holds no square of it (a
// sliver along a round plate's edge: free cells of the band along the circle,
// and cells outside it) is refused before gmsh meshes the free cells, and
// alone: before 7 December 2026 it was refused once the grid was meshed, and
// one of ten plates across got the warning that it is likely in another unit
// first. Inside a hole's box likewise, and on the uniform grid in the hole.
TEST_CASE("refinement: a region that holds no square gets its refusal alone", "[refinement]") {
  const auto disk = write_text_file("refined_disk.geo", disk_10);
  const auto out = mesher_temp("refined_no_square.pdp");
  const std::string options = " --spacing 1mm --horizon-factor 3 --refine-factor 2 --refine-region ";
  expect_pd_mesh_refusal_alone(disk + options + "-100m,-100m,-9.5mm,100m", out,
                               "--refine-region -100m,-100m,-9.5mm,100m: no lattice square of the plate lies in it");
  const auto holed = write_text_file("refined_hole.geo", plate_40_hole_geo);
  expect_pd_mesh_refusal_alone(holed + options + "19mm,19mm,21mm,21mm", out,
                               "--refine-region 19mm,19mm,21mm,21mm: no lattice square of the plate lies in it");
  expect_pd_mesh_refusal_alone(holed + " --grid uniform" + options + "19mm,19mm,21mm,21mm", out,
                               "--refine-region 19mm,19mm,21mm,21mm: no lattice square of the plate lies in it");
}
