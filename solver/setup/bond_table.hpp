#pragma once
// The bond table: per directed bond i->j, the constants the force kernel
// needs, precomputed once (structure of arrays, CSR by particle i).
#include <cstdint>
#include <vector>

namespace pd::solver {

struct BondTable {
  std::size_t particle_count = 0;
  std::vector<std::uint64_t> offsets;   // bonds of i: [offsets[i], offsets[i+1])
  std::vector<std::uint32_t> neighbor;  // j
  // The reference bond xi_ij = x_j - x_i [m] in float (the kernels need no
  // gather of the neighbour's reference position; 1e-7 relative is far finer
  // than any strain of interest, and xi_ji = -xi_ij holds exactly), and its
  // length |xi_ij| [m] in double.
  std::vector<float> xi_x, xi_y;
  std::vector<double> rest_length;
  // k_ij = 0.5 (lambda_i + lambda_j) c E_ij / |xi_ij|^2 [N/m^4], E_ij from bond_weights.hpp
  // (= 0.5 (lambda_i + lambda_j) c phi_ij A_j / |xi_ij| with partial-volume weights): the
  // force density on i is k_ij (|y_ij| - |xi_ij|) along y_ij (theory.md Sec. 1, with the
  // surface correction of Sec. 3 folded in).
  std::vector<double> stiffness;
  // The stiffness with i's own surface-correction factor lambda_i S_i(n) in
  // place of g_ij, for the share of the bond's energy that W_i holds, when a
  // model splits it so (theory.md Sec. 5.7); empty when it equals `stiffness`.
  std::vector<double> energy_stiffness;
  double energy_stiffness_of(std::size_t b) const { return energy_stiffness.empty() ? stiffness[b] : energy_stiffness[b]; }
  double critical_stretch = 0;  // s0: a bond breaks when its extension exceeds s0 |xi_ij|
  // Variable horizons only (variable_horizon_bonds.hpp), empty otherwise: per
  // bond its owner's s0(delta_i) |xi_ij| [m], which replaces critical_stretch.
  std::vector<double> critical_extension;
  // Dual-horizon rows only (variable_horizon_bonds.hpp), empty otherwise: per
  // entry the halves of directed bonds it holds. A directed bond is two halves,
  // its own entry and its dual entry; the own entry of i -> j that also holds
  // the dual entry of j -> i (equal horizons) is 2, any other entry 1.
  std::vector<std::uint8_t> entry_halves;
  // Dual-horizon tables only (variable_horizon_bonds.hpp), empty otherwise:
  // per particle the first dual entry of its row. A row holds i's own bonds
  // in [offsets[i], dual_begin[i]) and the reactions of the bonds others own
  // towards i in [dual_begin[i], offsets[i+1]), so that a kernel knows by
  // position whose dilatation an entry carries (theory.md Sec. 6.8).
  std::vector<std::uint64_t> dual_begin;
  // The end of i's own entries: the whole row unless the table has dual entries.
  std::uint64_t own_end(std::size_t i) const { return dual_begin.empty() ? offsets[i + 1] : dual_begin[i]; }
  // phi_ij A_j [m^2] for the damage index, float (an index needs no more); empty when damage is off.
  std::vector<float> damage_weight;
  std::vector<double> family_area;      // sum_j phi_ij A_j [m^2]; empty when damage is off
  // State-based models only (theory.md Sec. 5), empty otherwise: per bond V_ij / |xi_ij| [m]
  // with V_ij = phi_ij A_j (0 for a bond a pre-crack cut), and per particle the
  // weighted volume m_i = sum_j V_ij [m^2] of the uncut family, fixed at set-up.
  // A dual entry (dual_begin) holds its owner's V_ji / |xi| times V_j / V_i,
  // and m_i sums i's own entries only (theory.md Sec. 6.8).
  std::vector<double> volume_over_length;
  std::vector<double> weighted_volume;
  // The quasi-static OSB energy table only (energy_bonds.hpp), empty otherwise:
  // per bond i -> j the partner's weight A_j w_ji / A_i [m] (w_ji = V_ji/|xi|,
  // 0 when i is not in j's family), with which W_j's dilatation pulls on i
  // (theory.md Sec. 5.6). Equals volume_over_length on uniform grids.
  std::vector<double> partner_volume_over_length;
  std::size_t size() const { return neighbor.size(); }

  // The one list of the per-entry arrays (one value per row entry, in the
  // rows' order): f(name, member) for each, `member` a pointer to it
  // (table.*member), for the code that copies, cuts, joins or resizes a
  // table array by array. An array a table does not hold is empty.
  template <class F>
  static constexpr void for_each_entry_array(F&& f) {
    f("neighbor", &BondTable::neighbor);
    f("xi_x", &BondTable::xi_x);
    f("xi_y", &BondTable::xi_y);
    f("rest_length", &BondTable::rest_length);
    f("stiffness", &BondTable::stiffness);
    f("energy_stiffness", &BondTable::energy_stiffness);
    f("critical_extension", &BondTable::critical_extension);
    f("entry_halves", &BondTable::entry_halves);
    f("damage_weight", &BondTable::damage_weight);
    f("volume_over_length", &BondTable::volume_over_length);
    f("partner_volume_over_length", &BondTable::partner_volume_over_length);
  }
  // The same for the per-particle values (one per particle), beside the
  // rows' bounds `offsets` and `dual_begin`, which say where the entries are.
  template <class F>
  static constexpr void for_each_particle_array(F&& f) {
    f("family_area", &BondTable::family_area);
    f("weighted_volume", &BondTable::weighted_volume);
  }
};

// Every array of BondTable is in one of the lists above or is a row bound: a
// new array left out of them would be dropped by a cut or a copy without a
// word, so that it fails to compile instead (all std::vector have one size).
namespace bond_table_detail {
template <bool entries>
constexpr std::size_t array_count() {
  std::size_t count = 0;
  const auto add = [&count](const char*, auto) { ++count; };
  if constexpr (entries) BondTable::for_each_entry_array(add);
  else BondTable::for_each_particle_array(add);
  return count;
}
}  // namespace bond_table_detail
static_assert(sizeof(BondTable) == sizeof(std::size_t) + sizeof(double) +
                                       (bond_table_detail::array_count<true>() +
                                        bond_table_detail::array_count<false>() + 2) *
                                           sizeof(std::vector<double>),
              "a BondTable array is missing from for_each_entry_array or for_each_particle_array");

// Directed bonds broken in table t with the entries' states `intact` (pre-cut ones included).
inline std::uint64_t broken_directed_bonds(const BondTable& t, const std::vector<std::uint8_t>& intact) {
  std::uint64_t broken = 0;
  if (t.entry_halves.empty()) {
    for (auto state : intact) broken += state == 0;
    return broken;
  }
  for (std::size_t e = 0; e < intact.size(); ++e) broken += intact[e] == 0 ? t.entry_halves[e] : 0;
  return broken / 2;
}

// Directed bonds broken among the own entries of table t (a row's own bonds,
// BondTable::own_end): on a process of a distributed run, whose rows also
// hold dual entries of bonds other processes own and count.
inline std::uint64_t broken_own_entries(const BondTable& t, const std::vector<std::uint8_t>& intact) {
  std::uint64_t broken = 0;
  for (std::size_t i = 0; i < t.particle_count; ++i)
    for (auto e = t.offsets[i]; e < t.own_end(i); ++e) broken += intact[e] == 0;
  return broken;
}

}  // namespace pd::solver
