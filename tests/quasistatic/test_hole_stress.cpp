// Stresses from the FEM reference (validation/hole_stress.hpp): the gradient
// of the quadratic elements and the plane-stress hoop component.
#include <catch2/catch.hpp>
#include <cmath>

#include "calculix.hpp"
#include "fem_interpolation.hpp"
#include "fem_mesh.hpp"
#include "hole_stress.hpp"
#include "support.hpp"

using namespace pd::validation;

// Reference: a field linear in x and y is reproduced exactly by the
// isoparametric 6-node triangles (curved ones at the hole too), so its
// gradient must come out exact at any point.
TEST_CASE("the FEM gradient of a linear nodal field is exact on curved elements too", "[quasistatic][fem]") {
  const auto folder = pd::quasistatic::test::fresh_folder("fem_gradient");
  pd::PlateGeometry plate;
  make_plate_grid({PD_C1_GEOMETRY, pd::GridKind::uniform, 1e-3, 3e-3, pd::Quadrature::full}, &plate);
  FemMeshOptions options;
  options.hole_size = 5e-4;
  const auto mesh = write_fem_mesh(plate, options, folder + "/mesh.inp");
  std::vector<double> field(mesh.x.size());
  for (std::size_t k = 0; k < mesh.x.size(); ++k) field[k] = 3e-4 * mesh.x[k] - 7e-5 * mesh.y[k] + 1e-6;
  const FemInterpolator interpolate(mesh);
  double worst = 0;
  int points = 0;
  // A ring just outside the hole (radius 4 mm, centre (10, 10) mm) and a row across the plate.
  for (int k = 0; k < 72; ++k, ++points) {
    const double t = 2 * M_PI * k / 72, r = 4.0001e-3;
    const auto g = interpolate.gradient_at(field, interpolate.locate(0.01 + r * std::cos(t), 0.01 + r * std::sin(t)));
    worst = std::max({worst, std::fabs(g[0] - 3e-4), std::fabs(g[1] + 7e-5)});
  }
  for (int k = 0; k <= 40; ++k, ++points) {
    const auto g = interpolate.gradient_at(field, interpolate.locate(0.5e-3 * k, 2.3e-3));
    worst = std::max({worst, std::fabs(g[0] - 3e-4), std::fabs(g[1] + 7e-5)});
  }
  INFO("largest error " << worst << " at " << points << " points");
  CHECK(worst < 1e-9 * 3e-4);
}

// Reference: Kirsch's solution for a circular hole of radius a in an infinite
// plate under remote uniaxial stress S along x (e.g. Timoshenko and Goodier,
// Theory of Elasticity, 3rd ed., Sec. 35):
//   sigma_thetatheta(r, theta) = S/2 (1 + a^2/r^2) - S/2 (1 + 3 a^4/r^4) cos(2 theta),
// i.e. 3 S at (a, 90 deg), -S at (a, 0), 1.21875 S at (2a, 90 deg). The plate
// is 2000 hole radii wide (finite-width effect below 1e-5) and pulled by
// u_x = -/+ U on its edges, S = E 2U / L. Measured (h = a / 5 at the hole):
// 3.004, 3.003, -1.003 at 90, 270 and 0 deg, 0.966 at 45 deg where the edge
// stress changes fastest along the curve, 1.223 and 1.110 inside; bound 0.04 S.
TEST_CASE("the FEM hoop stress at a tiny hole follows Kirsch's solution", "[quasistatic][fem]") {
  const auto folder = pd::quasistatic::test::fresh_folder("kirsch");
  const auto fem = pd::quasistatic::test::tiny_hole_fem(folder, 0.002e-3, "kirsch");
  const auto& mesh = fem.mesh;
  const auto& solution = fem.solution;
  const auto& load = fem.load;
  const double S = load.youngs_modulus * 2e-7 / 0.02, a = 0.01e-3, nu = load.poisson_ratio;
  const FemInterpolator interpolate(mesh);
  const auto hoop = [&](double r, double theta) {
    const auto g = fem_displacement_gradient(interpolate, solution, 0.01 + r * std::cos(theta), 0.01 + r * std::sin(theta));
    return hoop_component(plane_stress(g, load.youngs_modulus, nu), theta) / S;
  };
  const auto kirsch = [&](double r, double theta) {
    return 0.5 * (1 + a * a / (r * r)) - 0.5 * (1 + 3 * std::pow(a / r, 4)) * std::cos(2 * theta);
  };
  for (const auto& [r, theta] : {std::pair{a, M_PI / 2}, std::pair{a, 3 * M_PI / 2}, std::pair{a, 0.0},
                                 std::pair{a, M_PI / 4}, std::pair{2 * a, M_PI / 2}, std::pair{1.5 * a, M_PI / 3}}) {
    INFO("r / a = " << r / a << ", theta = " << theta * 180 / M_PI << " deg: FEM " << hoop(r, theta) << " S, Kirsch "
                    << kirsch(r, theta) << " S");
    CHECK(std::fabs(hoop(r, theta) - kirsch(r, theta)) < 0.04);
  }
  // The far field: uniaxial, sigma_thetatheta = S sin^2(theta).
  CHECK(hoop(5e-3, M_PI / 3) == Approx(0.75).epsilon(1e-3));
}
