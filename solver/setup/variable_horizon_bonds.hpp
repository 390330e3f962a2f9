#pragma once
// The bond table of a run with variable horizons (theory.md Sec. 6): every
// directed bond i -> j (j in i's family, the horizon H_i) with the constants
// of its owner i, Model::constants(material, delta_i), and its own critical
// extension s0(delta_i) |xi_ij|. The micromodulus of each end's half of a
// bond is C(delta) = c(delta) / 2 (a pair of equal horizons gets c).
//
//   ordinary_variable (standard PD, Imachi et al. 2021, Eq. (12)): the row
//     of i holds i's own bonds; the force on i from j is its own half
//     C(delta_i) plus j's half C(delta_j) when i is also in H_j, nothing of j
//     otherwise. Newton's third law fails for pairs in one family only.
//   dual_horizon (Ren et al. 2017): the bond i -> j carries C(delta_i) only,
//     and the row of j also holds it as a "dual entry" (i in H'_j): the same
//     bond seen from j, with the stiffness k_ij V_i / V_j (so that the force
//     on j [N] is minus the force on i [N]), i's critical extension and the
//     damage weight phi_ij V_i. Both copies see the same extension bit for bit
//     (xi_ji = -xi_ij exactly), so they break at the same step; a bond and its
//     dual bond j -> i are separate entries and break independently.
// Each row: the own bonds in family order, then the dual entries by owner
// (BondTable::dual_begin says where they start).
// Bond-based models: where the bond i -> j and its reverse j -> i both exist
// with the same rest length and critical extension (equal horizons), the own
// entry of i -> j also holds the dual entry of j -> i (the sum of their
// stiffnesses and damage weights): the two see the same extension bit for
// bit and break at the same step, so one evaluation serves both
// (BondTable::entry_halves counts what an entry holds).
// The kernels sum a row as any bond table's (compute_bond_forces_with with
// PerBondCriticalExtension); with dual horizons momentum is conserved to
// round-off because every bond's force appears with opposite signs in two rows.
//
// A state-based model (OSB, dual horizons only; theory.md Sec. 6.8) adds the
// dilatation's weights: an own entry i -> j holds V_ij / |xi_ij| of i's own
// quadrature, its dual entry in j's row the same times V_i / V_j (the force
// in newtons is the owner's, as for the stiffness), and m_i sums i's own
// entries. The kernel gives an own entry i's dilatation and a dual entry its
// owner's (neighbor_kernel.hpp, compute_dual_horizon_state_forces), so its
// rows keep every own entry apart from every dual entry: no combined entries.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <type_traits>
#include <vector>

#include "bond_setup.hpp"
#include "bond_table.hpp"
#include "error.hpp"
#include "horizon_mode.hpp"
#include "material.hpp"

