// Graded free meshes (pd-mesh --grid free --graded-spacing DXF[,L],
// docs/mesher.md "Graded free meshes", theory.md Sec. 7.4): a 40 x 40 mm
// plate with a hole of radius R = 4 mm at its centre, dx = 1 mm, m = 3,
// DXF = 0.25 mm, L = 3 horizons = 9 mm by default. The target size is
// h(d) = DXF + (dx - DXF) min(1, d / L), d = |x - c| - R the distance from the
// hole, here in closed form for the circle.
//
// References: the requested sizes DXF and dx; the closed-form cell count
// of the size field, the integral of 1 / h^2 over the plate; the exact area
// 40^2 - pi R^2; and for the partial volumes, that the cells tile any disk in
// the material off the curved cells, so the own cell plus the partial volumes
// of a family cover exactly pi delta_i^2 (theory.md Sec. 2.2).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>

#include "particle_file.hpp"
#include "pd_mesh_run.hpp"

using namespace pd::test_support;

namespace {

constexpr double dx = 1e-3, m = 3, fine = 0.25e-3, grading = 3 * m * dx, centre = 20e-3, hole_r = 4e-3,
                 side = 40e-3;

double distance_from_hole(const pd::ParticleSet& p, std::size_t i) {
  return std::hypot(p.x[i] - centre, p.y[i] - centre) - hole_r;
}

double target_size(double distance) { return fine + (dx - fine) * std::min(1.0, distance / grading); }

pd::ParticleSet mesh_plate(const std::string& grid_options, const std::string& name) {
  const auto geo = write_text_file("graded_plate.geo", plate_40_hole_geo);
  const auto out = mesher_temp(name + ".pdp");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 " + grid_options + " -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  return pd::read_particle_file(out);
}

const pd::ParticleSet& graded_plate() {
  static const pd::ParticleSet p = mesh_plate("--grid free --graded-spacing 0.25mm", "graded");
  return p;
}

}  // namespace

TEST_CASE("graded mesh: cells of about DXF at the hole, about dx far away, horizons m h(x)",
          "[mesher][graded]") {
  const auto& p = graded_plate();
  double near_sum = 0, far_sum = 0, worst_horizon = 0;
  std::size_t near = 0, far = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = distance_from_hole(p, i), size = std::sqrt(p.volume[i]);
    // The horizon follows the smooth field at the centroid (closed form here;
    // pd-mesh measures d to chords of DXF / 8 on the circle, which lie within
    // (DXF / 8)^2 / (8 R) = 3.1e-5 mm of it: 1.1e-5 of h at the hole).
    worst_horizon = std::max(worst_horizon, std::fabs(p.horizon[i] - m * target_size(d)) / (m * target_size(d)));
    if (d < 2 * fine) near_sum += size, ++near;  // the first rows of cells at the hole
    if (d > grading + 2 * dx) far_sum += size, ++far;
  }
  INFO(near << " cells at the hole, mean sqrt(area) " << near_sum / near << " m; " << far
            << " cells beyond L, mean " << far_sum / far << " m; worst horizon error " << worst_horizon);
  CHECK(near > 100);  // 2 pi R / DXF = 100 boundary edges, one or two rows
  CHECK(far > 300);
  // gmsh's cells scatter about the target (triangles have about half a
  // quad's area): the mean within 0.7 ... 1.3 of the target.
  CHECK(near_sum / near > 0.7 * fine);
  CHECK(near_sum / near < 1.3 * fine);
  CHECK(far_sum / far > 0.7 * dx);
  CHECK(far_sum / far < 1.3 * dx);
  CHECK(worst_horizon < 2e-5);
  CHECK(*std::min_element(p.horizon.begin(), p.horizon.end()) == Approx(m * fine).epsilon(0.05));
  CHECK(*std::max_element(p.horizon.begin(), p.horizon.end()) == Approx(m * dx).epsilon(1e-12));
  CHECK_THAT(p.provenance, Catch::Contains("\"graded_spacing_m\": "));
}

TEST_CASE("graded mesh: particle count follows the size field, exact area", "[mesher][graded]") {
  const auto& p = graded_plate();
  // Closed form of the integral of 1 / h^2: over the band R < r < R + L,
  // 2 pi (R + d) / h(d)^2 with h = DXF + k d, k = (dx - DXF) / L, and beyond
  // it the plate (wholly inside it: 20 - 4 - 9 = 7 mm to the edges) at dx.
  const double k = (dx - fine) / grading, h1 = fine + k * grading;
  // Integral of (R + d) / (DXF + k d)^2 dd from 0 to L, u = DXF + k d.
  const double a = hole_r - fine / k;  // R + d = a + u / k
  const double band = 2 * M_PI / k * (a * (1 / fine - 1 / h1) + std::log(h1 / fine) / k);
  const double outside = (side * side - M_PI * std::pow(hole_r + grading, 2)) / (dx * dx);
  const double expected = band + outside;
  double area = 0;
  for (double v : p.volume) area += v;
  INFO(p.size() << " particles, the size field's integral " << expected);
  CHECK(static_cast<double>(p.size()) > 0.75 * expected);
  CHECK(static_cast<double>(p.size()) < 1.25 * expected);
  CHECK(area == Approx(side * side - M_PI * hole_r * hole_r).epsilon(1e-9));
  // Between the uniform free grids at dx and at DXF.
  const auto at_dx = mesh_plate("--grid free", "free_at_dx");
  INFO("uniform free grid at dx: " << at_dx.size());
  CHECK(p.size() > at_dx.size());
  CHECK(static_cast<double>(p.size()) < 0.2 * (side * side - M_PI * hole_r * hole_r) / (fine * fine));
  // A grading length far beyond the plate (1e6 mm) meshes the plate at about
  // DXF: the estimate before meshing takes at most the whole plate at DXF
  // (before, its bands' 1e12 particles were refused).
  const auto long_grading = mesh_plate("--grid free --graded-spacing 0.5mm,1e6mm", "graded_far");
  CHECK(static_cast<double>(long_grading.size()) < 1.5 * (side * side - M_PI * hole_r * hole_r) / (0.5e-3 * 0.5e-3));
}

