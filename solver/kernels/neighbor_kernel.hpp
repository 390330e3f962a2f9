#pragma once
// The neighbour-list kernels (theory.md Sec. 1): each particle sums the
// forces of its own bonds from the bond table, so the loop over particles
// runs in parallel without atomics and every particle's sum has a fixed
// order (results do not depend on the thread count). The force law is the
// model's (Model::force_over_length, Model::holds); the effects are chosen at
// compile time: with DamageOff there is no bond-state array at all. The
// surface correction is folded into the bond stiffness (bond_setup.hpp).
#include <cmath>
#include <cstdint>
#include <vector>

#include "bond_table.hpp"
#include "deformed_bond.hpp"
#include "effects.hpp"
#include "particle_state.hpp"

namespace pd::solver {

// D_i = 1 - (intact share of the family) [Peng et al. 2023, Eq. (10)]. The
// SIMD sum of the intact weights may differ from the family area in the last
// bits: a particle with every bond intact must read exactly 0 (one broken
// bond weighs far more than 1e-9). A particle without bonds (pd-mesh warns
// of one: a cell cut off by holes) has none to break: 0, not 0/0.
inline double damage_index(double intact_area, double family_area) {
  if (!(family_area > 0)) return 0.0;
  const double d = 1.0 - intact_area / family_area;
  return d < 1e-9 ? 0.0 : d;
}

// Where a bond's critical extension s0 |xi| comes from, chosen at compile
// time: one s0 for the whole table (one horizon), or one extension per bond,
// its owner's (variable horizons, variable_horizon_bonds.hpp).
struct SharedCriticalStretch {
  double critical_stretch;
  const double* rest;
  double operator()(std::uint64_t b) const { return critical_stretch * rest[b]; }
};
struct PerBondCriticalExtension {
  const double* extension;
  double operator()(std::uint64_t b) const { return extension[b]; }
};

// Where the entries a state-based pre-pass sums end in a row, chosen at
// compile time: the whole row (one horizon), or i's own entries only (a
// dual-horizon table, whose dual entries carry their owners' dilatation).
struct WholeRows {
  const std::uint64_t* offsets;
  std::uint64_t operator()(std::int64_t i) const { return offsets[i + 1]; }
};
struct OwnEntries {
  const std::uint64_t* dual_begin;
  std::uint64_t operator()(std::int64_t i) const { return dual_begin[i]; }
};

// Fills k.fx, k.fy with the internal force densities [N/m^3] of the listed
// particles (`list` of `count` indices; nullptr = particles 0 .. count-1),
// from the displacements k.ux, k.uy and the table's reference bonds. With
// DamageOn each bond whose extension exceeds its critical extension
// (`critical(b)`) breaks before it is summed (both directions of a bond see
// the same extension bit for bit, so they break at the same step), and
// damage[i] is updated.
// `intact`: per bond of `bonds`; `damage`: per particle (both unused with DamageOff).
//
// Each kernel below comes in two forms: F_in_team, the loop for a team of
// threads that is already running (an orphaned `omp for` without the barrier
// at its end, so that a caller running several independent loops in one
// parallel region waits once, at its next barrier), and F, which starts a
// team for the loop alone. Both split the particles alike (static schedule).
template <class Model, class Damage, class Critical>
void compute_bond_forces_with_in_team(const BondTable& bonds, Kinematics& k, std::uint8_t* intact, double* damage,
                                      const std::uint32_t* list, std::int64_t count, Critical critical) {
  static_assert(!Model::has_pre_pass, "the neighbour-list kernel has no per-particle pre-pass yet");
  const float* xi_x = bonds.xi_x.data();
  const float* xi_y = bonds.xi_y.data();
  const double* ux = k.ux.data();
  const double* uy = k.uy.data();
  const std::uint32_t* neighbor = bonds.neighbor.data();
  const double* rest = bonds.rest_length.data();
  const double* stiffness = bonds.stiffness.data();
  const float* damage_weight = bonds.damage_weight.data();
#pragma omp for schedule(static) nowait
  for (std::int64_t index = 0; index < count; ++index) {
    const std::int64_t i = list ? static_cast<std::int64_t>(list[index]) : index;
    double fx = 0, fy = 0, intact_area = 0;
    const double uxi = ux[i], uyi = uy[i];
    const auto first = bonds.offsets[i], last = bonds.offsets[i + 1];
    // Branch-free body, so that the compiler can vectorise it (SIMD lanes sum in a
    // fixed order: results stay independent of the thread count).
#pragma omp simd reduction(+ : fx, fy, intact_area)
    for (auto b = first; b < last; ++b) {
      const auto j = neighbor[b];
      const auto bond = deformed_bond(static_cast<double>(xi_x[b]), static_cast<double>(xi_y[b]), rest[b],
                                      ux[j] - uxi, uy[j] - uyi);
      double f = Model::force_over_length(stiffness[b], bond);
      if constexpr (Damage::enabled) {
        // A bond breaks for good when over-stretched [Peng et al. 2023, Eqs. (8), (9)]; broken
        // bonds are still evaluated (they are few) but weighted by 0.
        const std::uint8_t holds =
            intact[b] & static_cast<std::uint8_t>(Model::holds(critical(b), bond));
        intact[b] = holds;
        const double weight = static_cast<double>(holds);
        f *= weight;
        intact_area += weight * static_cast<double>(damage_weight[b]);
      }
      fx += f * bond.yx;
      fy += f * bond.yy;
    }
    k.fx[i] = fx;
    k.fy[i] = fy;
    if constexpr (Damage::enabled) damage[i] = damage_index(intact_area, bonds.family_area[i]);
  }
}

template <class Model, class Damage, class Critical>
void compute_bond_forces_with(const BondTable& bonds, Kinematics& k, std::uint8_t* intact, double* damage,
                              const std::uint32_t* list, std::int64_t count, Critical critical) {
#pragma omp parallel
  compute_bond_forces_with_in_team<Model, Damage>(bonds, k, intact, damage, list, count, critical);
}

// The constant-horizon form: one critical stretch for every bond of the table.
template <class Model, class Damage>
void compute_bond_forces_in_team(const BondTable& bonds, Kinematics& k, std::uint8_t* intact, double* damage,
                                 const std::uint32_t* list, std::int64_t count) {
  compute_bond_forces_with_in_team<Model, Damage>(
      bonds, k, intact, damage, list, count, SharedCriticalStretch{bonds.critical_stretch, bonds.rest_length.data()});
}

template <class Model, class Damage>
void compute_bond_forces(const BondTable& bonds, Kinematics& k, std::uint8_t* intact, double* damage,
                         const std::uint32_t* list, std::int64_t count) {
#pragma omp parallel
  compute_bond_forces_in_team<Model, Damage>(bonds, k, intact, damage, list, count);
}

// The tangent product on the lists: (gx[i], gy[i]) = the change of particle
// i's force density when the displacements (ux, uy) change by (dx, dy), the
// sum of Model::force_change over i's intact bonds (theory.md Sec. 4.8), for
// the particles of `list` (all particles when null). `intact`: per bond, or
// null (broken bonds then have stiffness 0). Written, not added.
template <class Model>
void bond_force_change_in_team(const BondTable& bonds, const double* ux, const double* uy, const double* dx,
                               const double* dy, const std::uint8_t* intact, const std::uint32_t* list,
                               std::int64_t count, double* gx, double* gy) {
#pragma omp for schedule(static) nowait
  for (std::int64_t q = 0; q < count; ++q) {
    const std::size_t i = list ? list[q] : static_cast<std::size_t>(q);
    double sum_x = 0, sum_y = 0;
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      if (intact && !intact[b]) continue;
      const auto j = bonds.neighbor[b];
      const auto bond = deformed_bond(static_cast<double>(bonds.xi_x[b]), static_cast<double>(bonds.xi_y[b]),
                                      bonds.rest_length[b], ux[j] - ux[i], uy[j] - uy[i]);
      double bx = 0, by = 0;
      Model::force_change(bonds.stiffness[b], bond, dx[j] - dx[i], dy[j] - dy[i], bx, by);
      sum_x += bx;
      sum_y += by;
    }
    gx[i] = sum_x;
    gy[i] = sum_y;
  }
}

