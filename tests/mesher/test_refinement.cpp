// Refinement regions (docs/mesher.md, "Refinement regions"): a plate with a
// band of squares dx / f (f = 2, 4, 8), each particle with the horizon m x its
// own side. Reference: for a particle whose horizon disk lies inside the
// plate, the cells tile the disk, so the own cell plus the partial volumes of
// the family cover exactly pi delta_i^2 (theory.md Sec. 2.2), whatever the
// sizes of the cells the disk cuts: at the interface too.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "particle_file.hpp"
#include "pd_mesh_run.hpp"

using namespace pd::test_support;

namespace {

// 24 x 16 mm; the right half, x in [12, 24] mm, is refined.
const std::string plate_24_16 =
    "Point(1) = {0, 0, 0}; Point(2) = {24, 0, 0}; Point(3) = {24, 16, 0}; Point(4) = {0, 16, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n";

pd::ParticleSet refined_plate(int factor, const std::string& region = "12mm,0mm,24mm,16mm") {
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("refined_" + std::to_string(factor) + ".pdp");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --grid uniform --refine-region " + region +
                               " --refine-factor " + std::to_string(factor) + " -o " + out);
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

TEST_CASE("refinement: bad options get a message naming the option and the value", "[refinement]") {
  const auto geo = write_text_file("refined_plate.geo", plate_24_16);
  const auto out = mesher_temp("refused.pdp");
  const std::string base = geo + " --spacing 1mm --horizon-factor 3 -o " + out;
  SECTION("a factor that is not a power of two") {
    const auto run = run_pd_mesh(base + " --refine-region 12mm,0mm,24mm,16mm --refine-factor 3");
    CHECK(run.status != 0);
    CHECK_THAT(run.err, Catch::Contains("--refine-factor 3: expected a power of two from 2 to 64"));
  }
  SECTION("a malformed rectangle") {
    const auto run = run_pd_mesh(base + " --refine-region 12mm,0mm,24mm --refine-factor 2");
    CHECK(run.status != 0);
    CHECK_THAT(run.err, Catch::Contains("--refine-region '12mm,0mm,24mm': expected X0,Y0,X1,Y1"));
  }
  SECTION("a rectangle outside the plate") {
    const auto run = run_pd_mesh(base + " --refine-region 30mm,0mm,40mm,16mm --refine-factor 2");
    CHECK(run.status != 0);
    CHECK_THAT(run.err, Catch::Contains("--refine-region: the rectangle"));
    CHECK_THAT(run.err, Catch::Contains("does not meet the plate's bounding box"));
  }
  SECTION("a factor without a region") {
    const auto run = run_pd_mesh(base + " --refine-factor 2");
    CHECK(run.status != 0);
    CHECK_THAT(run.err, Catch::Contains("--refine-region and --refine-factor go together"));
  }
}
