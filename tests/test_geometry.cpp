// Exact polygon-disk intersection areas, checked against independent references:
// closed forms (disk inside a square, square inside a disk, half-plane cuts)
// and CGAL exact-arithmetic polygon clipping of the disk's fine inscribed and
// circumscribed polygons, which bracket the true area.
#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "geometry.hpp"

namespace {
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Polygon = CGAL::Polygon_2<Kernel>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<Kernel>;

double cgal_intersection_area(const std::vector<double>& vx, const std::vector<double>& vy,
                              const Polygon& disk_polygon) {
  Polygon cell;
  for (std::size_t i = 0; i < vx.size(); ++i) cell.push_back(Kernel::Point_2(vx[i], vy[i]));
  if (cell.is_clockwise_oriented()) cell.reverse_orientation();
  std::vector<PolygonWithHoles> pieces;
  CGAL::intersection(cell, disk_polygon, std::back_inserter(pieces));
  double area = 0;
  for (const auto& piece : pieces) {
    area += CGAL::to_double(piece.outer_boundary().area());
    for (auto h = piece.holes_begin(); h != piece.holes_end(); ++h) area += CGAL::to_double(h->area());
  }
  return area;
}

// Regular polygon with `sides` vertices on a circle of radius `radius`.
Polygon regular_polygon(pd::Vec2 c, double radius, int sides) {
  Polygon p;
  for (int k = 0; k < sides; ++k) {
    const double a = 2 * M_PI * k / sides;
    p.push_back(Kernel::Point_2(c.x + radius * std::cos(a), c.y + radius * std::sin(a)));
  }
  return p;
}
}  // namespace

TEST_CASE("polygon area and centroid by the shoelace formula", "[geometry]") {
  const std::vector<double> vx{0, 2, 2, 0}, vy{0, 0, 1, 1};
  CHECK(pd::polygon_signed_area(vx.data(), vy.data(), 4) == Approx(2.0));
  const auto c = pd::polygon_centroid(vx.data(), vy.data(), 4);
  CHECK(c.x == Approx(1.0));
  CHECK(c.y == Approx(0.5));
  // A distorted quad: true centroid differs from the vertex average.
  const std::vector<double> qx{0, 4, 1, 0}, qy{0, 0, 1, 1};
  const auto q = pd::polygon_centroid(qx.data(), qy.data(), 4);
  // Split into triangles (0,0)-(4,0)-(1,1) [area 2] and (0,0)-(1,1)-(0,1) [area 0.5].
  CHECK(q.x == Approx((2 * 5.0 / 3 + 0.5 * 1.0 / 3) / 2.5));
  CHECK(q.y == Approx((2 * 1.0 / 3 + 0.5 * 2.0 / 3) / 2.5));
}

TEST_CASE("polygon area keeps its digits far from the origin", "[geometry]") {
  // A 0.1 mm square 1 km from the origin: products of absolute coordinates
  // (1e3 * 1e3) would leave about 1e-10 m^2 of round-off on its 1e-8 m^2.
  const double h = 1e-4, x0 = 1000.0, y0 = -700.0;
  const std::vector<double> vx{x0, x0 + h, x0 + h, x0}, vy{y0, y0, y0 + h, y0 + h};
  CHECK(pd::polygon_signed_area(vx.data(), vy.data(), 4) == Approx(h * h).epsilon(1e-9));
  CHECK(pd::polygon_signed_area(vx.data(), vy.data(), 2) == 0.0);  // fewer than 3 vertices: no area
}

