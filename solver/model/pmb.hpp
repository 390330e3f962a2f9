#pragma once
// Constants of the prototype microelastic brittle (PMB) bond-based model,
// theory.md Sec. 1 and [Peng, Chen, Bobaru 2023, Eqs. (1)-(9)].
//
// Thickness convention: the micromodulus c contains 1/h and the neighbour
// volume V_j = A_j h contains h, so h cancels in every force, energy density
// and time step. We therefore store c_area = c * h = c computed with h = 1 and
// use cell areas A_j [m^2] everywhere; h only scales reported forces [N] and
// energies [J] of the whole plate.
#include <cmath>

#include "scene.hpp"

namespace pd::solver {

struct PmbConstants {
  double micromodulus_area = 0;  // c * h [N/m^5 * m] = 9E/(pi delta^3) (plane stress)
  double critical_stretch = 0;   // s0 [-]
  double model_poisson_ratio = 0;  // 1/3 plane stress, 1/4 plane strain (fixed by the model)
  double horizon = 0;            // delta [m]
};

// Plane stress: c = 9E/(pi h delta^3), s0 = sqrt(4 pi G0 / (9 E delta)).
// Plane strain: c = 48E/(5 pi h delta^3), and from G0 = c h s0^2 delta^4 / 4 (the energy
// to break all bonds crossing a unit crack area, Ha & Bobaru 2010, the same relation
// that gives the plane-stress s0): s0 = sqrt(5 pi G0 / (12 E delta)).
inline PmbConstants pmb_constants(const MaterialSpec& m, double horizon) {
  PmbConstants k;
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

}  // namespace pd::solver
