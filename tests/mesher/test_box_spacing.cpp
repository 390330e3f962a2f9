// NB-NUG boxes meshed finer than the squares (pd-mesh --box-spacing DXB,
// docs/mesher.md "Finer boxes"): a 40 x 40 mm plate with a hole of radius
// 4 mm at its centre, dx = 1 mm, m = 3, so the box around the hole (padded by
// one coarse horizon, 3 mm) spans [13, 27]^2 mm and squares lie all round it.
// Reference for the partial volumes: for a particle whose own horizon disk
// lies in the material and off the cells at the hole, the cells tile the disk,
// so the own cell plus the partial volumes of the family cover exactly
// pi delta_i^2 (theory.md Sec. 2.2), whatever the cells' shapes and sizes.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "pd_mesh_run.hpp"

using namespace pd::test_support;

namespace {

constexpr double dx = 1e-3, m = 3, hole_x = 20e-3, hole_y = 20e-3, hole_r = 4e-3, side = 40e-3;

// extra: e.g. "--box-spacing 0.5mm"; empty: the boxes at dx.
pd::ParticleSet plate_with_box(const std::string& extra, const std::string& name) {
  const auto geo = write_text_file("box_plate.geo", plate_40_hole_geo);
  const auto out = mesher_temp(name + ".pdp");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 " + extra + " -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  return pd::read_particle_file(out);
}

bool is_box_cell(const pd::ParticleSet& p, std::size_t i) {
  return p.region[i] == static_cast<std::uint8_t>(pd::Region::box_free_mesh);
}

}  // namespace

TEST_CASE("box spacing: box cells about DXB, their horizons m x DXB, squares unchanged", "[mesher][box_spacing]") {
  const auto at_dx = plate_with_box("", "box_at_dx");
  std::size_t box_cells_at_dx = 0;
  for (std::size_t i = 0; i < at_dx.size(); ++i) box_cells_at_dx += is_box_cell(at_dx, i);
  for (int k : {2, 4}) {
    const double box = dx / k;
    const auto p = plate_with_box("--box-spacing " + std::to_string(1.0 / k) + "mm", "box_" + std::to_string(k));
    std::size_t squares = 0, box_cells = 0;
    double box_area = 0, sum_size = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (is_box_cell(p, i)) {
        // The rule of the option: m x the box's target size, the same for every box cell.
        CHECK(p.horizon[i] == Approx(m * box).epsilon(1e-12));
        box_area += p.volume[i];
        sum_size += std::sqrt(p.volume[i]);
        ++box_cells;
      } else {
        CHECK(p.region[i] == static_cast<std::uint8_t>(pd::Region::uniform_square));
        CHECK(p.volume[i] == Approx(dx * dx).epsilon(1e-12));
        CHECK(p.horizon[i] == Approx(m * dx).epsilon(1e-12));
        ++squares;
      }
    }
    INFO("DXB = dx / " << k << ": " << box_cells << " box cells, mean sqrt(area) " << sum_size / box_cells << " m");
    // The box is the cells [13, 27]^2 mm whatever DXB: 1600 - 196 squares,
    // and the box cells fill the rest, 14^2 mm^2 less the hole (exact, with
    // the cells' curved edges).
    CHECK(squares == 1600u - 196u);
    CHECK(box_area == Approx(196e-6 - M_PI * hole_r * hole_r).epsilon(1e-9));
    // gmsh meshes at the target size: cells of about DXB (quads DXB^2,
    // triangles about half that), k^2 times as many as at dx within 25 %.
    CHECK(sum_size / box_cells > 0.7 * box);
    CHECK(sum_size / box_cells < 1.2 * box);
    CHECK(static_cast<double>(box_cells) / box_cells_at_dx > 0.75 * k * k);
    CHECK(static_cast<double>(box_cells) / box_cells_at_dx < 1.25 * k * k);
    CHECK_THAT(p.provenance, Catch::Contains("\"box_spacing_m\": "));
  }
}

TEST_CASE("box spacing: DXB = dx gives the grid without the option", "[mesher][box_spacing]") {
  // Reference: the grid pd-mesh builds without --box-spacing.
  const auto plain = plate_with_box("", "box_plain");
  const auto same = plate_with_box("--box-spacing 1mm", "box_same");
  REQUIRE(same.size() == plain.size());
  CHECK(same.x == plain.x);
  CHECK(same.y == plain.y);
  CHECK(same.volume == plain.volume);
  CHECK(same.horizon == plain.horizon);
  CHECK(same.neighbors == plain.neighbors);
  CHECK(same.partial_volume == plain.partial_volume);
}

