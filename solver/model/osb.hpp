#pragma once
// Ordinary state-based PD in 2D, in the form of Madenci & Oterkus (theory.md
// Sec. 5): the strain energy density of particle i is
//   W_i = a theta_i^2 + b delta sum_j s_ij^2 |xi_ij| V_ij,
// the first term from the dilatation theta_i (a per-particle pre-pass), the
// second a sum over bonds with the same form as the PMB energy. The Poisson
// ratio is the material's (not fixed by the model as in PMB).
//
// Thickness convention as in pmb.hpp: constants per unit thickness (h = 1),
// cell areas A_j [m^2] as neighbour volumes.
//
// What a broken bond leaves (model.osb_failure, theory.md Sec. 5.8) is a
// template parameter, so that the kernels' loops are compiled for one
// variant and test nothing per bond; `Osb` is the default variant.
#include <cmath>
#include <sstream>

#include "deformed_bond.hpp"
#include "material.hpp"
#include "model_summary.hpp"

namespace pd::solver {

// What a bond that breaks during a run takes with it (theory.md Sec. 5.8).
// Pre-cracked bonds are not in the family at all (no weight in m_i, theta_i
// or the force) under every variant.
enum class OsbFailure {
  force_and_dilatation,  // (a) its bond term, its dilatation term and its share of theta_i
  force_only,            // (b) its whole force (both terms); its share of theta_i stays
  bond_term_only,        // (c) its bond (distortion) term only; theta_i and the dilatation force keep it
};

struct OsbFailureEntry {
  OsbFailure failure;
  const char* name;  // model.osb_failure in the scene
};
inline constexpr OsbFailureEntry osb_failures[] = {
    {OsbFailure::force_and_dilatation, "force_and_dilatation"},
    {OsbFailure::force_only, "force_only"},
    {OsbFailure::bond_term_only, "bond_term_only"},
};

inline const char* to_string(OsbFailure failure) {
  for (const auto& f : osb_failures)
    if (f.failure == failure) return f.name;
  return "?";
}

// The constants of the 2D OSB model (the same for every failure variant).
struct OsbConstants {
  double bulk_modulus = 0;          // 2D kappa [Pa]: E/(2(1-nu)) plane stress, E/(2(1+nu)(1-2nu)) plane strain
  double shear_modulus = 0;         // mu = E/(2(1+nu)) [Pa]
  double dilatation_coefficient = 0;  // a = (kappa - 2 mu)/2 [Pa]
  // c_d = 4 b delta = 24 mu/(pi delta^3) [N/m^5]: the bond sum of W written as
  // 1/4 sum_j c_d s^2 E_ij, the PMB form (theory.md Sec. 5).
  double deviatoric_micromodulus_area = 0;
  double critical_stretch = 0;      // s0 [-]
  double poisson_ratio = 0;         // nu of the material
  double horizon = 0;               // delta [m]
};

template <OsbFailure Failure>
struct OsbWith {
  static constexpr const char* name = "osb";
  static constexpr const char* description = "ordinary state-based (2D)";

  // The failure variant as two facts the kernels read at compile time: does a
  // broken bond's term stay in theta_i (b, c), and does its dilatation force
  // stay (c)? Intact bonds are the same under all three.
  static constexpr OsbFailure failure = Failure;
  static constexpr bool broken_bond_in_dilatation = Failure != OsbFailure::force_and_dilatation;
  static constexpr bool broken_bond_keeps_dilatation_force = Failure == OsbFailure::bond_term_only;

  using Constants = OsbConstants;  // the same for every variant