namespace pd::solver {

// One directed bond with its owner's constants, before it goes into the rows.
struct OwnedBond {
  std::uint32_t owner = 0, neighbor = 0;
  double rest_length = 0, stiffness = 0, critical_extension = 0;
  float owner_weight = 0, neighbor_weight = 0;  // phi_ij V_j (for i), phi_ij V_i (for j's dual entry)
  // State-based models only: V_ij of the owner's dilatation [m^2]
  // (dilatation_volume, bond_setup.hpp; 0 across a pre-crack).
  double dilatation_volume = 0;
  bool intact = true;
};

// The stiffness of the dual entry of bond b in the row of its neighbour j,
// k_ij V_i / V_j: the force on j [N] is minus the force on i [N].
inline double dual_entry_stiffness(const ParticleSet& p, const OwnedBond& b) {
  return b.stiffness * p.volume[b.owner] / p.volume[b.neighbor];
}

// The rows of the table from the owned bonds (in owner order, each owner's
// bonds in family order); `intact` receives the entries' states.
// `with_dilatation` (a state-based model): also the dilatation's weights and
// the energy's stiffness (BondTable::volume_over_length, weighted_volume,
// energy_stiffness; theory.md Sec. 6.8). `entry_bond` receives per entry the
// index in `bonds` of the directed bond whose state it carries: an own entry
// its bond, a dual entry the bond it is the reaction of, a combined entry its
// own bond (its reverse breaks with it). With every bond kept these are the
// bonds' places family by family, the layout of distributed checkpoints
// (setup/local_bonds.hpp, local_rows).
BondTable variable_horizon_rows(const ParticleSet& particles, const std::vector<OwnedBond>& bonds, HorizonMode mode,
                                bool with_damage, std::vector<std::uint8_t>* intact, bool with_dilatation = false,
                                std::vector<std::uint64_t>* entry_bond = nullptr);

// Whether i is in the family of j (ordinary_variable: does j give i its half?).
class FamilyMembership {
public:
  explicit FamilyMembership(const Families& families);
  bool contains(std::uint32_t owner, std::uint32_t member) const;

private:
  std::vector<std::uint64_t> pairs_;  // owner << 32 | member, sorted
};

// The bond b of owner i with i's constants (for_each_owned_bond below):
// `constants` per particle, Model::constants(material, delta_j);
// `ordinary` (ordinary PD) whether i is in H_j, null with dual horizons.
// Inlined: it is the per-bond body of the rows' set-up loop.
template <class Model>
[[gnu::always_inline]] inline OwnedBond owned_bond(const ParticleSet& p, const BondSetup& setup,
                     const std::vector<typename Model::Constants>& constants, const FamilyMembership* ordinary,
                     std::uint32_t i, const BondRef& b) {
  const BondConstants c = bond_constants<Model>(p, setup, constants[i], i, b);
  OwnedBond o;
  o.owner = i;
  o.neighbor = b.neighbor;
  o.rest_length = c.rest_length;
  // i's half, C(delta_i) = c(delta_i) / 2 (theory.md Sec. 6.1) ...
  o.stiffness = 0.5 * c.stiffness;
  // ... and in ordinary PD j's half, on the same quadrature weight, if i is in H_j.
  if (ordinary && ordinary->contains(b.neighbor, i))
    o.stiffness += 0.5 * bond_constants<Model>(p, setup, constants[b.neighbor], i, b).stiffness;
  o.critical_extension = constants[i].critical_stretch * c.rest_length;
  o.owner_weight = c.damage_weight;
  o.neighbor_weight = static_cast<float>(b.partial_volume * p.volume[i]);
  if constexpr (Model::has_pre_pass) o.dilatation_volume = dilatation_volume(p, setup, i, b);
  o.intact = c.intact;
  return o;
}

// Model::constants(material, delta_i) of every particle.
template <class Model>
std::vector<typename Model::Constants> owner_constants(const ParticleSet& p, const MaterialSpec& material) {
  std::vector<typename Model::Constants> constants;
  constants.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) constants.push_back(Model::constants(material, p.horizon[i]));
  return constants;
}

// Calls f(const OwnedBond&) for every directed bond i -> j (j in H_i) with
// its owner's constants Model::constants(material, delta_i): the stiffness of
// i's half C(delta_i) (and, in ordinary PD, j's half when i is in H_j),
// s0(delta_i) |xi_ij|; for a state-based model (dual horizons only) also
// V_ij of i's dilatation; owners in index order, each owner's bonds in family
// order. With `keep`, only the bonds for which keep(i, j) holds (the others
// cost no constants). An `f` that also takes a std::uint32_t gets the bond's
// place in its owner's family (0 for the first), kept or not. With
// `owners` (ascending), only their bonds are looked at (the others' families
// are not walked): a list that holds every owner of a bond `keep` keeps.
using KeepBond = std::function<bool(std::uint32_t owner, std::uint32_t neighbor)>;
template <class Model, class F>
void for_each_owned_bond(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                         HorizonMode mode, const KeepBond& keep, F&& f,
                         const std::vector<std::uint32_t>* owners = nullptr) {
  if (Model::has_pre_pass && mode != HorizonMode::dual_horizon)
    throw Error("owned_bonds: a state-based model has variable horizons only in dual-horizon form");
  const std::vector<typename Model::Constants> constants = owner_constants<Model>(p, material);
  std::unique_ptr<FamilyMembership> membership;
  if (mode == HorizonMode::ordinary_variable) membership = std::make_unique<FamilyMembership>(setup.families);
  const std::size_t owner_count = owners ? owners->size() : p.size();
  for (std::size_t k = 0; k < owner_count; ++k) {
    const std::uint32_t i = owners ? (*owners)[k] : static_cast<std::uint32_t>(k);
    std::uint32_t place = 0;
    setup.families.for_each_bond(i, [&](const BondRef& b) {
      const std::uint32_t k = place++;
      if (keep && !keep(i, b.neighbor)) return;
      if constexpr (std::is_invocable_v<F&, const OwnedBond&, std::uint32_t>)
        f(owned_bond<Model>(p, setup, constants, membership.get(), i, b), k);
      else
        f(owned_bond<Model>(p, setup, constants, membership.get(), i, b));
    });
  }
}