TEST_CASE("graded mesh: sum of phi V over a horizon is pi delta_i^2 at fine, transition and coarse particles",
          "[mesher][graded]") {
  const auto& p = graded_plate();
  double worst = 0;
  std::size_t fine_count = 0, transition = 0, coarse = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double delta = p.horizon[i];
    const bool in_plate = p.x[i] - delta >= 0 && p.x[i] + delta <= side && p.y[i] - delta >= 0 &&
                          p.y[i] + delta <= side;
    // Off the hole and off the cells with curved edges (about one DXF deep).
    if (!in_plate || distance_from_hole(p, i) < delta + 2 * fine) continue;
    double area = p.volume[i];  // the own cell, which no family contains
    for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b)
      area += p.partial_volume[b] * p.volume[p.neighbors[b]];
    const double exact = M_PI * delta * delta;
    worst = std::max(worst, std::fabs(area - exact) / exact);
    const double h = delta / m;
    (h < 0.5 * dx ? fine_count : h < dx * (1 - 1e-9) ? transition : coarse)++;
  }
  INFO(fine_count << " fine (h < dx / 2), " << transition << " transition, " << coarse
                  << " coarse particles; largest relative error " << worst);
  CHECK(fine_count > 50);
  CHECK(transition > 200);
  CHECK(coarse > 200);
  CHECK(worst < 1e-12);
}

TEST_CASE("graded mesh: bad values are refused naming the option and the value", "[mesher][graded][cli]") {
  const auto geo = write_text_file("graded_bad.geo", plate_40_hole_geo);
  const auto out = mesher_temp("never_graded.pdp");
  const std::string base = geo + " --spacing 1mm --horizon-factor 3 --grid free";
  expect_pd_mesh_failure(base + " --graded-spacing 1mm", out,
                         "--graded-spacing 1mm: the fine size DXF 1 mm is not smaller than the spacing 1 mm");
  expect_pd_mesh_failure(base + " --graded-spacing 2mm", out, "is not smaller than the spacing");
  expect_pd_mesh_failure(base + " --graded-spacing 0mm", out,
                         "--graded-spacing 0mm: the fine size DXF 0mm must be a finite, positive length");
  expect_pd_mesh_failure(base + " --graded-spacing -0.5mm", out, "must be a finite, positive length");
  expect_pd_mesh_failure(base + " --graded-spacing 0.01mm", out,
                         "--graded-spacing 0.01mm: the fine size DXF 0.01 mm is below the spacing / 64");
  expect_pd_mesh_failure(base + " --graded-spacing 0.25mm,1mm", out,
                         "--graded-spacing 0.25mm,1mm: the grading length L 1 mm is too short; at least 2 (dx - "
                         "DXF) = 1.5 mm");
  expect_pd_mesh_failure(base + " --graded-spacing 0.25mm,0mm", out,
                         "the grading length L 0mm must be a finite, positive length");
  expect_pd_mesh_failure(base + " --graded-spacing 0.25", out, "--graded-spacing: '0.25' has no unit");
  expect_pd_mesh_failure(base + " --graded-spacing 0.25mm,4", out, "--graded-spacing: '4' has no unit");
  expect_pd_mesh_failure(geo + " --spacing 1mm --horizon-factor 3 --graded-spacing 0.25mm", out,
                         "--graded-spacing 0.25mm needs --grid free (the nbnug grid");
  // Nothing to grade towards: a plate of straight edges only.
  const auto square = write_text_file("graded_square.geo",
                                      "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0};\n"
                                      "Point(4) = {0, 20, 0}; Line(1) = {1, 2}; Line(2) = {2, 3};\n"
                                      "Line(3) = {3, 4}; Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4};\n"
                                      "Plane Surface(1) = {1};\n");
  expect_pd_mesh_failure(square + " --spacing 1mm --horizon-factor 3 --grid free --graded-spacing 0.25mm", out,
                         "graded_square.geo: --graded-spacing 0.25mm grades the cells from DXF at the curved "
                         "boundaries (holes, arcs) to dx, and every boundary of this plate is straight");
}

