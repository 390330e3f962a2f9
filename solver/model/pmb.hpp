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

#include "material.hpp"
#include "model_summary.hpp"

namespace pd::solver {

struct Pmb {
  static constexpr const char* name = "pmb";
  static constexpr const char* description = "PMB bond-based";

  struct Constants {
    double micromodulus_area = 0;    // c * h [N/m^5 * m] = 9E/(pi delta^3) (plane stress)
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
