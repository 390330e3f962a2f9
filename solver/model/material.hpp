#pragma once
// The material as the scene gives it (SI units). The models derive their
// constants from it (model/pmb.hpp).
namespace pd::solver {

enum class PlaneKind { stress, strain };

inline const char* to_string(PlaneKind plane) { return plane == PlaneKind::stress ? "stress" : "strain"; }

struct MaterialSpec {
  double youngs_modulus = 0;   // E [Pa]
  double density = 0;          // rho [kg/m^3]
  double fracture_energy = 0;  // G0 [J/m^2]
  double thickness = 1;        // h [m]
  PlaneKind plane = PlaneKind::stress;
  double poisson_ratio = -1;   // of the real material, for reporting only; -1 = not given
};

}  // namespace pd::solver