// Adds to w[i] the strain energy density of i's bonds in the table, sum over
// intact bonds of Model::energy_density [J/m^3] (theory.md Sec. 1, including
// the surface-correction factor). `intact`: per bond of `bonds`, or null
// without damage.
template <class Model>
void add_bond_energy_density_in_team(const BondTable& bonds, const Kinematics& k, const std::uint8_t* intact,
                                     std::vector<double>& w) {
  const std::int64_t n = static_cast<std::int64_t>(bonds.particle_count);
#pragma omp for schedule(static) nowait
  for (std::int64_t i = 0; i < n; ++i) {
    double sum = 0;
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      if (intact && !intact[b]) continue;
      const auto j = bonds.neighbor[b];
      const auto bond = deformed_bond(static_cast<double>(bonds.xi_x[b]), static_cast<double>(bonds.xi_y[b]),
                                      bonds.rest_length[b], k.ux[j] - k.ux[i], k.uy[j] - k.uy[i]);
      sum += Model::energy_density(bonds.energy_stiffness_of(b), bond);
    }
    w[static_cast<std::size_t>(i)] += sum;
  }
}

template <class Model>
void add_bond_energy_density(const BondTable& bonds, const Kinematics& k, const std::uint8_t* intact,
                             std::vector<double>& w) {
#pragma omp parallel
  add_bond_energy_density_in_team<Model>(bonds, k, intact, w);
}


