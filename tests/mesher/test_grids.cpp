// Grids built from the reference geometries, checked against exact areas.
// References: plate areas minus circle/ellipse areas (closed form); the
// disk-hole overlap is the closed-form lens area of two circles.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "families.hpp"
#include "gmsh_session.hpp"
#include "grids.hpp"
#include "plate_geometry.hpp"

namespace {

const std::string geometry_dir = PD_GEOMETRY_DIR;

// Area of the intersection of two disks with radii r1, r2 and centre distance d.
double lens_area(double r1, double r2, double d) {
  if (d >= r1 + r2) return 0;
  if (d <= std::fabs(r1 - r2)) return M_PI * std::pow(std::min(r1, r2), 2);
  const double a1 = r1 * r1 * std::acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1));
  const double a2 = r2 * r2 * std::acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2));
  return a1 + a2 - 0.5 * std::sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2));
}

struct Built {
  pd::PlateGeometry geometry;
  pd::ParticleSet particles;
  pd::GridReport report;
};

Built build(pd::GmshSession& session, const std::string& file, pd::GridKind grid, double dx, double delta,
            pd::Quadrature quadrature = pd::Quadrature::analytic, double padding = -1) {
  Built b;
  b.geometry = pd::load_plate_geometry(session, file, 1e-3, dx);
  b.particles = pd::build_grid(session, b.geometry, {grid, dx, padding < 0 ? delta : padding}, b.report);
  pd::sort_particles_spatially(b.particles);
  b.particles.horizon_nominal = delta;
  for (auto& h : b.particles.horizon) h = delta;
  pd::build_families(b.particles, quadrature);
  return b;
}

double volume_sum(const pd::ParticleSet& p) {
  double s = 0;
  for (double v : p.volume) s += v;
  return s;
}

}  // namespace

TEST_CASE("NB-NUG grid of C1: squares outside one padded box, exact area", "[mesher][c1]") {
  pd::GmshSession session;
  const double dx = 0.1e-3, delta = 0.4e-3;
  const auto b = build(session, geometry_dir + "/c1_plate_hole.geo", pd::GridKind::nbnug, dx, delta);
  const double exact = 20e-3 * 20e-3 - M_PI * 4e-3 * 4e-3;
  CHECK(std::fabs(volume_sum(b.particles) - exact) / exact < 1e-9);
  REQUIRE(b.report.boxes.size() == 1);
  const auto& box = b.report.boxes[0];
  // Box = hole bounding box [6, 14] mm grown by one horizon (0.4 mm) and
  // snapped outward to the 0.1 mm lattice: cells 56 .. 144.
  CHECK(box.i0 == 56);
  CHECK(box.i1 == 144);
  CHECK(box.j0 == 56);
  CHECK(box.j1 == 144);
  // Every square lies outside the box; every free cell inside it.
  std::size_t squares = 0;
  for (std::size_t i = 0; i < b.particles.size(); ++i) {
    const double x = b.particles.x[i], y = b.particles.y[i];
    const bool in_box = x > 5.6e-3 && x < 14.4e-3 && y > 5.6e-3 && y < 14.4e-3;
    if (b.particles.region[i] == static_cast<std::uint8_t>(pd::Region::uniform_square)) {
      ++squares;
      CHECK_FALSE(in_box);
      CHECK(b.particles.volume[i] == Approx(dx * dx).epsilon(1e-12));
    } else {
      CHECK(in_box);
    }
  }
  CHECK(squares == 200 * 200 - 88 * 88);
  // Free cells are about dx^2 (quad-dominant).
  CHECK(b.report.free.quads > 10 * b.report.free.triangles);
  CHECK(b.report.free.min_area / (dx * dx) > 0.2);
  CHECK(b.report.free.max_area / (dx * dx) < 2.5);
}

TEST_CASE("partial volumes next to a hole: pi delta^2 minus the exact disk-hole overlap", "[mesher][families]") {
  pd::GmshSession session;
  const double dx = 0.1e-3, delta = 0.4e-3, radius = 4e-3;
  const pd::Vec2 centre{10e-3, 10e-3};
  double worst_analytic = 0, worst_hhb = 0, worst_free_interior = 0;
  int checked = 0, free_interior = 0;
  for (auto quadrature : {pd::Quadrature::analytic, pd::Quadrature::hhb}) {
    const auto b = build(session, geometry_dir + "/c1_plate_hole.geo", pd::GridKind::nbnug, dx, delta, quadrature);
    const auto& p = b.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double d = std::hypot(p.x[i] - centre.x, p.y[i] - centre.y);
      if (quadrature == pd::Quadrature::analytic && d > radius + delta + 2 * dx &&
          std::max(std::fabs(p.x[i] - centre.x), std::fabs(p.y[i] - centre.y)) < 4.4e-3 - delta) {
        // A disk inside the body but over free cells of the box: exact again.
        double sum = p.volume[i];
        for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k)
          sum += p.partial_volume[k] * p.volume[p.neighbors[k]];
        worst_free_interior = std::max(worst_free_interior, std::fabs(sum / (M_PI * delta * delta) - 1));
        ++free_interior;
      }
      if (d > radius + delta + dx) continue;  // only disks that meet or nearly meet the hole
      // The particle's own cell is inside its disk (cells are smaller than delta).
      double sum = p.volume[i];
      for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k)
        sum += p.partial_volume[k] * p.volume[p.neighbors[k]];
      const double exact = M_PI * delta * delta - lens_area(delta, radius, d);
      const double error = std::fabs(sum - exact) / (M_PI * delta * delta);
      if (quadrature == pd::Quadrature::analytic) {
        worst_analytic = std::max(worst_analytic, error);
        ++checked;
      } else {
        worst_hhb = std::max(worst_hhb, error);
      }
    }
  }
  INFO("particles near the hole: " << checked << "; max error / (pi delta^2): analytic " << worst_analytic
                                   << ", HHB " << worst_hhb);
  INFO("disks over free cells away from the hole: " << free_interior << ", max error " << worst_free_interior);
  WARN("near the hole (" << checked << " particles): analytic " << worst_analytic << ", HHB " << worst_hhb
                         << "; over free cells (" << free_interior << "): analytic " << worst_free_interior);
  REQUIRE(checked > 500);
  REQUIRE(free_interior > 100);
  CHECK(worst_free_interior < 1e-12);
  // Curved cells carry 7 arc points per edge: the remaining polygon-vs-curve
  // error is ~1/64 of a bulge (~1e-4 dx^2) on the few cells the disk cuts.
  CHECK(worst_analytic < 1e-5);
  CHECK(worst_hhb > 10 * worst_analytic);
}

