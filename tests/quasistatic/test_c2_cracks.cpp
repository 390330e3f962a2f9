// Case C2 (docs/validation.md): quasi-static fracture of the C1 plate; the
// cracks that start at the hole are counted by hole_cracks.hpp.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "c2_fracture.hpp"
#include "hole_cracks.hpp"
#include "lattice.hpp"
#include "plate_grid.hpp"

using namespace pd::validation;

// Reference: damage fields made by hand, with a known number of radial cracks.
TEST_CASE("cracks at a hole are counted from the damage field", "[quasistatic][c2]") {
  const auto plate = pd::make_rectangle_lattice(20e-3, 20e-3, 2e-4, 6e-4, pd::Quadrature::full);
  const double cx = 0.01, cy = 0.01, radius = 0.004;
  HoleRing ring{cx, cy, radius, 3e-4, 1.2e-3, 0.3, 3e-4};
  const auto count_with = [&](const std::vector<double>& directions_degrees, double damage_elsewhere) {
    std::vector<double> damage(plate.size(), damage_elsewhere), first(plate.size(), -1.0);
    for (std::size_t i = 0; i < plate.size(); ++i) {
      const double dx = plate.x[i] - cx, dy = plate.y[i] - cy;
      for (double a : directions_degrees) {
        const double t = a * M_PI / 180;
        const double along = dx * std::cos(t) + dy * std::sin(t), across = -dx * std::sin(t) + dy * std::cos(t);
        if (along > radius && std::fabs(across) < 2.1e-4) {
          damage[i] = 0.5;
          first[i] = 1e-5 * (1 + a / 360);  // each crack its own initiation load
        }
      }
    }
    return cracks_at_hole(plate, damage, first, ring);
  };
  CHECK(count_with({90, 270}, 0.0).size() == 2);
  const auto four = count_with({75, 105, 255, 285}, 0.1);  // damage below the threshold elsewhere
  REQUIRE(four.size() == 4);
  for (const auto& crack : four) CHECK(crack.initiation_load_factor > 1e-5);
  CHECK(count_with({}, 0.2).empty());
  // One crack at 90 degrees: its direction and initiation load.
  const auto one = count_with({90}, 0.0);
  REQUIRE(one.size() == 1);
  CHECK(one[0].angle_degrees == Approx(90).margin(2));
  CHECK(one[0].initiation_load_factor == Approx(1.25e-5));
}

namespace {
// C2 at the CI resolution of the tests below: dx = 0.2 mm, m = 4 unless
// stated; steps of 0.01 mm per edge up to 0.04 mm, then 0.001 mm; NCG tolerance 1e-5.
C2Result run_c2_at_ci_resolution(pd::GridKind grid, std::string& log_text, double horizon_factor = 4,
                                  double stop_reaction_fraction = 0.05) {
  pd::PlateGeometry geometry;
  const auto particles =
      make_plate_grid({PD_C1_GEOMETRY, grid, 2e-4, horizon_factor * 2e-4, pd::Quadrature::analytic}, &geometry);
  C2Options options;
  options.first_steps = 4;
  options.small_increment = 1e-6;
  options.max_small_steps = 40;
  options.tolerance = 1e-5;
  options.stop_reaction_fraction = stop_reaction_fraction;
  std::ostringstream log;
  auto r = run_c2(particles, 0.01, 0.01, 0.004, C1Material{}, options, log);
  log_text = log.str();
  return r;
}
}  // namespace

// Reference: [Peng, Chen, Bobaru 2023, Sec. 4.2, Fig. 6]: on the NB-NUG grid two
// cracks start at the top and bottom of the hole and grow straight.
// CI resolution: dx = 0.2 mm, m = 4 (delta = 0.8 mm), 8,700 particles; steps of
// 0.01 mm per edge up to 0.04 mm, then 0.001 mm; NCG tolerance 1e-5.
TEST_CASE("C2: the NB-NUG grid gives two cracks, at the top and bottom of the hole", "[quasistatic][c2]") {
  std::string log;
  const auto r = run_c2_at_ci_resolution(pd::GridKind::nbnug, log);
  INFO(log);
  CHECK_THAT(r.stop_reason, Catch::StartsWith("separated"));
  REQUIRE(r.cracks.size() == 2);
  // Straight up and straight down (within 10 degrees), initiating at the same load.
  std::vector<double> angles{r.cracks[0].angle_degrees, r.cracks[1].angle_degrees};
  std::sort(angles.begin(), angles.end());
  CHECK(angles[0] == Approx(-90).margin(10));
  CHECK(angles[1] == Approx(90).margin(10));
  CHECK(r.cracks[0].initiation_load_factor == Approx(r.cracks[1].initiation_load_factor).epsilon(0.03));
}