template <class Model>
std::vector<OwnedBond> owned_bonds(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                                   HorizonMode mode, const KeepBond& keep = {}) {
  std::vector<OwnedBond> bonds;
  if (!keep) bonds.reserve(static_cast<std::size_t>(setup.families.bond_count()));
  for_each_owned_bond<Model>(p, setup, material, mode, keep, [&](const OwnedBond& o) { bonds.push_back(o); });
  return bonds;
}

// How a level's stencil differs between two particle sets: not at all, in
// the order of its bonds only, or in its bonds, spacing or horizon.
enum class StencilChange { same, order, other };
StencilChange stencil_change(const StencilLevel& before, const StencilLevel& after);

// Per particle of the set after an adaptive refinement event, 1 where its
// dual-horizon row may differ from that of its particle before the event
// (earlier.same_row; theory.md Sec. 8.6): the rows the event rebuilt and
// those whose constants or order a change of a level's stencil can change.
std::vector<std::uint8_t> rows_changed_by_event(const Families& now, const EarlierRowStiffness& earlier);
// The same, found once for the set-up (kept in earlier.changed_rows) for both
// the row sums and the general rows.
const std::vector<std::uint8_t>& changed_rows(const Families& now, const EarlierRowStiffness& earlier);

// The particles (ascending) within `reach` [m] of a particle with
// marked[i] != 0, and perhaps a few more: those in the squares of a grid of
// that side next to a square holding a marked particle. With `reach` the
// set's longest possible bond (longest_possible_bond, families.hpp: a family
// holds every cell that meets the disk of the horizon, theory.md Sec. 2.1, so
// a bond is longer than the largest horizon by up to a cell's
// centroid-to-vertex distance) they hold every bond into a marked particle.
std::vector<std::uint32_t> particles_near(const ParticleSet& p, const std::vector<std::uint8_t>& marked, double reach);

