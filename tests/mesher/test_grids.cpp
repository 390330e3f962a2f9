// Grids built from the reference geometries, checked against exact areas.
// References: plate areas minus circle/ellipse areas (closed form); the
// disk-hole overlap is the closed-form lens area of two circles.
#include <catch2/catch.hpp>
#include <algorithm>
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
  // One free region: the hole's bounding box [6, 14] mm grown by one horizon
  // (0.4 mm) and snapped outward to the 0.1 mm lattice, cells 56 .. 143.
  CHECK(b.report.free_regions == 1);
  const auto& cells = b.report.cells;
  for (long j = 0; j < cells.lattice.ny; ++j)
    for (long i = 0; i < cells.lattice.nx; ++i) {
      const bool in_box = i >= 56 && i < 144 && j >= 56 && j < 144;
      if ((cells.at(i, j) == pd::CellKind::free) != in_box) FAIL("cell " << i << ", " << j << " in the box: " << in_box);
    }
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
  CHECK(b.report.free_regions == 8);
  CHECK(b.geometry.holes.size() == 8);
  CHECK(b.geometry.holes[0].name == "hole_1");
  // The bounding box comes from the boundary polyline (within 1e-6 dx of the circle).
  CHECK((b.geometry.holes[0].xmin + b.geometry.holes[0].xmax) / 2 == Approx(50e-3 / 9).epsilon(1e-9));
  // Padding is at least one horizon after snapping: every cell within one
  // horizon of a hole's bounding box is free.
  const auto& cells = b.report.cells;
  for (const auto& hole : b.geometry.holes)
    for (long j = 0; j < cells.lattice.ny; ++j)
      for (long i = 0; i < cells.lattice.nx; ++i) {
        const double x0 = i * dx, x1 = x0 + dx, y0 = j * dx, y1 = y0 + dx;
        const double gap_x = std::max({hole.xmin - x1, 0.0, x0 - hole.xmax});
        const double gap_y = std::max({hole.ymin - y1, 0.0, y0 - hole.ymax});
        if (std::max(gap_x, gap_y) < delta - 1e-12 && cells.at(i, j) != pd::CellKind::free)
          FAIL("cell " << i << ", " << j << " is within one horizon of " << hole.name << " but not free");
      }
}

TEST_CASE("boxes that overlap merge into one free region", "[mesher][c3]") {
  pd::GmshSession session;
  // Case C: pores at y = 12.5 +- 1.5 mm; a 1.2 mm padding makes their boxes overlap vertically.
  const double dx = 0.25e-3;
  const auto g = pd::load_plate_geometry(session, geometry_dir + "/c3c_pores.geo", 1e-3, dx);
  const auto lattice = pd::plate_lattice(g, dx);
  const auto apart = pd::free_regions(g, pd::classify_cells(g, lattice, pd::GridKind::nbnug, dx));
  CHECK(apart.regions.size() == 16);
  const auto merged = pd::free_regions(g, pd::classify_cells(g, lattice, pd::GridKind::nbnug, 1.2e-3));
  CHECK(merged.regions.size() == 8);
  // Each region: its outer loop and the two holes inside.
  for (const auto& region : merged.regions) CHECK(region.loops.size() == 3);
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