// Reference: [Peng, Chen, Bobaru 2023, Sec. 4.2]: on the uniform grid the upper
// and lower cracks start at the same load (symmetry of geometry, grid and
// loading). The paper's four cracks (dx = 0.05 mm, delta = 0.2 mm) start at the
// two corners that end the flat top (and bottom) step of the zig-zag hole
// boundary, 4.5 horizons apart there; here (dx = 0.2 mm, m = 4) they are 2
// horizons apart and one crack forms between them (at dx = 0.1 mm, 3 horizons:
// two branches that merge within a horizon; docs/validation.md), so the count
// asserted here is 2: a change of the solver or the grids that made the
// zig-zag matter at this horizon would show up as a different count.
TEST_CASE("C2: the uniform grid at CI resolution gives two symmetric cracks", "[quasistatic][c2]") {
  std::string log;
  const auto r = run_c2_at_ci_resolution(pd::GridKind::uniform, log);
  INFO(log);
  CHECK_THAT(r.stop_reason, Catch::StartsWith("separated"));
  REQUIRE(r.cracks.size() == 2);
  CHECK(r.cracks[0].angle_degrees == Approx(-r.cracks[1].angle_degrees).margin(5));
  CHECK(r.cracks[0].initiation_load_factor == Approx(r.cracks[1].initiation_load_factor).epsilon(1e-9));
}

// Reference: [Peng, Chen, Bobaru 2023, Sec. 4.2, Fig. 6]: four cracks on the
// uniform grid, from the corners of the zig-zag hole boundary. What decides
// it is how many horizons apart the two corners that end the flat top step
// are (docs/validation.md, "C2: the uniform grid's four cracks"): 4.5 on the
// paper's grid (dx = 0.05 mm, m = 4). Here dx = 0.2 mm with m = 2 puts them 4
// horizons apart (the flat step spans x = 9.2 to 10.8 mm, delta = 0.4 mm), at
// a CI cost: measured 4 cracks at +-80 and +-100 degrees, all starting at
// u = 0.055 mm. (m = 2 is not the paper's horizon factor; the C2 comparison
// itself stays at m = 4, where this grid gives 2.) With two cells per
// horizon the last few bonds where the cracks meet the free edges hold on
// after the cracks have cut the plate: 7 % of the peak reaction at 0.08 mm
// (2.8 % with the scalar surface correction of earlier versions; they give way
// at 0.12 mm); "separated" is taken here as below 10 % of the peak.
TEST_CASE("C2: the uniform grid gives four cracks when its zig-zag corners are 4 horizons apart",
          "[quasistatic][c2]") {
  std::string log;
  const auto r = run_c2_at_ci_resolution(pd::GridKind::uniform, log, 2, 0.1);
  INFO(log);
  CHECK_THAT(r.stop_reason, Catch::StartsWith("separated"));
  REQUIRE(r.cracks.size() == 4);
  std::vector<double> angles;
  for (const auto& crack : r.cracks) {
    angles.push_back(crack.angle_degrees);
    CHECK(crack.initiation_load_factor == Approx(r.cracks[0].initiation_load_factor).epsilon(1e-9));
  }
  std::sort(angles.begin(), angles.end());
  // Two on each side of the hole, mirror images about both axes, away from the top and bottom.
  CHECK(angles[0] == Approx(-angles[3]).margin(5));
  CHECK(angles[1] == Approx(-angles[2]).margin(5));
  CHECK(angles[0] + angles[1] == Approx(-180).margin(5));
  CHECK(std::fabs(angles[2] - 90) > 5);
}

// The same setting for the NB-NUG grid (dx = 0.2 mm, m = 2), so that the two
// grids are compared where the uniform grid gives four cracks: the NB-NUG
// grid's smooth hole boundary gives two, one above and one below the hole
// [Peng, Chen, Bobaru 2023, Sec. 4.2, Fig. 6]. At this coarse horizon (two
// cells) they need not start at the same load or grow exactly vertically.
TEST_CASE("C2: at the uniform grid's four-crack setting the NB-NUG grid gives two", "[quasistatic][c2]") {
  std::string log;
  const auto r = run_c2_at_ci_resolution(pd::GridKind::nbnug, log, 2);
  INFO(log);
  CHECK_THAT(r.stop_reason, Catch::StartsWith("separated"));
  REQUIRE(r.cracks.size() == 2);
  CHECK(r.cracks[0].angle_degrees * r.cracks[1].angle_degrees < 0);  // one above, one below
  for (const auto& crack : r.cracks) CHECK(std::fabs(std::fabs(crack.angle_degrees) - 90) < 30);
}