// Each particle's sum of the stiffnesses of its whole dual-horizon row
// [N/m^4], whether or not the rows are built (the lattice sweep computes most
// pairs without them), for the stable time step: the own entries' sum plus
// the dual entries' sum. With `earlier` (an adaptive refinement event,
// theory.md Sec. 8.6) the particles whose row the event left alone take
// their earlier sum over and only the others' are summed, bit for bit as the
// whole computation sums them. `computed` receives the number of sums computed.
// With `keep` (no `earlier`; and `owners` as for_each_owned_bond takes
// them), the bonds for which keep(i, j) holds only: the
// sums of the particles all of whose bonds either way it keeps are the
// whole computation's, bit for bit (a process's owned particles); the
// others' are partial.
template <class Model>
std::vector<double> dual_horizon_row_stiffness(const ParticleSet& p, const BondSetup& setup,
                                               const MaterialSpec& material,
                                               const EarlierRowStiffness* earlier = nullptr,
                                               std::size_t* computed = nullptr, const KeepBond& keep = {},
                                               const std::vector<std::uint32_t>* owners = nullptr) {
  const std::size_t n = p.size();
  std::vector<double> own(n, 0.0), dual(n, 0.0);
  if (!earlier) {
    for_each_owned_bond<Model>(
        p, setup, material, HorizonMode::dual_horizon, keep,
        [&](const OwnedBond& b) {
          own[b.owner] += b.stiffness;
          dual[b.neighbor] += dual_entry_stiffness(p, b);
        },
        owners);
    for (std::size_t i = 0; i < n; ++i) own[i] += dual[i];
    if (computed) *computed = n;
    return own;
  }
  if (keep || owners)
    throw Error("dual_horizon_row_stiffness: bonds to keep and earlier rows are not taken together");
  if (earlier->same_row.size() != n)
    throw Error("dual_horizon_row_stiffness: the earlier rows are given for another particle count");
  const std::vector<std::uint8_t>& changed = changed_rows(setup.families, *earlier);
  const std::vector<std::uint32_t> near = particles_near(p, changed, earlier->longest_bond);
  const auto constants = owner_constants<Model>(p, material);
  // Owners in index order and each owner's bonds in family order, as above:
  // every sum adds the same terms in the same order.
  for (const std::uint32_t i : near) {
    setup.families.for_each_bond(i, [&](const BondRef& b) {
      if (!changed[i] && !changed[b.neighbor]) return;
      const OwnedBond o = owned_bond<Model>(p, setup, constants, nullptr, i, b);
      if (changed[i]) own[i] += o.stiffness;
      if (changed[b.neighbor]) dual[b.neighbor] += dual_entry_stiffness(p, o);
    });
  }
  for (std::size_t i = 0; i < n; ++i)
    own[i] = changed[i] ? own[i] + dual[i] : earlier->sums->at(earlier->same_row[i]);
  if (computed) *computed = static_cast<std::size_t>(std::count(changed.begin(), changed.end(), 1));
  return own;
}

// The rows of every particle; with `keep`, the rows of the bonds for which
// keep(i, j) holds (the lattice kernel's general particles, lattice_kernel.hpp:
// their pairs with lattice particles come from the sweep), family_area then
// over the kept entries only. `entry_bond`: as for variable_horizon_rows.
template <class Model>
BondTable variable_horizon_table(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                                 HorizonMode mode, bool with_damage, std::vector<std::uint8_t>* intact,
                                 const KeepBond& keep = {}, std::vector<std::uint64_t>* entry_bond = nullptr) {
  return variable_horizon_rows(p, owned_bonds<Model>(p, setup, material, mode, keep), mode, with_damage, intact,
                               Model::has_pre_pass, entry_bond);
}

// The rows of the general particles of a lattice split (lattice_kernel.hpp):
// the bonds with both ends general (is_lattice 0), each with its owner's
// constants and its dual entry, as variable_horizon_table builds them with
// that `keep`. With `earlier` (an adaptive refinement event of a bond-based
// model, EarlierRowStiffness::general_rows set; theory.md Sec. 8.7) the
// rows of the particles whose row the event left alone (rows_changed_by_event)
// and none of whose row's particles changed its lattice membership are
// copied from the earlier set with the new indices; only the others are
// built, from the bonds that have one of them at an end. Bit for bit the
// whole build (tested). `copied` receives the number of rows of general
// particles copied.
struct GeneralRowsPlan {
  std::vector<std::uint8_t> build;        // per particle: 1 if its row is built
  std::vector<std::uint32_t> new_of_old;  // per particle before the event: its index now, or Families::none
  // The general particles with a bond to a general particle whose row is built, or whose own row is (sorted).
  std::vector<std::uint32_t> owners;
};
GeneralRowsPlan plan_general_rows(const ParticleSet& particles, const Families& now,
                                  const std::vector<std::uint8_t>& is_lattice, const EarlierRowStiffness& earlier);
// The rows of `plan.build` from `bonds` (as variable_horizon_rows makes
// them, written in place), the others copied.
BondTable general_rows_with_copies(const ParticleSet& particles, const std::vector<OwnedBond>& bonds,
                                   const GeneralRowsPlan& plan, const EarlierRowStiffness& earlier,
                                   const std::vector<std::uint8_t>& is_lattice, bool with_damage,
                                   std::vector<std::uint8_t>* intact, std::size_t* copied);

