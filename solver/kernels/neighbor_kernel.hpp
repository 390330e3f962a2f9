#pragma once
// The PMB force kernel (theory.md Sec. 1): each particle sums the forces of its
// own bonds, so the loop over particles runs in parallel without atomics and
// every particle's sum has a fixed order (results do not depend on the thread
// count). The effects are chosen at compile time: with DamageOff there is no
// bond-state array at all; the surface correction is folded into the bond
// stiffness (bonds.hpp), so it costs nothing here.
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "bond_table.hpp"
#include "effects.hpp"
#include "particle_state.hpp"

namespace pd::solver {

// Fills k.fx, k.fy with the internal force densities. With DamageOn each bond
// whose stretch exceeds s0 breaks before it is summed (both directions of a
// bond see the same stretch bit for bit, so they break at the same step), and
// the damage index is updated.
// Same for the listed particles only (`list` of `count` indices; nullptr =
// all particles): the general neighbour-list path beside the lattice kernel.
// `intact`: per bond of `bonds`; `damage`: per particle (both unused with DamageOff).
template <class DamageMode>
void compute_internal_forces_of(const BondTable& bonds, Kinematics& k, std::uint8_t* intact, double* damage,
                                const std::uint32_t* list, std::int64_t count) {
  const double* x = k.x.data();
  const double* y = k.y.data();
  const std::uint32_t* neighbor = bonds.neighbor.data();
  const double* rest = bonds.rest_length.data();
  const double* stiffness = bonds.stiffness.data();
  const double critical_stretch = bonds.critical_stretch;
  const float* damage_weight = bonds.damage_weight.data();
#pragma omp parallel for schedule(static)
  for (std::int64_t index = 0; index < count; ++index) {
    const std::int64_t i = list ? static_cast<std::int64_t>(list[index]) : index;
    double fx = 0, fy = 0, intact_area = 0;
    const double xi = x[i], yi = y[i];
    const auto first = bonds.offsets[i], last = bonds.offsets[i + 1];
    // Branch-free body, so that the compiler can vectorise it (SIMD lanes sum in a
    // fixed order: results stay independent of the thread count).
#pragma omp simd reduction(+ : fx, fy, intact_area)
    for (auto b = first; b < last; ++b) {
      const auto j = neighbor[b];
      const double dx = x[j] - xi, dy = y[j] - yi;
      const double length = std::sqrt(dx * dx + dy * dy);
      const double extension = length - rest[b];
      double f = stiffness[b] * extension / length;
      if constexpr (DamageMode::enabled) {
        // A bond breaks for good when its stretch exceeds s0 [004:(8),(9)]; broken bonds
        // are still evaluated (they are few) but weighted by 0.
        const std::uint8_t holds = intact[b] & static_cast<std::uint8_t>(extension <= critical_stretch * rest[b]);
        intact[b] = holds;
        const double weight = static_cast<double>(holds);
        f *= weight;
        intact_area += weight * static_cast<double>(damage_weight[b]);
      }
      fx += f * dx;
      fy += f * dy;
    }
    k.fx[i] = fx;
    k.fy[i] = fy;
    if constexpr (DamageMode::enabled) {
      // The SIMD sum may differ from family_area in the last bits: a particle with
      // all bonds intact must read exactly 0 (one broken bond weighs far more than 1e-9).
      const double damage_index = 1.0 - intact_area / bonds.family_area[i];
      damage[i] = damage_index < 1e-9 ? 0.0 : damage_index;
    }
  }
}

// Strain energy density W_i [J/m^3] of every particle (theory.md Sec. 1,
// including the surface-correction factor): W_i = 1/4 sum_j k_ij e_ij^2 over intact bonds.
// `intact`: per bond of `bonds`, or null without damage.
inline void compute_strain_energy_density(const BondTable& bonds, const Kinematics& k, const std::uint8_t* intact,
                                          std::vector<double>& energy_density) {
  const std::int64_t n = static_cast<std::int64_t>(bonds.particle_count);
  energy_density.resize(bonds.particle_count);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double w = 0;
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      if (intact && !intact[b]) continue;
      const auto j = bonds.neighbor[b];
      const double dx = k.x[j] - k.x[i], dy = k.y[j] - k.y[i];
      const double extension = std::sqrt(dx * dx + dy * dy) - bonds.rest_length[b];
      w += bonds.stiffness[b] * extension * extension;
    }
    energy_density[i] = 0.25 * w;
  }
}

}  // namespace pd::solver