TEST_CASE("polygon-disk area: closed-form cases", "[geometry]") {
  const std::vector<double> sx{-1, 1, 1, -1}, sy{-1, -1, 1, 1};
  // Disk inside the square: pi r^2.
  CHECK(pd::polygon_disk_intersection_area(sx.data(), sy.data(), 4, {0.1, -0.2}, 0.5) ==
        Approx(M_PI * 0.25).epsilon(1e-14));
  // Square inside the disk: the square.
  CHECK(pd::polygon_disk_intersection_area(sx.data(), sy.data(), 4, {0, 0}, 2.0) == Approx(4.0).epsilon(1e-14));
  // Disk centred on an edge midpoint, radius 0.5: half the disk.
  CHECK(pd::polygon_disk_intersection_area(sx.data(), sy.data(), 4, {1, 0}, 0.5) ==
        Approx(M_PI * 0.125).epsilon(1e-14));
  // Disk centred on a corner: a quarter.
  CHECK(pd::polygon_disk_intersection_area(sx.data(), sy.data(), 4, {1, 1}, 0.5) ==
        Approx(M_PI * 0.0625).epsilon(1e-14));
  // Disk cut by one edge at distance d from the centre: pi r^2 - segment.
  const double r = 0.8, d = 0.5;  // centre at x = 1 - d
  const double segment = r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
  CHECK(pd::polygon_disk_intersection_area(sx.data(), sy.data(), 4, {1 - d, 0}, r) ==
        Approx(M_PI * r * r - segment).epsilon(1e-13));
  // Disjoint.
  CHECK(pd::polygon_disk_intersection_area(sx.data(), sy.data(), 4, {3, 3}, 0.5) == 0.0);
  // Clockwise input gives the same (positive) area.
  const std::vector<double> cx{-1, -1, 1, 1}, cy{-1, 1, 1, -1};
  CHECK(pd::polygon_disk_intersection_area(cx.data(), cy.data(), 4, {1, 0}, 0.5) ==
        Approx(M_PI * 0.125).epsilon(1e-14));
}

TEST_CASE("polygon-disk area agrees with CGAL exact clipping on random polygons and disks", "[geometry]") {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int sides = 2048;  // inscribed/circumscribed bracket: relative gap ~ (pi/sides)^2 ~ 2.4e-6
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    // Random convex or star-shaped polygons with 3..7 vertices (triangles and quads of free meshes).
    const int n = 3 + trial % 5;
    const pd::Vec2 centre{0.3 * u(rng), 0.3 * u(rng)};
    std::vector<double> angles(n);
    for (auto& a : angles) a = M_PI * (u(rng) + 1.0);
    std::sort(angles.begin(), angles.end());
    std::vector<double> vx(n), vy(n);
    for (int k = 0; k < n; ++k) {
      const double radius = 0.4 + 0.6 * (0.5 * (u(rng) + 1));
      vx[k] = centre.x + radius * std::cos(angles[k]);
      vy[k] = centre.y + radius * std::sin(angles[k]);
    }
    if (std::fabs(pd::polygon_signed_area(vx.data(), vy.data(), n)) < 1e-3) continue;
    const pd::Vec2 c{u(rng), u(rng)};
    const double r = 0.2 + 0.8 * (0.5 * (u(rng) + 1));
    const double exact = pd::polygon_disk_intersection_area(vx.data(), vy.data(), n, c, r);
    const double inner = cgal_intersection_area(vx, vy, regular_polygon(c, r, sides));
    const double outer = cgal_intersection_area(vx, vy, regular_polygon(c, r / std::cos(M_PI / sides), sides));
    INFO("trial " << trial << " inner " << inner << " exact " << exact << " outer " << outer);
    CHECK(exact >= inner - 1e-12);
    CHECK(exact <= outer + 1e-12);
    ++checked;
  }
  CHECK(checked >= 30);
}

TEST_CASE("HHB factor, 004:(12)", "[geometry]") {
  CHECK(pd::hhb_factor(0.5, 1.0, 0.2) == 1.0);
  CHECK(pd::hhb_factor(1.0, 1.0, 0.2) == Approx(0.5));
  CHECK(pd::hhb_factor(1.05, 1.0, 0.2) == Approx(0.25));
  CHECK(pd::hhb_factor(1.2, 1.0, 0.2) == 0.0);
}