TEST_CASE("C3-A (OpenCASCADE ellipse curves): 8 boxes, exact area", "[mesher][c3]") {
  pd::GmshSession session;
  const double dx = 0.125e-3, delta = 0.5e-3;
  const auto b = build(session, geometry_dir + "/c3a_pores.geo", pd::GridKind::nbnug, dx, delta);
  const double exact = 50e-3 * 25e-3 - 8 * M_PI * 0.75e-3 * 0.75e-3;
  CHECK(std::fabs(volume_sum(b.particles) - exact) / exact < 1e-9);
  CHECK(b.report.boxes.size() == 8);
  CHECK(b.geometry.holes.size() == 8);
  CHECK(b.geometry.holes[0].name == "hole_1");
  // The bounding box comes from samples every dx/16: exact to the sagitta (~1e-5 relative here).
  CHECK((b.geometry.holes[0].xmin + b.geometry.holes[0].xmax) / 2 == Approx(50e-3 / 9).epsilon(1e-5));
  // Padding is at least one horizon after snapping.
  for (const auto& box : b.report.boxes) {
    const auto& hole = b.geometry.holes[box.holes.at(0)];
    CHECK(hole.xmin - (box.i0 * dx) >= delta - 1e-12);
    CHECK(box.i1 * dx - hole.xmax >= delta - 1e-12);
    CHECK(hole.ymin - (box.j0 * dx) >= delta - 1e-12);
    CHECK(box.j1 * dx - hole.ymax >= delta - 1e-12);
  }
}

TEST_CASE("boxes that overlap merge into one", "[mesher][c3]") {
  pd::GmshSession session;
  // Case C: pores at y = 12.5 +- 1.5 mm; a 1.2 mm padding makes their boxes overlap vertically.
  const auto g = pd::load_plate_geometry(session, geometry_dir + "/c3c_pores.geo", 1e-3, 0.25e-3);
  long nx = 0, ny = 0;
  pd::lattice_cells(g, 0.25e-3, nx, ny);
  CHECK(pd::nbnug_boxes(g, 0.25e-3, 0.25e-3, nx, ny).size() == 16);
  const auto merged = pd::nbnug_boxes(g, 0.25e-3, 1.2e-3, nx, ny);
  CHECK(merged.size() == 8);
  for (const auto& box : merged) CHECK(box.holes.size() == 2);
}

TEST_CASE("uniform grid removes squares whose centroid is in a hole", "[mesher][uniform]") {
  pd::GmshSession session;
  const double dx = 0.2e-3;
  const auto b = build(session, geometry_dir + "/c1_plate_hole.geo", pd::GridKind::uniform, dx, 3 * dx);
  for (std::size_t i = 0; i < b.particles.size(); ++i)
    CHECK(std::hypot(b.particles.x[i] - 10e-3, b.particles.y[i] - 10e-3) > 4e-3);
  // Count of lattice centroids outside the circle, computed independently.
  std::size_t expected = 0;
  for (int j = 0; j < 100; ++j)
    for (int i = 0; i < 100; ++i)
      if (std::hypot((i + 0.5) * dx - 10e-3, (j + 0.5) * dx - 10e-3) > 4e-3) ++expected;
  CHECK(b.particles.size() == expected);
}

TEST_CASE("global free grid: one free mesh, exact area", "[mesher][free]") {
  pd::GmshSession session;
  const double dx = 0.4e-3;
  const auto b = build(session, geometry_dir + "/c1_plate_hole.geo", pd::GridKind::free, dx, 3 * dx);
  const double exact = 20e-3 * 20e-3 - M_PI * 4e-3 * 4e-3;
  CHECK(std::fabs(volume_sum(b.particles) - exact) / exact < 1e-9);
  for (auto r : b.particles.region) CHECK(r == static_cast<std::uint8_t>(pd::Region::other));
}