template <class Model>
BondTable dual_horizon_general_rows(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                                    const std::vector<std::uint8_t>& is_lattice, bool with_damage,
                                    std::vector<std::uint8_t>* intact, const EarlierRowStiffness* earlier = nullptr,
                                    std::size_t* copied = nullptr) {
  if (copied) *copied = 0;
  const auto both_general = [&](std::uint32_t i, std::uint32_t j) { return !is_lattice[i] && !is_lattice[j]; };
  // A state-based model's rows keep the dilatation's weights too: built whole.
  if (Model::has_pre_pass || !earlier || !earlier->general_rows || !earlier->general_table)
    return variable_horizon_table<Model>(p, setup, material, HorizonMode::dual_horizon, with_damage, intact,
                                         both_general);
  const GeneralRowsPlan plan = plan_general_rows(p, setup.families, is_lattice, *earlier);
  // A built row needs its own bonds, the bonds into it (its dual entries)
  // and their reverses (combined entries): every bond between general
  // particles with a built row at an end, in owner order and family order
  // as the whole build lists them (for_each_owned_bond), from the owners
  // that have such a bond (plan.owners) only.
  const auto constants = owner_constants<Model>(p, material);
  std::vector<OwnedBond> bonds;
  for (const std::uint32_t i : plan.owners)
    setup.families.for_each_bond(i, [&](const BondRef& b) {
      if (both_general(i, b.neighbor) && (plan.build[i] || plan.build[b.neighbor]))
        bonds.push_back(owned_bond<Model>(p, setup, constants, nullptr, i, b));
    });
  return general_rows_with_copies(p, bonds, plan, *earlier, is_lattice, with_damage, intact, copied);
}

// The total strain energy of dual-horizon PD as the rows of an energy table
// (theory.md Sec. 6.6): each particle's own bonds only, with k_ij = 2
// C(delta_i) = c(delta_i) (the table's W_i = 1/4 sum_j k_ij e_ij^2 then gives
// each bond the energy 1/2 C(delta_i) e^2 V_i of Sec. 6.2), for
// energy_bond_table (energy_bonds.hpp), whose symmetrised stiffness
// (A_i k_ij + A_j k_ji) / (2 A_i) holds exactly the bond and the dual bond of
// every pair: its gradient is the dual-horizon force of every particle.
template <class Model>
BondTable dual_horizon_energy_rows(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material) {
  std::vector<OwnedBond> bonds = owned_bonds<Model>(p, setup, material, HorizonMode::dual_horizon);
  for (auto& b : bonds) b.stiffness *= 2;
  // Rows of own bonds only (no dual entries): the mode that adds none.
  return variable_horizon_rows(p, bonds, HorizonMode::ordinary_variable, /*with_damage=*/true, nullptr);
}

// The states of a dual-horizon table's entries from its particles' bond
// states family by family (the layout of distributed checkpoints): each
// row's own entries in turn from `family_states` (a row's own entries are its
// particle's family in order; `family_states` null: left as they are, set
// already), then each dual entry from its owner's own entry towards the
// row's particle (it is the reaction of that bond, which breaks with it).
// One process's table, whose every owner has its row. pd::Error where the
// states do not fit the table.
void set_entry_states_from_families(const BondTable& table, const std::vector<std::uint8_t>* family_states,
                                    std::vector<std::uint8_t>& intact);

// Stable time step of a table whose rows hold every force on their particle
// (theory.md Sec. 4.5): dt_i = sqrt(2 rho / sum_row k), the smallest [s].
double row_stable_time_step(const BondTable& table, double density);
// The same bound from each particle's row sum of stiffnesses [N/m^4].
double row_stable_time_step(const std::vector<double>& row_stiffness, double density);