TEST_CASE("segment predicates and point in polygon", "[geometry]") {
  CHECK(pd::segments_intersect({0, 0}, {1, 1}, {0, 1}, {1, 0}));
  CHECK(pd::segments_cross_properly({0, 0}, {1, 1}, {0, 1}, {1, 0}));
  CHECK(pd::segments_intersect({0, 0}, {1, 0}, {1, 0}, {2, 1}));          // touching at an end
  CHECK_FALSE(pd::segments_cross_properly({0, 0}, {1, 0}, {1, 0}, {2, 1}));
  CHECK_FALSE(pd::segments_intersect({0, 0}, {1, 0}, {0, 1}, {1, 1}));
  const std::vector<double> sx{0, 1, 1, 0}, sy{0, 0, 1, 1};
  CHECK(pd::point_in_polygon({0.5, 0.5}, sx.data(), sy.data(), 4));
  CHECK_FALSE(pd::point_in_polygon({1.5, 0.5}, sx.data(), sy.data(), 4));
  CHECK(pd::point_segment_distance({0.5, 1.0}, {0, 0}, {1, 0}) == Approx(1.0));
  CHECK(pd::point_segment_distance({2.0, 0.0}, {0, 0}, {1, 0}) == Approx(1.0));
}

namespace {

// The exact area must lie between CGAL's exact clippings of the inscribed and
// the circumscribed 2048-gon (up to round-off relative to the cell's area).
void check_within_cgal_bracket(const std::vector<double>& vx, const std::vector<double>& vy, pd::Vec2 c,
                               double r) {
  const int sides = 2048;
  const double exact = pd::polygon_disk_intersection_area(vx.data(), vy.data(), vx.size(), c, r);
  const double inner = cgal_intersection_area(vx, vy, regular_polygon(c, r, sides));
  const double outer = cgal_intersection_area(vx, vy, regular_polygon(c, r / std::cos(M_PI / sides), sides));
  const double round_off = 1e-12 * std::fabs(pd::polygon_signed_area(vx.data(), vy.data(), vx.size()));
  INFO("inner " << inner << " exact " << exact << " outer " << outer);
  CHECK(exact >= inner - round_off);
  CHECK(exact <= outer + round_off);
}

// The square [cx - h, cx + h] x [cy - h, cy + h], counter-clockwise.
void square(double cx, double cy, double h, std::vector<double>& vx, std::vector<double>& vy) {
  vx = {cx - h, cx + h, cx + h, cx - h};
  vy = {cy - h, cy - h, cy + h, cy + h};
}

}  // namespace

