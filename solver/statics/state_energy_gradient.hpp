#pragma once
// The exact gradient of the discrete OSB strain energy (theory.md Sec. 5.6),
// for the quasi-static solver: minus the derivative of
//   Pi = h sum_i A_i W_i,   W_i = a theta_i^2 + 1/4 sum_j k^W_ij e_ij^2,
//   theta_i = (2 / m_i) sum_j w_ij Lambda_ij e_ij,   w_ij = V_ij / |xi_ij|,
// each particle with its own family weights (osb.hpp, theory.md Sec. 5.2),
// divided by h A_i. It runs on the energy table of energy_bonds.hpp, which
// holds both directions of every pair: per bond i -> j the symmetrised
// stiffness k^E_ij (the bond terms of W_i and W_j together), i's own w_ij
// and the partner's A_j w_ji / A_i. Unlike the dynamic force
// (compute_state_forces), the direction cosine Lambda is differentiated too,
// and the two ends' dilatation terms carry their own weights: on non-uniform
// grids the dynamic force is not the gradient of any energy, and a minimiser
// needs one. The dynamic kernels are not touched.
#include <cstdint>

#include "bond_table.hpp"
#include "deformed_bond.hpp"
#include "particle_state.hpp"

namespace pd::solver {

// k.fx, k.fy = -dPi/du_i / (h A_i) [N/m^3] at k.ux, k.uy, after the pre-pass
// (compute_dilatation on the same table) has left pressure[i] = theta_i / m_i.
// d(Lambda e)/dy = Lambda y/|y| + (e/|y|) (n - Lambda y/|y|) with n = xi/|xi|:
// the dynamic force's direction Lambda y/|y| plus a term of the order of the
// stretch times the bond's rotation. `intact`: the bonds' states; a broken
// bond's stiffness (and, under variant (a), its weights) are already 0 in the
// table, and under variant (b) its dilatation force is dropped here as in the
// dynamic force (theory.md Sec. 5.8; that variant has no energy).
template <class Model>
void compute_state_energy_forces(const BondTable& t, Kinematics& k, const std::uint8_t* intact,
                                 const double* pressure, double dilatation_coefficient) {
  static_assert(Model::has_pre_pass, "for state-based models");
  const std::int64_t n = static_cast<std::int64_t>(t.particle_count);
  const double a = dilatation_coefficient;
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double fx = 0, fy = 0;
    const double uxi = k.ux[i], uyi = k.uy[i], pi = pressure[i];
    for (auto b = t.offsets[i]; b < t.offsets[i + 1]; ++b) {
      const auto j = t.neighbor[b];
      const double xi_x = t.xi_x[b], xi_y = t.xi_y[b], rest = t.rest_length[b];
      const auto bond = deformed_bond(xi_x, xi_y, rest, k.ux[j] - uxi, k.uy[j] - uyi);
      const auto terms = Model::bond(bond, xi_x, xi_y, rest);
      // dW/de of both ends' bond terms: k^E e along y/|y|.
      const double bond_part = Model::force_over_length(t.stiffness[b], terms);
      // Both ends' dilatation terms, each with its own weight: 4 a (theta_i/m_i w_ij
      // + theta_j/m_j A_j w_ji / A_i), times d(Lambda e)/dy.
      double dilatation = 4.0 * a * (pi * t.volume_over_length[b] + pressure[j] * t.partner_volume_over_length[b]);
      if constexpr (!Model::broken_bond_keeps_dilatation_force && Model::broken_bond_in_dilatation)
        dilatation *= static_cast<double>(intact[b]);  // variant (b): no force from a broken bond
      const double lambda = terms.along * terms.inverse_length;          // Lambda
      const double tilt = terms.extension_over_length;                   // e/|y|
      const double along_y = lambda * (1.0 - tilt) * terms.inverse_length;  // per unit y
      const double along_n = tilt;                                       // per unit n
      const double inverse_rest = 1.0 / rest;
      fx += (bond_part + dilatation * along_y) * bond.yx + dilatation * along_n * xi_x * inverse_rest;
      fy += (bond_part + dilatation * along_y) * bond.yy + dilatation * along_n * xi_y * inverse_rest;
    }
    k.fx[i] = fx;
    k.fy[i] = fy;
  }
}

}  // namespace pd::solver
