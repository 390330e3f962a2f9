#pragma once
// The prototype microelastic brittle (PMB) bond-based model (theory.md
// Sec. 1; Silling & Askari 2005; Peng, Chen & Bobaru 2023, Eqs. (1)-(9)).
//
// Thickness convention: the micromodulus c contains 1/h and the neighbour
// volume V_j = A_j h contains h, so h cancels in every force, energy density
// and time step. We therefore store c_area = c * h = c computed with h = 1 and
// use cell areas A_j [m^2] everywhere; h only scales reported forces [N] and
// energies [J] of the whole plate.
#include <cmath>
#include <sstream>

#include "deformed_bond.hpp"
#include "material.hpp"
#include "model_summary.hpp"

namespace pd::solver {

struct Pmb {
  static constexpr const char* name = "pmb";
  static constexpr const char* description = "PMB bond-based";

  struct Constants {
    double micromodulus_area = 0;    // c * h [N/m^5] = 9E/(pi delta^3) (plane stress)
    double critical_stretch = 0;     // s0 [-]
    double model_poisson_ratio = 0;  // 1/3 plane stress, 1/4 plane strain (fixed by the model)
    double horizon = 0;              // delta [m]
  };

  // Plane stress: c = 9E/(pi h delta^3), s0 = sqrt(4 pi G0 / (9 E delta)).
  // Plane strain: c = 48E/(5 pi h delta^3), and from G0 = c h s0^2 delta^4 / 4 (the energy
  // to break all bonds crossing a unit crack area, Ha & Bobaru 2010, the same relation
  // that gives the plane-stress s0): s0 = sqrt(5 pi G0 / (12 E delta)). theory.md Sec. 1.
  static Constants constants(const MaterialSpec& m, double horizon) {
    Constants k;
    k.horizon = horizon;
    const double d3 = horizon * horizon * horizon;
    if (m.plane == PlaneKind::stress) {
      k.micromodulus_area = 9.0 * m.youngs_modulus / (M_PI * d3);
      k.critical_stretch = std::sqrt(4.0 * M_PI * m.fracture_energy / (9.0 * m.youngs_modulus * horizon));
      k.model_poisson_ratio = 1.0 / 3.0;
    } else {
      k.micromodulus_area = 48.0 * m.youngs_modulus / (5.0 * M_PI * d3);
      k.critical_stretch = std::sqrt(5.0 * M_PI * m.fracture_energy / (12.0 * m.youngs_modulus * horizon));
      k.model_poisson_ratio = 1.0 / 4.0;
    }
    return k;
  }

  // Stiffness k_ij [N/m^4] of a bond of rest length |xi| with quadrature weight
  // E_ij [m^3] (bond_weights.hpp) and surface-correction factor
  // `correction` = (lambda_i + lambda_j) / 2: correction c E_ij / |xi|^2, so that
  // W_i = 1/4 sum_j k_ij e_ij^2 = 1/4 sum_j correction c s_ij^2 E_ij (theory.md Sec. 2).
  static double bond_stiffness(const Constants& k, double correction, double energy_weight, double rest_length) {
    return correction * k.micromodulus_area * energy_weight / (rest_length * rest_length);
  }

  // ---- The pair law, written once for every kernel (theory.md Sec. 1): the
  // neighbour lists and energies (double), the lattice sweep (8 float lanes)
  // and the quasi-static problem (double, with its derivative).

  // A bond-based model needs no per-particle pass before the bond forces
  // (a state-based one sums e.g. the dilatation there: force_field.hpp).
  static constexpr bool has_pre_pass = false;

  // W_i holds half of each bond's energy 1/4 k_ij e^2 with the mean factor
  // g_ij (theory.md Sec. 3), not its own end's share.
  static constexpr bool energy_at_own_end = false;

  // The force density on i from the bond is F y, with F = k e / |y|
  // [N/m^4 / m] (Eq. (1) of Peng et al. 2023 with the stretch e/|xi| and
  // k = c E_ij / |xi|^2); returns F. The force on j is -F y (the pair's
  // other direction, with its own k).
  template <class Real>
  static Real force_over_length(Real stiffness, const DeformedBond<Real>& b) {
    return stiffness * b.excess / (b.length * b.sum);
  }

  // Whether the bond holds: e <= s0 |xi| (Eq. (8)), `critical_extension` =
  // s0 |xi| [m]. Tested on excess <= s0 |xi| (|y| + |xi|): no division.
  template <class Real>
  static auto holds(Real critical_extension, const DeformedBond<Real>& b) {
    return b.excess <= critical_extension * b.sum;
  }

  // The bond's part of the strain energy density of i, 1/4 k e^2 [J/m^3]
  // (W_i = 1/4 sum_j k_ij e_ij^2, theory.md Sec. 1). Also on float lanes:
  // the lattice sweep sums it during the force evaluation of an energy row.
  template <class Real>
  static Real energy_density(Real stiffness, const DeformedBond<Real>& b) {
    const Real e = extension(b);
    return Real(0.25f) * stiffness * e * e;
  }

  // The change (gx, gy) of the force density k e n (n = y / |y|) when eta
  // changes by (dx, dy): k [(n.d) n + (e / |y|)(d - (n.d) n)], the bond's
  // part of minus the Hessian of the energy (theory.md Sec. 4.8): the
  // quasi-static problem's lists (double) and the lattice sweep's tangent
  // product (8 float lanes, lattice_tangent.hpp). Written as
  // k [(1 - e/|y|) (y.d) / |y|^2 y + (e/|y|) d] with one division,
  // w = 1 / (|y|^2 (|y| + |xi|)): e/|y| = excess |y| w, 1/|y|^2 = (|y| + |xi|) w.
  template <class Real>
  static void force_change(Real stiffness, const DeformedBond<Real>& b, Real dx, Real dy, Real& gx, Real& gy) {
    const Real length_squared = b.yx * b.yx + b.yy * b.yy;
    const Real w = Real(1.0f) / (length_squared * b.sum);
    const Real ratio = b.excess * b.length * w;  // e / |y|
    const Real axial = stiffness * (Real(1.0f) - ratio) * (b.yx * dx + b.yy * dy) * b.sum * w;
    const Real geometric = stiffness * ratio;
    gx = axial * b.yx + geometric * dx;
    gy = axial * b.yy + geometric * dy;
  }

  static ModelSummary summary(const Constants& k, PlaneKind plane) {
    ModelSummary s;
    s.name = name;
    s.description = std::string(description) + ", plane " + to_string(plane);
    s.horizon = k.horizon;
    s.critical_stretch = k.critical_stretch;
    s.model_poisson_ratio = k.model_poisson_ratio;
    s.constants = {{"micromodulus_times_thickness", k.micromodulus_area},
                   {"critical_stretch", k.critical_stretch},
                   {"horizon_m", k.horizon}};
    std::ostringstream text;
    text << "c*h = " << k.micromodulus_area << " N/m^5, s0 = " << k.critical_stretch << ", horizon " << k.horizon
         << " m";
    s.constants_text = text.str();
    return s;
  }
};

}  // namespace pd::solver