// ---- State-based models (Model::has_pre_pass; theory.md Sec. 5). Separate
// loops, so that the bond-based ones above stay as they are.

// The pre-pass: theta_i = 2/m_i sum_j Lambda_ij e_ij V_ij/|xi_ij| over the
// intact bonds (Model::dilatation_term), and pressure[i] = theta_i / m_i
// [1/m^2], which the force pass reads at both ends of a bond. With DamageOn
// the over-stretched bonds break here (both directions of a bond see the
// same extension, so they break together), so that a broken bond leaves the
// dilatation and the force of the same step. Under the failure variants that
// keep a broken bond in the dilatation (Model::broken_bond_in_dilatation,
// theory.md Sec. 5.8) the sum runs over all bonds of the family.
// `critical(b)`: the bond's critical extension; `row_end(i)`: the end of the
// entries of i's dilatation (WholeRows, or OwnEntries with dual horizons,
// where only i's own bonds break here: theory.md Sec. 6.8).
template <class Model, class Damage, class Critical, class RowEnd>
void compute_dilatation_with(const BondTable& bonds, const Kinematics& k, std::uint8_t* intact, double* theta,
                             double* pressure, Critical critical, RowEnd row_end) {
  static_assert(Model::has_pre_pass, "for state-based models");
  const std::int64_t n = static_cast<std::int64_t>(bonds.particle_count);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double sum = 0;
    const double uxi = k.ux[i], uyi = k.uy[i];
    const auto last = row_end(i);
    // A local copy: the stores to intact[] (bytes, which may alias anything)
    // would otherwise make the loop reload the policy's members every bond.
    const Critical critical_of = critical;
    for (auto b = bonds.offsets[i]; b < last; ++b) {
      const auto j = bonds.neighbor[b];
      const double xi_x = bonds.xi_x[b], xi_y = bonds.xi_y[b], rest = bonds.rest_length[b];
      const auto bond = deformed_bond(xi_x, xi_y, rest, k.ux[j] - uxi, k.uy[j] - uyi);
      double term = Model::dilatation_term(bonds.volume_over_length[b], Model::bond(bond, xi_x, xi_y, rest));
      if constexpr (Damage::enabled) {
        const std::uint8_t holds = intact[b] & static_cast<std::uint8_t>(Model::holds(critical_of(b), bond));
        intact[b] = holds;
        if constexpr (!Model::broken_bond_in_dilatation) term *= static_cast<double>(holds);
      }
      sum += term;
    }
    const double m = bonds.weighted_volume[i];
    theta[i] = m > 0 ? 2.0 * sum / m : 0.0;  // a particle without bonds has no dilatation
    pressure[i] = m > 0 ? theta[i] / m : 0.0;
  }
}

// The constant-horizon pre-pass: one critical stretch, whole rows.
template <class Model, class Damage>
void compute_dilatation(const BondTable& bonds, const Kinematics& k, std::uint8_t* intact, double* theta,
                        double* pressure) {
  compute_dilatation_with<Model, Damage>(bonds, k, intact, theta, pressure,
                                         SharedCriticalStretch{bonds.critical_stretch, bonds.rest_length.data()},
                                         WholeRows{bonds.offsets.data()});
}