  // theory.md Sec. 5 (Madenci & Oterkus 2014, the 2D constants a, b and the
  // critical stretch). The scene guarantees 0 < nu < 0.5.
  static Constants constants(const MaterialSpec& m, double horizon) {
    Constants k;
    const double E = m.youngs_modulus, nu = m.poisson_ratio;
    k.horizon = horizon;
    k.poisson_ratio = nu;
    k.shear_modulus = E / (2.0 * (1.0 + nu));
    k.bulk_modulus = m.plane == PlaneKind::stress ? E / (2.0 * (1.0 - nu)) : E / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu));
    k.dilatation_coefficient = 0.5 * (k.bulk_modulus - 2.0 * k.shear_modulus);
    k.deviatoric_micromodulus_area = 24.0 * k.shear_modulus / (M_PI * horizon * horizon * horizon);
    const double g = 6.0 * k.shear_modulus / M_PI + 16.0 * (k.bulk_modulus - 2.0 * k.shear_modulus) / (9.0 * M_PI * M_PI);
    k.critical_stretch = std::sqrt(m.fracture_energy / (g * horizon));
    return k;
  }

  // The deviatoric bond's stiffness [N/m^4], as pmb.hpp with c_d for c:
  // correction c_d E_ij / |xi|^2. `correction` is the distortion factor of
  // the surface correction (theory.md Sec. 5.7): the mean g_ij of the two
  // ends' factors for the force, i's own factor for W_i; the dilatation part
  // has its own factors D_ij in the dilatation weights (dilatation_volume).
  static double bond_stiffness(const Constants& k, double correction, double energy_weight, double rest_length) {
    return correction * k.deviatoric_micromodulus_area * energy_weight / (rest_length * rest_length);
  }

  static double dilatation_coefficient(const Constants& k) { return k.dilatation_coefficient; }

  // The dilatation theta_i is summed per particle before the bond forces
  // (neighbor_kernel.hpp, compute_dilatation).
  static constexpr bool has_pre_pass = true;

  // W_i holds its own end's share of each bond's energy, with i's own
  // distortion factor lambda_i S_i(n) (calibrated on i's family alone, so
  // that W_i is the classical energy density under homogeneous strains);
  // the force uses the mean g_ij, which makes it the derivative of the sum
  // of A_i W_i all the same (theory.md Sec. 5.7).
  static constexpr bool energy_at_own_end = true;

  // A deformed bond as the dilatation and the OSB force take it (theory.md
  // Sec. 5.2), formed with a single division: with q = 1/(|y| (|y| + |xi|)),
  //   e/|y| = (|y|^2 - |xi|^2) q   and   1/|y| = (|y| + |xi|) q,
  // and the length of y along the reference direction n = xi/|xi|, so that
  // Lambda_ij = (y . xi)/(|y| |xi|) = (y . n)/|y| needs no division of its
  // own. Divisions and square roots share one slow unit of the processor
  // (and take 10-20 times an addition on 8 float lanes): the sweeps' pairs
  // are bound by them (docs/performance.md, "OSB").
  template <class Real>
  struct Bond {
    Real along;                  // y . n [m]
    Real extension_over_length;  // e/|y| [-]
    Real inverse_length;         // 1/|y| [1/m]
  };
  // `direction_x`, `direction_y`: n = xi/|xi|.
  template <class Real>
  static Bond<Real> bond(const DeformedBond<Real>& b, Real direction_x, Real direction_y) {
    using simd::fmadd;
    const Real q = Real(1) / (b.length * b.sum);
    return {fmadd(b.yx, direction_x, b.yy * direction_y), b.excess * q, b.sum * q};
  }

  // The same from the reference bond xi and |xi| (the neighbour lists store
  // xi per bond; the lattice sweep keeps n per stencil offset).
  template <class Real>
  static Bond<Real> bond(const DeformedBond<Real>& b, Real xi_x, Real xi_y, Real rest_length) {
    const Real inverse_rest = Real(1) / rest_length;
    return bond(b, xi_x * inverse_rest, xi_y * inverse_rest);
  }

  // The bond's term of the dilatation sum theta_i = 2/m_i sum_j Lambda e_ij V_ij/|xi|,
  // with `volume_over_length` = V_ij / |xi| [m]: Lambda e V_ij/|xi| = (y . n)(e/|y|) V_ij/|xi|.
  template <class Real>
  static Real dilatation_term(Real volume_over_length, const Bond<Real>& t) {
    return t.along * t.extension_over_length * volume_over_length;
  }

  // The deviatoric force density on i is F y with F = k e / |y| (as PMB).
  template <class Real>
  static Real force_over_length(Real stiffness, const Bond<Real>& t) {
    return stiffness * t.extension_over_length;
  }

  // The dilatation force density on i along y: 4 a Lambda (V_ij/|xi|)
  // (theta_i/m_i + theta_j/m_j), divided by |y| (theory.md Sec. 5.2), that is
  // 4 a (y . n) (V_ij/|xi|) (theta_i/m_i + theta_j/m_j) / |y|^2;
  // `pressure_sum` = theta_i/m_i + theta_j/m_j [1/m^2].
  template <class Real>
  static Real dilatation_force_over_length(Real a, Real volume_over_length, Real pressure_sum, const Bond<Real>& t) {
    return Real(4) * a * volume_over_length * pressure_sum * t.along * (t.inverse_length * t.inverse_length);
  }

  // The same criterion as PMB: e <= s0 |xi| (theory.md Sec. 5).
  template <class Real>
  static auto holds(Real critical_extension, const DeformedBond<Real>& b) {
    return b.excess <= critical_extension * b.sum;
  }

  // The bond's part of W_i, 1/4 k e^2 [J/m^3]; the dilatation part
  // a theta_i^2 is added per particle (neighbor_kernel.hpp).
  static double energy_density(double stiffness, const DeformedBond<double>& b) {
    const double e = extension(b);
    return 0.25 * stiffness * e * e;
  }

  static ModelSummary summary(const Constants& k, PlaneKind plane) {
    ModelSummary s;
    s.name = name;
    s.description = std::string(description) + ", plane " + to_string(plane);
    s.horizon = k.horizon;
    s.critical_stretch = k.critical_stretch;
    s.model_poisson_ratio = k.poisson_ratio;
    s.constants = {{"bulk_modulus_2d_Pa", k.bulk_modulus},
                   {"shear_modulus_Pa", k.shear_modulus},
                   {"dilatation_coefficient_a_Pa", k.dilatation_coefficient},
                   {"deviatoric_micromodulus_times_thickness", k.deviatoric_micromodulus_area},
                   {"critical_stretch", k.critical_stretch},
                   {"horizon_m", k.horizon}};
    std::ostringstream text;
    text << "kappa = " << k.bulk_modulus << " Pa, mu = " << k.shear_modulus << " Pa, a = " << k.dilatation_coefficient
         << " Pa, c_d*h = " << k.deviatoric_micromodulus_area << " N/m^5, s0 = " << k.critical_stretch << ", horizon "
         << k.horizon << " m, broken bonds: " << to_string(Failure) << " (model.osb_failure)";
    s.constants_text = text.str();
    return s;
  }
};

using Osb = OsbWith<OsbFailure::force_and_dilatation>;  // today's default, variant (a)

// What a bond of length dx (neighbour cell dx^2) that breaks at its critical
// stretch under variant (a) adds to W_i where theta_i was 0, over the energy
// its bond term takes with it: (2 / (3 pi)) (a / mu) (dx / delta) on a
// whole family (theory.md Sec. 5.8, "Energy at a break"). Above 1, cracking
// adds energy (plane strain from nu = 0.483 at delta = 3 dx).
inline double osb_break_energy_ratio(const OsbConstants& k, double spacing) {
  return 2.0 / (3.0 * M_PI) * (k.dilatation_coefficient / k.shear_modulus) * (spacing / k.horizon);
}

}  // namespace pd::solver