// Cells that touch the circle at one point: the contact has no area, so the
// result is that of the cell with the point removed. References: closed forms
// (0, the cell's area, pi r^2) and CGAL's exact clipping bracket.
TEST_CASE("polygon-disk area at tangency: along an edge, at a vertex, inside and outside", "[geometry]") {
  std::vector<double> vx, vy;
  SECTION("a lattice square touching the horizon along its near edge (m + 1/2 offsets)") {
    // The configuration of a horizon factor m = 1.5, 2.5, ... on a lattice of
    // dx = 0.1 mm far from the origin: the square at offset (m + 1/2) dx along
    // x (and along y) touches the circle at the middle of its near edge.
    const double dx = 1e-4;
    for (double m : {1.5, 2.5, 3.5, 4.5, 7.5}) {
      for (int base : {0, 7, 37, 123}) {
        const pd::Vec2 c{(base + 0.5) * dx, (base + 3.5) * dx};
        const double offset = (m + 0.5) * dx;
        for (const pd::Vec2 at : {pd::Vec2{c.x + offset, c.y}, pd::Vec2{c.x - offset, c.y},
                                  pd::Vec2{c.x, c.y + offset}, pd::Vec2{c.x, c.y - offset}}) {
          square(at.x, at.y, 0.5 * dx, vx, vy);
          const double area = pd::polygon_disk_intersection_area(vx.data(), vy.data(), 4, c, m * dx);
          INFO("m = " << m << ", base " << base << ": area / dx^2 = " << area / (dx * dx));
          CHECK(area <= 1e-12 * dx * dx);
          check_within_cgal_bracket(vx, vy, c, m * dx);
        }
      }
    }
  }
  SECTION("an edge touching the circle away from its middle, at any angle") {
    // A unit square rotated by theta, placed so that its edge touches the unit
    // circle at the point of angle theta, the contact a fraction s along the edge.
    for (double theta : {0.0, 0.3, 1.0, 2.5, -2.0}) {
      for (double s : {0.5, 0.1, 0.9, 0.999}) {
        const pd::Vec2 normal{std::cos(theta), std::sin(theta)}, along{-normal.y, normal.x};
        vx.clear(), vy.clear();
        for (const auto& [u, v] : {std::pair{0.0, -s}, std::pair{1.0, -s}, std::pair{1.0, 1 - s}, std::pair{0.0, 1 - s}}) {
          vx.push_back(2.5 + (1 + u) * normal.x + v * along.x);
          vy.push_back(-1.0 + (1 + u) * normal.y + v * along.y);
        }
        const pd::Vec2 c{2.5, -1.0};
        INFO("theta " << theta << ", s " << s);
        CHECK(pd::polygon_disk_intersection_area(vx.data(), vy.data(), 4, c, 1.0) <= 1e-12);
        check_within_cgal_bracket(vx, vy, c, 1.0);
      }
    }
  }
  SECTION("a square touching the circle at a vertex, from outside") {
    const double r = 1.3, h = 0.25;
    for (double theta : {0.25 * M_PI, 0.7, 3.0}) {
      // Corner (-h, -h) of the square at the contact point, the square beyond it.
      const pd::Vec2 contact{r * std::cos(theta), r * std::sin(theta)};
      const pd::Vec2 centre{contact.x + h * (std::cos(theta) >= 0 ? 1 : -1),
                            contact.y + h * (std::sin(theta) >= 0 ? 1 : -1)};
      square(centre.x, centre.y, h, vx, vy);
      INFO("theta " << theta);
      CHECK(pd::polygon_disk_intersection_area(vx.data(), vy.data(), 4, {0, 0}, r) <= 1e-12);
      check_within_cgal_bracket(vx, vy, {0, 0}, r);
    }
  }
  SECTION("a square inscribed in the circle: all four vertices on it") {
    for (double r : {1.0, 3e-4}) {
      square(0.2, -0.1, r / std::sqrt(2.0), vx, vy);
      const double area = pd::polygon_disk_intersection_area(vx.data(), vy.data(), 4, {0.2, -0.1}, r);
      // The square itself; its vertices lie on the circle up to the round-off of r / sqrt 2.
      CHECK(area == Approx(2 * r * r).epsilon(1e-13));
      check_within_cgal_bracket(vx, vy, {0.2, -0.1}, r);
    }
  }
  SECTION("a disk inscribed in the square: tangent to all four edges from inside") {
    for (double r : {1.0, 5e-5}) {
      square(1.0, 2.0, r, vx, vy);
      const double area = pd::polygon_disk_intersection_area(vx.data(), vy.data(), 4, {1.0, 2.0}, r);
      CHECK(area == Approx(M_PI * r * r).epsilon(1e-14));
      check_within_cgal_bracket(vx, vy, {1.0, 2.0}, r);
    }
  }
  SECTION("a triangle with one vertex on the circle, the others inside or outside") {
    const pd::Vec2 c{0.0, 0.0};
    const double r = 1.0;
    // Vertex on the circle, both others inside: the whole triangle.
    vx = {1.0, 0.2, 0.3}, vy = {0.0, 0.5, -0.4};
    CHECK(pd::polygon_disk_intersection_area(vx.data(), vy.data(), 3, c, r) ==
          Approx(std::fabs(pd::polygon_signed_area(vx.data(), vy.data(), 3))).epsilon(1e-14));
    check_within_cgal_bracket(vx, vy, c, r);
    // Vertex on the circle, both others outside beyond the tangent: nothing.
    vx = {1.0, 1.5, 1.4}, vy = {0.0, -0.3, 0.6};
    CHECK(pd::polygon_disk_intersection_area(vx.data(), vy.data(), 3, c, r) <= 1e-15);
    check_within_cgal_bracket(vx, vy, c, r);
    // Vertex on the circle, one other inside, one outside.
    vx = {1.0, 0.0, 1.5}, vy = {0.0, 0.5, 1.0};
    check_within_cgal_bracket(vx, vy, c, r);
  }
}