// The pre-pass's bond sums alone, for the listed particles (`list` of
// `count`): sum[i] = sum_j Lambda_ij e_ij V_ij/|xi_ij| over i's intact bonds
// in the table, breaking the over-stretched ones as compute_dilatation. The
// lattice kernel adds the sums of its pairs and forms theta (lattice_sweep.hpp).
// `critical(b)` and `row_end(i)` as compute_dilatation_with: with dual
// horizons (OwnEntries) each own entry's term goes to its owner only.
template <class Model, class Damage, class Critical, class RowEnd>
void add_dilatation_sums_with_in_team(const BondTable& bonds, const Kinematics& k, std::uint8_t* intact,
                                      const std::uint32_t* list, std::int64_t count, double* sum, Critical critical,
                                      RowEnd row_end) {
  static_assert(Model::has_pre_pass, "for state-based models");
#pragma omp for schedule(static) nowait
  for (std::int64_t index = 0; index < count; ++index) {
    const std::int64_t i = static_cast<std::int64_t>(list[index]);
    double s = 0;
    const double uxi = k.ux[i], uyi = k.uy[i];
    const auto last = row_end(i);
    const Critical critical_of = critical;  // a local copy, as in compute_dilatation_with
    for (auto b = bonds.offsets[i]; b < last; ++b) {
      const auto j = bonds.neighbor[b];
      const double xi_x = bonds.xi_x[b], xi_y = bonds.xi_y[b], rest = bonds.rest_length[b];
      const auto bond = deformed_bond(xi_x, xi_y, rest, k.ux[j] - uxi, k.uy[j] - uyi);
      double term = Model::dilatation_term(bonds.volume_over_length[b], Model::bond(bond, xi_x, xi_y, rest));
      if constexpr (Damage::enabled) {
        const std::uint8_t holds = intact[b] & static_cast<std::uint8_t>(Model::holds(critical_of(b), bond));
        intact[b] = holds;
        if constexpr (!Model::broken_bond_in_dilatation) term *= static_cast<double>(holds);
      } else if (!Model::broken_bond_in_dilatation && intact && !intact[b]) {
        term = 0;  // the energy's call: states given, nothing breaks
      }
      s += term;
    }
    sum[i] += s;
  }
}

// The constant-horizon form: one critical stretch, whole rows.
template <class Model, class Damage>
void add_dilatation_sums_in_team(const BondTable& bonds, const Kinematics& k, std::uint8_t* intact,
                                 const std::uint32_t* list, std::int64_t count, double* sum) {
  add_dilatation_sums_with_in_team<Model, Damage>(bonds, k, intact, list, count, sum,
                                                  SharedCriticalStretch{bonds.critical_stretch,
                                                                        bonds.rest_length.data()},
                                                  WholeRows{bonds.offsets.data()});
}

template <class Model, class Damage>
void add_dilatation_sums(const BondTable& bonds, const Kinematics& k, std::uint8_t* intact, const std::uint32_t* list,
                         std::int64_t count, double* sum) {
#pragma omp parallel
  add_dilatation_sums_in_team<Model, Damage>(bonds, k, intact, list, count, sum);
}

// The force densities [N/m^3] of a state-based model after its pre-pass:
// on i from the bond i -> j, the bond part (Model::force_over_length, the
// bond table's stiffness) plus the dilatation part of both ends
// (Model::dilatation_force_over_length with theta_i/m_i + theta_j/m_j), along
// y_ij; the pair's other direction gets the same scalar with the opposite
// direction, so momentum is conserved (theory.md Sec. 5). The bonds' states
// are those the pre-pass left; damage[i] as compute_bond_forces.
// `list`, `count`: the particles to compute, as compute_bond_forces (nullptr:
// all of the table's).
template <class Model, class Damage>
void compute_state_forces_in_team(const BondTable& bonds, Kinematics& k, const std::uint8_t* intact, double* damage,
                                  const double* pressure, double dilatation_coefficient,
                                  const std::uint32_t* list = nullptr, std::int64_t count = -1) {
  static_assert(Model::has_pre_pass, "for state-based models");
  const std::int64_t n = count < 0 ? static_cast<std::int64_t>(bonds.particle_count) : count;
  const double a = dilatation_coefficient;
#pragma omp for schedule(static) nowait
  for (std::int64_t index = 0; index < n; ++index) {
    const std::int64_t i = list ? static_cast<std::int64_t>(list[index]) : index;
    double fx = 0, fy = 0, intact_area = 0;
    const double uxi = k.ux[i], uyi = k.uy[i], pi = pressure[i];
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      const auto j = bonds.neighbor[b];
      const double xi_x = bonds.xi_x[b], xi_y = bonds.xi_y[b], rest = bonds.rest_length[b];
      const auto bond = deformed_bond(xi_x, xi_y, rest, k.ux[j] - uxi, k.uy[j] - uyi);
      const auto terms = Model::bond(bond, xi_x, xi_y, rest);
      const double bond_part = Model::force_over_length(bonds.stiffness[b], terms);
      const double dilatation_part =
          Model::dilatation_force_over_length(a, bonds.volume_over_length[b], pi + pressure[j], terms);
      double f = bond_part + dilatation_part;
      if constexpr (Damage::enabled) {
        const double weight = static_cast<double>(intact[b]);
        // A broken bond loses its bond term; its dilatation term too unless
        // the variant keeps it (theory.md Sec. 5.8).
        if constexpr (Model::broken_bond_keeps_dilatation_force)
          f = weight * bond_part + dilatation_part;
        else
          f *= weight;
        intact_area += weight * static_cast<double>(bonds.damage_weight[b]);
      }
      fx += f * bond.yx;
      fy += f * bond.yy;
    }
    k.fx[i] = fx;
    k.fy[i] = fy;
    if constexpr (Damage::enabled) damage[i] = damage_index(intact_area, bonds.family_area[i]);
  }
}