// DXF[,L] is split as every tool splits its lists: blanks around an item are
// not part of it, and an empty item is refused by its place (before 7
// December 2026 split at the first comma: '0.5mm ,9mm' was "'0.5mm ' has
// characters after the length", '0.5mm,' meshed with the default L without
// a word, and '0.5mm,,9mm' was "',9mm' is not a length").
TEST_CASE("graded mesh: blanks around DXF and L are not part of them and an empty item is named by its place",
          "[mesher][graded][cli]") {
  const auto as_typed = mesh_plate("--grid free --graded-spacing 0.5mm,9mm", "graded_as_typed");
  const auto blanks = mesh_plate("--grid free --graded-spacing '0.5mm , 9mm '", "graded_blanks");
  CHECK(blanks.size() == as_typed.size());
  CHECK(blanks.x == as_typed.x);
  const auto geo = write_text_file("graded_bad.geo", plate_40_hole_geo);
  const auto out = mesher_temp("never_graded.pdp");
  const std::string base = geo + " --spacing 1mm --horizon-factor 3 --grid free --graded-spacing ";
  const std::string expected = ": expected DXF or DXF,L with units (e.g. 0.05mm or 0.05mm,2mm)";
  expect_pd_mesh_refusal_alone(base + "0.5mm,", out, "--graded-spacing 0.5mm,: item 2 is empty" + expected);
  expect_pd_mesh_refusal_alone(base + "0.5mm,,9mm", out, "--graded-spacing 0.5mm,,9mm: item 2 is empty" + expected);
  expect_pd_mesh_refusal_alone(base + "',9mm'", out, "--graded-spacing ,9mm: item 1 is empty" + expected);
  expect_pd_mesh_refusal_alone(base + "0.5mm,9mm,10mm", out, "--graded-spacing 0.5mm,9mm,10mm" + expected);
}

TEST_CASE("graded mesh: the summary reports the grading, the cell sizes and the horizons", "[mesher][graded][cli]") {
  const auto geo = write_text_file("graded_summary.geo", plate_40_hole_geo);
  const auto out = mesher_temp("graded_summary.pdp"), summary = mesher_temp("graded_summary.txt");
  REQUIRE(run_shell(std::string(PD_MESH_EXE) + " " + geo + " --spacing 1mm --horizon-factor 3 --grid free " +
                    "--graded-spacing 0.25mm,6mm -o " + out + " > " + summary + " 2>&1") == 0);
  const auto text = file_text(summary);
  INFO(text);
  // The requested sizes and L, as given.
  CHECK_THAT(text, Catch::Contains("graded: target size 0.25 mm at the curved boundaries to 1 mm at 6 mm from them; "
                                   "cell sizes sqrt(area) "));
  CHECK_THAT(text, Catch::Contains("graded free cells (at their centroid's target size)"));
  // The horizons from m x (DXF + a little: the first centroids lie off the
  // hole), below 1 mm, to m dx = 3 mm.
  CHECK_THAT(text, Catch::Contains("horizons: 0."));
  CHECK_THAT(text, Catch::Contains(" to 3 mm (m x own size:"));
}

// A grading length of more than ten plates is most likely in another unit
// (20m for 20 mm): the cells then hardly grow across the plate. Before 7
// December 2026 it was meshed without a word; 10 plates and less are not
// warned about.
TEST_CASE("graded mesh: a grading length of more than ten plates is warned about as another unit",
          "[mesher][graded]") {
  const auto c1 = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("graded_unit.pdp");
  const auto base = c1 + " --spacing 1mm --horizon-factor 3 --grid free -o " + out + " --graded-spacing ";
  expect_pd_mesh_warning_alone(base + "0.5mm,20m",
                               c1 + ": --graded-spacing 0.5mm,20m: the grading length L 20000 mm is more than ten "
                                    "times the plate's larger side (20 mm): is it in another unit? The cells grow by "
                                    "less than a tenth of the way from DXF 0.5 mm to dx 1 mm across the plate, a free "
                                    "mesh at about DXF everywhere; L is a few horizons (the default, 3 horizons, is 9 "
                                    "mm)");
  expect_pd_mesh_warning_alone(base + "0.5mm,200mm", "");
}

// A grading length far too long on a plate of straight edges is refused
// alone: before 7 December 2026 the warning that the length is likely in
// another unit came first, then the refusal of the same option.
TEST_CASE("graded mesh: a grading length far too long on a straight plate gets its refusal alone",
          "[mesher][graded]") {
  const auto geo = write_text_file("graded_square.geo",
                                   "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0}; "
                                   "Point(4) = {0, 20, 0};\nLine(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; "
                                   "Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n");
  expect_pd_mesh_refusal_alone(geo + " --spacing 1mm --horizon-factor 3 --grid free --graded-spacing 0.5mm,20m",
                               mesher_temp("graded_square.pdp"),
                               geo + ": --graded-spacing 0.5mm,20m grades the cells from DXF at the curved boundaries "
                                     "(holes, arcs) to dx, and every boundary of this plate is straight; for a finer "
                                     "grid everywhere give a smaller --spacing");
}