// The same for a state-based model on a dual-horizon table (theory.md Secs.
// 5.4, 6.8): dt_i = 2 sqrt(rho / R_i) with
// R_i = 2 sum_row k + 16 |a| (g_i^2 / m_i^2 + sum_{dual entries} w g_j / m_j^2),
// g_i = sum_{own entries} V_ij / |xi_ij|, w the dual entry's weight and j its
// owner; the smallest [s]. `dilatation_coefficient`: a [Pa]. `rows`: the
// rows whose bound is taken (null: all), e.g. a process's owned rows in a
// table of its slab's band, whose rows at the band's edges lack bonds (the
// dual entries' owners' g_j / m_j^2 from their own entries still).
double dual_horizon_state_stable_time_step(const BondTable& table, double dilatation_coefficient, double density,
                                           const std::vector<std::uint32_t>* rows = nullptr);
// The parts of that bound: g_i / m_i^2 (0 for a particle without bonds), and
// one row's dt_i from its sums [s] (infinite where R_i is not positive).
double dilatation_response(double g, double weighted_volume);
double dual_horizon_state_row_time_step(double stiffness_sum, double g, double g_over_m2, double reactions,
                                        double dilatation_coefficient, double density);

// The same bound for `rows` without building the table: from the bonds of
// `owners` (ascending; every owner of a bond into a row, each with its whole
// family), walked twice, first for each owner's own entries (its
// stiffnesses, g and m, in family order), then for the rows' dual entries in
// owner order, as the table lists them: bit for bit the table's bound of
// those rows. Null `rows` and `owners`: every particle, the whole table's
// bound (a one-process run with the lattice split, which builds rows for
// its general particles only); a process's owned rows of a distributed run
// and its local particles as owners (its table would hold every local
// particle's bonds).
template <class Model>
double dual_horizon_state_stable_time_step(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                                           double dilatation_coefficient, double density,
                                           const std::vector<std::uint32_t>* rows = nullptr,
                                           const std::vector<std::uint32_t>* owners = nullptr) {
  const std::size_t n = p.size();
  std::vector<double> stiffness_sum(n, 0.0), g(n, 0.0), m(n, 0.0);
  for_each_owned_bond<Model>(
      p, setup, material, HorizonMode::dual_horizon, {},
      [&](const OwnedBond& b) {
        stiffness_sum[b.owner] += b.stiffness;
        g[b.owner] += b.dilatation_volume / b.rest_length;  // (the own entry's V_ij / |xi_ij|)
        m[b.owner] += b.dilatation_volume;
      },
      owners);
  std::vector<double> g_over_m2(n, 0.0), reactions(n, 0.0);
  if (owners)
    for (const std::uint32_t i : *owners) g_over_m2[i] = dilatation_response(g[i], m[i]);
  else
    for (std::size_t i = 0; i < n; ++i) g_over_m2[i] = dilatation_response(g[i], m[i]);
  // With every particle a row, every bond's dual entry is in one.
  std::vector<std::uint8_t> is_row;
  KeepBond into_row;
  if (rows) {
    is_row.assign(n, 0);
    for (const std::uint32_t i : *rows) is_row[i] = 1;
    into_row = [&is_row](std::uint32_t, std::uint32_t j) { return is_row[j] != 0; };
  }
  for_each_owned_bond<Model>(
      p, setup, material, HorizonMode::dual_horizon, into_row,
      [&](const OwnedBond& b) {
        stiffness_sum[b.neighbor] += dual_entry_stiffness(p, b);
        // (The dual entry's weight, variable_horizon_rows.)
        const double weight = b.dilatation_volume / b.rest_length * p.volume[b.owner] / p.volume[b.neighbor];
        reactions[b.neighbor] += weight * g_over_m2[b.owner];
      },
      owners);
  const auto row_time_step = [&](std::size_t i) {
    return dual_horizon_state_row_time_step(stiffness_sum[i], g[i], g_over_m2[i], reactions[i],
                                            dilatation_coefficient, density);
  };
  double smallest = INFINITY;
  if (rows)
    for (const std::uint32_t i : *rows) smallest = std::min(smallest, row_time_step(i));
  else
    for (std::size_t i = 0; i < n; ++i) smallest = std::min(smallest, row_time_step(i));
  return smallest;
}

}  // namespace pd::solver