template <class Model, class Damage>
void compute_state_forces(const BondTable& bonds, Kinematics& k, const std::uint8_t* intact, double* damage,
                          const double* pressure, double dilatation_coefficient, const std::uint32_t* list = nullptr,
                          std::int64_t count = -1) {
#pragma omp parallel
  compute_state_forces_in_team<Model, Damage>(bonds, k, intact, damage, pressure, dilatation_coefficient, list,
                                              count);
}

// The force densities [N/m^3] of a state-based model on a dual-horizon table
// (theory.md Sec. 6.8), after compute_dilatation_with over the own entries
// (OwnEntries), which broke the over-stretched own bonds. On i:
//   own entries i -> j:  the owner's half of the bond term (the table's
//     stiffness, C_d = c_d / 2) plus 4 a Lambda (V_ij/|xi|) theta_i/m_i, i's
//     own dilatation only;
//   dual entries (bonds j -> i that j owns): the same force [N] opposite, as a
//     density of i's volume (the table's stiffness and weight carry V_j/V_i),
//     with the owner's theta_j/m_j. A dual entry breaks here, with the same
//     extension bit for bit and the same critical extension as its own copy
//     in the pre-pass of the same step, so both copies leave together and
//     momentum stays conserved through fracture.
// damage[i] as compute_bond_forces, over both kinds of entries (theory.md Sec. 6.1).
// `list`, `count`: the particles to compute (nullptr: all of the table's), as
// compute_state_forces; the lattice kernel's general particles (Sec. 6.8).
template <class Model, class Damage>
void compute_dual_horizon_state_forces_in_team(const BondTable& bonds, Kinematics& k, std::uint8_t* intact,
                                               double* damage, const double* pressure, double dilatation_coefficient,
                                               const std::uint32_t* list = nullptr, std::int64_t count = -1) {
  static_assert(Model::has_pre_pass, "for state-based models");
  const std::int64_t n = count < 0 ? static_cast<std::int64_t>(bonds.particle_count) : count;
  const double a = dilatation_coefficient;
  // The force of one entry with the pressure theta/m it carries, weighted by
  // its state: a broken bond loses its bond term, and its dilatation term
  // unless the variant keeps it (theory.md Sec. 5.8).
  const auto entry_force = [&](std::uint64_t b, const DeformedBond<double>& bond, double entry_pressure,
                               [[maybe_unused]] double weight) {
    const auto terms = Model::bond(bond, static_cast<double>(bonds.xi_x[b]), static_cast<double>(bonds.xi_y[b]),
                                   bonds.rest_length[b]);
    const double bond_part = Model::force_over_length(bonds.stiffness[b], terms);
    const double dilatation_part =
        Model::dilatation_force_over_length(a, bonds.volume_over_length[b], entry_pressure, terms);
    if constexpr (!Damage::enabled) return bond_part + dilatation_part;
    else if constexpr (Model::broken_bond_keeps_dilatation_force) return weight * bond_part + dilatation_part;
    else return weight * (bond_part + dilatation_part);
  };
#pragma omp for schedule(static) nowait
  for (std::int64_t index = 0; index < n; ++index) {
    const std::int64_t i = list ? static_cast<std::int64_t>(list[index]) : index;
    double fx = 0, fy = 0, intact_area = 0;
    const double uxi = k.ux[i], uyi = k.uy[i];
    const auto own_end = bonds.dual_begin[i];
    for (auto b = bonds.offsets[i]; b < own_end; ++b) {
      const auto j = bonds.neighbor[b];
      const auto bond = deformed_bond(static_cast<double>(bonds.xi_x[b]), static_cast<double>(bonds.xi_y[b]),
                                      bonds.rest_length[b], k.ux[j] - uxi, k.uy[j] - uyi);
      double weight = 1;
      if constexpr (Damage::enabled) {
        weight = static_cast<double>(intact[b]);
        intact_area += weight * static_cast<double>(bonds.damage_weight[b]);
      }
      const double f = entry_force(b, bond, pressure[i], weight);
      fx += f * bond.yx;
      fy += f * bond.yy;
    }
    for (auto b = own_end; b < bonds.offsets[i + 1]; ++b) {
      const auto j = bonds.neighbor[b];
      const auto bond = deformed_bond(static_cast<double>(bonds.xi_x[b]), static_cast<double>(bonds.xi_y[b]),
                                      bonds.rest_length[b], k.ux[j] - uxi, k.uy[j] - uyi);
      double weight = 1;
      if constexpr (Damage::enabled) {
        const std::uint8_t holds =
            intact[b] & static_cast<std::uint8_t>(Model::holds(bonds.critical_extension[b], bond));
        intact[b] = holds;
        weight = static_cast<double>(holds);
        intact_area += weight * static_cast<double>(bonds.damage_weight[b]);
      }
      const double f = entry_force(b, bond, pressure[j], weight);
      fx += f * bond.yx;
      fy += f * bond.yy;
    }
    k.fx[i] = fx;
    k.fy[i] = fy;
    if constexpr (Damage::enabled) damage[i] = damage_index(intact_area, bonds.family_area[i]);
  }
}

