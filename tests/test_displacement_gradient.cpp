// The least-squares displacement gradient of a family (docs/theory.md Sec. 10.1).
// Reference: analytic fields. For u = u0 + G x the estimate equals G exactly
// at every particle, edges and corners included (one-sided families); for a
// quadratic field it equals the exact gradient at a particle whose family is
// point-symmetric (the second-order terms cancel), and not at a corner.
#include <catch2/catch.hpp>
#include <cmath>

#include "displacement_gradient.hpp"
#include "lattice.hpp"

namespace {
const double dx = 1e-4;  // [m]
const auto lattice = pd::make_rectangle_lattice(20 * dx, 14 * dx, dx, 3 * dx, pd::Quadrature::analytic);
}  // namespace

TEST_CASE("the family gradient of a linear displacement field is exact everywhere", "[gradient]") {
  const double g[2][2] = {{2e-4, -3e-4}, {5e-5, -1e-4}};  // d u_a / d x_b
  std::vector<double> ux(lattice.size()), uy(lattice.size());
  for (std::size_t i = 0; i < lattice.size(); ++i) {
    ux[i] = 1e-6 + g[0][0] * lattice.x[i] + g[0][1] * lattice.y[i];
    uy[i] = -2e-6 + g[1][0] * lattice.x[i] + g[1][1] * lattice.y[i];
  }
  const auto gradients = pd::family_displacement_gradients(lattice, ux, uy);
  double worst = 0;
  for (const auto& e : gradients)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) worst = std::max(worst, std::fabs(e.du_dx[a][b] - g[a][b]));
  INFO("largest error " << worst << " over " << lattice.size() << " particles");
  CHECK(worst < 1e-10 * 3e-4);
}

TEST_CASE("the family gradient of a quadratic field is exact only for a symmetric family", "[gradient]") {
  // u_x = c x^2, u_y = c x y: du_x/dx = 2 c x, du_y/dx = c y, du_y/dy = c x.
  const double c = 1.0;  // [1/m]
  std::vector<double> ux(lattice.size()), uy(lattice.size());
  for (std::size_t i = 0; i < lattice.size(); ++i) {
    ux[i] = c * lattice.x[i] * lattice.x[i];
    uy[i] = c * lattice.x[i] * lattice.y[i];
  }
  std::size_t centre = 0, corner = 0;
  for (std::size_t i = 0; i < lattice.size(); ++i) {
    if (std::hypot(lattice.x[i] - 10.5 * dx, lattice.y[i] - 7.5 * dx) < 1e-9) centre = i;
    if (std::hypot(lattice.x[i] - 0.5 * dx, lattice.y[i] - 0.5 * dx) < 1e-9) corner = i;
  }
  const auto at_centre = pd::family_displacement_gradient(lattice, ux, uy, centre);
  const double x = lattice.x[centre], y = lattice.y[centre];
  CHECK(at_centre.du_dx[0][0] == Approx(2 * c * x).epsilon(1e-9));
  CHECK(at_centre.du_dx[1][0] == Approx(c * y).epsilon(1e-9));
  CHECK(at_centre.du_dx[1][1] == Approx(c * x).epsilon(1e-9));
  CHECK(std::fabs(at_centre.du_dx[0][1]) < 1e-12);
  // At the corner the family is one-sided: the error is of order c delta.
  const auto at_corner = pd::family_displacement_gradient(lattice, ux, uy, corner);
  CHECK(std::fabs(at_corner.du_dx[0][0] - 2 * c * lattice.x[corner]) > 0.1 * c * dx);
}