TEST_CASE("box spacing: sum of phi V over a horizon is pi delta_i^2 at both resolutions, across the box edge",
          "[mesher][box_spacing]") {
  // (With --horizon-smoothing too: the ramp's larger disks are tiled as well.)
  for (const std::string options : {"--box-spacing 0.5mm", "--box-spacing 0.25mm",
                                    "--box-spacing 0.25mm --horizon-smoothing 2mm"}) {
    const auto p = plate_with_box(options, "box_sum");
    double worst = 0;
    std::size_t squares = 0, box_cells = 0, squares_seeing_box = 0, box_cells_seeing_squares = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double delta = p.horizon[i];
      const bool in_plate = p.x[i] - delta >= 0 && p.x[i] + delta <= side && p.y[i] - delta >= 0 &&
                            p.y[i] + delta <= side;
      // Off the hole and off the cells along it (at most about one DXB deep; 2 dx is ample).
      const bool off_hole = std::hypot(p.x[i] - hole_x, p.y[i] - hole_y) - hole_r >= delta + 2 * dx;
      if (!in_plate || !off_hole) continue;
      double area = p.volume[i];  // the own cell, which no family contains
      bool sees_box = false, sees_square = false;
      for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b) {
        const auto j = p.neighbors[b];
        area += p.partial_volume[b] * p.volume[j];
        (is_box_cell(p, j) ? sees_box : sees_square) = true;
      }
      const double exact = M_PI * delta * delta;
      worst = std::max(worst, std::fabs(area - exact) / exact);
      if (is_box_cell(p, i)) {
        ++box_cells;
        box_cells_seeing_squares += sees_square;
      } else {
        ++squares;
        squares_seeing_box += sees_box;
      }
    }
    INFO(options << ": " << squares << " squares (" << squares_seeing_box << " see box cells), "
                       << box_cells << " box cells (" << box_cells_seeing_squares << " see squares), "
                       << "largest relative error " << worst);
    CHECK(squares > 100);
    CHECK(box_cells >= 50);
    CHECK(squares_seeing_box > 10);
    CHECK(box_cells_seeing_squares > 10);
    CHECK(worst < 1e-12);
  }
}

TEST_CASE("box spacing: bad values are refused naming the option and the value", "[mesher][box_spacing][cli]") {
  const auto geo = write_text_file("box_bad.geo", plate_40_hole_geo);
  const auto out = mesher_temp("never_box.pdp");
  const std::string base = geo + " --spacing 1mm --horizon-factor 3";
  expect_pd_mesh_failure(base + " --box-spacing 2mm", out, "--box-spacing 2mm (2 mm): larger than the spacing");
  expect_pd_mesh_failure(base + " --box-spacing 0mm", out, "--box-spacing 0mm (0 mm): expected a finite, positive");
  expect_pd_mesh_failure(base + " --box-spacing -0.5mm", out, "--box-spacing -0.5mm (-0.5 mm): expected a finite");
  expect_pd_mesh_failure(base + " --box-spacing nanmm", out, "--box-spacing: 'nanmm' is not a number with a unit");
  expect_pd_mesh_failure(base + " --box-spacing 'nan mm'", out, "--box-spacing: 'nan' is not a finite number");
  expect_pd_mesh_failure(base + " --box-spacing 1e400mm", out, "--box-spacing: '1e400' is not a finite number");
  expect_pd_mesh_failure(base + " --box-spacing 0.3mm", out, "--box-spacing 0.3mm (0.3 mm): expected the spacing");
  expect_pd_mesh_failure(base + " --box-spacing 0.5", out, "--box-spacing: '0.5' has no unit");
  expect_pd_mesh_failure(base + " --box-spacing 0.5mm --grid uniform", out, "--box-spacing 0.5mm needs --grid nbnug");
  // Smoothing needs a finer region: boxes at dx are none (before the fourth
  // sitting of 5 December 2026 any --box-spacing with it was refused).
  expect_pd_mesh_failure(base + " --box-spacing 1mm --horizon-smoothing 1mm", out,
                         "--horizon-smoothing 1mm with --box-spacing 1mm (= the spacing: no finer boxes) needs "
                         "--refine-region and --refine-factor, or --box-spacing finer than the spacing");
}