template <class Model, class Damage>
void compute_dual_horizon_state_forces(const BondTable& bonds, Kinematics& k, std::uint8_t* intact, double* damage,
                                       const double* pressure, double dilatation_coefficient) {
#pragma omp parallel
  compute_dual_horizon_state_forces_in_team<Model, Damage>(bonds, k, intact, damage, pressure, dilatation_coefficient);
}

// Adds to w[i] the strain energy density of a state-based model,
// W_i = a theta_i^2 + sum over intact bonds of Model::energy_density
// (theory.md Sec. 5), with theta_i from the current displacements (over the
// intact bonds, or all with Model::broken_bond_in_dilatation, Sec. 5.8).
// On a dual-horizon table both sums run over i's own entries, the energy of
// the bonds i owns with the whole stiffness 2 C_d (theory.md Sec. 6.8).
// `intact`: per bond, or null without damage.
template <class Model>
void add_state_energy_density(const BondTable& bonds, const Kinematics& k, const std::uint8_t* intact,
                              double dilatation_coefficient, std::vector<double>& w) {
  static_assert(Model::has_pre_pass, "for state-based models");
  const std::int64_t n = static_cast<std::int64_t>(bonds.particle_count);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    double sum = 0, dilatation_sum = 0;
    const auto own_end = bonds.own_end(static_cast<std::size_t>(i));
    for (auto b = bonds.offsets[i]; b < own_end; ++b) {
      const bool broken = intact && !intact[b];
      if (broken && !Model::broken_bond_in_dilatation) continue;
      const auto j = bonds.neighbor[b];
      const double xi_x = bonds.xi_x[b], xi_y = bonds.xi_y[b], rest = bonds.rest_length[b];
      const auto bond = deformed_bond(xi_x, xi_y, rest, k.ux[j] - k.ux[i], k.uy[j] - k.uy[i]);
      if (!broken) sum += Model::energy_density(bonds.energy_stiffness_of(b), bond);
      dilatation_sum += Model::dilatation_term(bonds.volume_over_length[b], Model::bond(bond, xi_x, xi_y, rest));
    }
    const double m = bonds.weighted_volume[i];
    const double theta = m > 0 ? 2.0 * dilatation_sum / m : 0.0;
    w[static_cast<std::size_t>(i)] += dilatation_coefficient * theta * theta + sum;
  }
}

}  // namespace pd::solver