TEST_CASE("distance comparisons by squares answer as the comparisons of hypot's values", "[geometry]") {
  // Reference: std::hypot compared directly, including limits a few ulps
  // either side of hypot's own value (where the squares alone could tie or
  // round the other way) and on cell corners on a lattice of steps, as a
  // family's cells meet a horizon.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-3e-3, 3e-3);
  std::size_t ties = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double dx = coordinate(rng), dy = coordinate(rng);
    const double exact = std::hypot(dx, dy);
    double limits[7] = {exact, coordinate(rng) + 3e-3, 0.5 * exact, 2 * exact, 0, 0, 0};
    limits[4] = std::nextafter(exact, 0.0), limits[5] = std::nextafter(exact, 1.0);
    limits[6] = std::nextafter(limits[4], 0.0);
    for (const double limit : limits) {
      ties += limit == exact;
      REQUIRE(pd::hypot_at_most(dx, dy, limit) == (std::hypot(dx, dy) <= limit));
    }
  }
  CHECK(ties == 20000);
  // Two lengths compared: equal ones (components swapped or mirrored), a few
  // ulps apart, far apart, zero and near the bottom of the range.
  for (int trial = 0; trial < 20000; ++trial) {
    const pd::Vec2 u{coordinate(rng), coordinate(rng)};
    const pd::Vec2 others[] = {{u.y, u.x},
                               {-u.x, u.y},
                               {std::nextafter(u.x, 1.0), u.y},
                               {u.x, std::nextafter(u.y, -1.0)},
                               {coordinate(rng), coordinate(rng)},
                               {0, 0},
                               {1e-160 * u.x, 1e-160 * u.y}};
    for (const pd::Vec2 v : others) {
      REQUIRE(pd::hypot_less(u, v) == (std::hypot(u.x, u.y) < std::hypot(v.x, v.y)));
      REQUIRE(pd::hypot_less(v, u) == (std::hypot(v.x, v.y) < std::hypot(u.x, u.y)));
    }
  }
  const pd::Vec2 tiny{3e-162, 4e-162}, tinier{4e-162, 2.9e-162};
  CHECK(pd::hypot_less(tinier, tiny));
  CHECK_FALSE(pd::hypot_less(tiny, tinier));
  CHECK_FALSE(pd::hypot_less({0, 0}, {0, 0}));
  // Cell corners at multiples of a quarter step from centres at multiples of
  // a half step, against horizons of whole steps: exact ties of length.
  const double step = 1e-3;
  std::size_t cells = 0, inside = 0;
  for (int i = -12; i <= 12; ++i)
    for (int j = -12; j <= 12; ++j) {
      const double cx = 0.5 * step * i + 0.0375, cy = 0.5 * step * j - 0.0125, h = 0.25 * step;
      const double vx[4] = {cx - h, cx + h, cx + h, cx - h}, vy[4] = {cy - h, cy - h, cy + h, cy + h};
      for (const double horizon : {1.5 * step, 3 * step, 0.75 * step}) {
        const pd::Vec2 from{0.0375, -0.0125};
        const double farthest = pd::polygon_max_vertex_distance(vx, vy, 4, from);
        REQUIRE(pd::polygon_within_distance(vx, vy, 4, from, horizon) == (farthest <= horizon));
        REQUIRE(pd::polygon_within_distance(vx, vy, 4, from, farthest) == true);
        REQUIRE(pd::polygon_within_distance(vx, vy, 4, from, std::nextafter(farthest, 0.0)) == false);
        ++cells, inside += farthest <= horizon;
      }
    }
  CHECK(inside > 0);
  CHECK(inside < cells);
}
