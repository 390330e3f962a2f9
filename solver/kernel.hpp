#pragma once
// The PMB force kernel (theory.md Sec. 1): each particle sums the forces of its
// own bonds, so the loop over particles runs in parallel without atomics and
// every particle's sum has a fixed order (results do not depend on the thread
// count). The effects are chosen at compile time: DamageOn = false has no
// bond-state array at all; the surface correction is folded into the bond
// stiffness (bonds.hpp), so it costs nothing here.
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "bonds.hpp"

namespace pd::solver {

// Current positions (reference + displacement) [m], velocities [m/s] and
// internal force densities [N/m^3], structure of arrays.
struct Kinematics {
  std::vector<double> x, y;    // current position
  std::vector<double> vx, vy;  // velocity
  std::vector<double> fx, fy;  // internal force density sum_j f_ij phi_ij V_j
};

// Bond state, only with damage.
struct DamageState {
  std::vector<std::uint8_t> intact;  // per directed bond: 1 = intact, 0 = broken (forever)
  std::vector<double> damage;        // D_i = 1 - sum intact phi A / sum phi A  [004:(10)]
};

struct DamageOn {};
struct DamageOff {};

// Fills k.fx, k.fy. With DamageOn, first breaks every bond whose stretch
// exceeds s0 (both directions of a bond see the same stretch bit for bit, so
// they break at the same step), and updates the damage index.
template <class DamageMode>
void compute_internal_forces(const BondTable& bonds, Kinematics& k, DamageState* state) {
  const std::int64_t n = static_cast<std::int64_t>(bonds.particle_count);
  const double* x = k.x.data();
  const double* y = k.y.data();
  const std::uint32_t* neighbor = bonds.neighbor.data();
  const double* rest = bonds.rest_length.data();
  const double* stiffness = bonds.stiffness.data();
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double fx = 0, fy = 0, intact_area = 0;
    const double xi = x[i], yi = y[i];
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      if constexpr (std::is_same_v<DamageMode, DamageOn>) {
        if (!state->intact[b]) continue;
      }
      const auto j = neighbor[b];
      const double dx = x[j] - xi, dy = y[j] - yi;
      const double length = std::sqrt(dx * dx + dy * dy);
      const double extension = length - rest[b];
      if constexpr (std::is_same_v<DamageMode, DamageOn>) {
        if (extension > bonds.critical_extension[b]) {
          state->intact[b] = 0;  // irreversible [004:(8),(9)]
          continue;
        }
        intact_area += static_cast<double>(bonds.damage_weight[b]);
      }
      const double f = stiffness[b] * extension / length;
      fx += f * dx;
      fy += f * dy;
    }
    k.fx[i] = fx;
    k.fy[i] = fy;
    if constexpr (std::is_same_v<DamageMode, DamageOn>) {
      state->damage[i] = 1.0 - intact_area / bonds.family_area[i];
    }
  }
}

// Strain energy density W_i [J/m^3] of every particle (theory.md Sec. 1,
// including the surface-correction factor): W_i = 1/4 sum_j k_ij e_ij^2 over intact bonds.
inline void compute_strain_energy_density(const BondTable& bonds, const Kinematics& k,
                                          const DamageState* state, std::vector<double>& energy_density) {
  const std::int64_t n = static_cast<std::int64_t>(bonds.particle_count);
  energy_density.resize(bonds.particle_count);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double w = 0;
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      if (state && !state->intact[b]) continue;
      const auto j = bonds.neighbor[b];
      const double extension = std::hypot(k.x[j] - k.x[i], k.y[j] - k.y[i]) - bonds.rest_length[b];
      w += bonds.stiffness[b] * extension * extension;
    }
    energy_density[i] = 0.25 * w;
  }
}

}  // namespace pd::solver