// --horizon-smoothing with --box-spacing (theory.md Sec. 7.1): every box
// cell's horizon is m DXB + (m dx - m DXB) max(0, 1 - d / L_s), d its
// distance to the nearest square of side dx, computed here from all the
// squares; the squares keep m dx. Cells farther than L_s keep m DXB.
TEST_CASE("box spacing with a smoothed horizon: the ramp from the squares into the box", "[mesher][box_spacing]") {
  const double box = 0.25e-3, smoothing = 2e-3, fine = m * box, coarse = m * dx;
  const auto p = plate_with_box("--box-spacing 0.25mm --horizon-smoothing 2mm", "box_smoothed");
  std::vector<std::size_t> squares;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!is_box_cell(p, i)) squares.push_back(i);
  double worst = 0;
  std::size_t ramped = 0, kept_fine = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!is_box_cell(p, i)) {
      CHECK(p.horizon[i] == coarse);
      continue;
    }
    double distance = 1e9;
    for (auto k : squares) {
      const double ex = std::max(std::fabs(p.x[i] - p.x[k]) - 0.5 * dx, 0.0);
      const double ey = std::max(std::fabs(p.y[i] - p.y[k]) - 0.5 * dx, 0.0);
      distance = std::min(distance, std::hypot(ex, ey));
    }
    const double expected = fine + (coarse - fine) * std::max(0.0, 1 - distance / smoothing);
    worst = std::max(worst, std::fabs(p.horizon[i] - expected) / expected);
    ramped += expected > fine * (1 + 1e-9);
    kept_fine += expected == fine;
  }
  INFO(ramped << " box cells ramped, " << kept_fine << " at the fine horizon; largest relative error " << worst);
  CHECK(worst < 1e-14);
  CHECK(ramped > 500);
  CHECK(kept_fine > 100);
  // A smoothing length beyond the box's depth leaves no cell at m DXB: said.
  const auto geo = write_text_file("box_plate.geo", plate_40_hole_geo);
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --box-spacing 0.25mm --horizon-smoothing "
                                     "20mm -o " + mesher_temp("box_smoothed_long.pdp"));
  INFO(run.err);
  CHECK(run.status == 0);
  CHECK_THAT(run.err, Catch::Contains("--horizon-smoothing 20mm is longer than the") &&
                          Catch::Contains("mm from the boxes' innermost cell to the squares of side dx: no box cell "
                                          "keeps the fine horizon 0.75 mm"));
}

// A refinement region over the whole plate leaves the boxes no square of side
// dx to ramp towards: nothing is smoothed, and said (before 6 December 2026,
// without a word).
TEST_CASE("box smoothing with no square of side dx left is warned about", "[mesher][box_spacing]") {
  const auto geo = write_text_file("box_plate.geo", plate_40_hole_geo);
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --box-spacing 0.25mm --refine-region "
                                     "-1mm,-1mm,100mm,100mm --refine-factor 2 --horizon-smoothing 2mm -o " +
                               mesher_temp("box_refined_everywhere.pdp"));
  INFO(run.err);
  CHECK(run.status == 0);
  CHECK_THAT(run.err, Catch::Contains("--horizon-smoothing 2mm smooths no box cell: no square of side dx is left in "
                                      "the plate (the refinement region covers it)"));
}

// A plate whose every boundary lies on lattice lines has no box: the option
// changes nothing, and says so (before the fourth sitting of 5 December
// 2026, without a word).
TEST_CASE("box spacing on a plate without boxes is warned about", "[mesher][box_spacing]") {
  const auto geo = write_text_file("no_box.geo",
                                   "Point(1) = {0,0,0}; Point(2) = {24,0,0}; Point(3) = {24,16,0}; "
                                   "Point(4) = {0,16,0};\nLine(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; "
                                   "Line(4) = {4,1};\nCurve Loop(1) = {1:4}; Plane Surface(1) = {1};\n");
  const auto out = mesher_temp("no_box.pdp");
  const auto run =
      run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --box-spacing 0.5mm --horizon-smoothing 2mm -o " + out);
  INFO(run.err);
  CHECK(run.status == 0);
  CHECK_THAT(run.err, Catch::Contains("--box-spacing 0.5mm changes nothing: every boundary of this plate lies on "
                                      "lattice lines, so it has no box of free cells to mesh finer (nor "
                                      "--horizon-smoothing any box cell to smooth)"));
}
