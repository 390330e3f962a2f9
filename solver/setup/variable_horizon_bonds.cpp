#include "variable_horizon_bonds.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"

namespace pd::solver {

FamilyMembership::FamilyMembership(const Families& families) {
  pairs_.reserve(static_cast<std::size_t>(families.bond_count()));
  for (std::uint32_t i = 0; i < families.particle_count; ++i)
    families.for_each_bond(i, [&](const BondRef& b) { pairs_.push_back(std::uint64_t{i} << 32 | b.neighbor); });
  std::sort(pairs_.begin(), pairs_.end());
}

bool FamilyMembership::contains(std::uint32_t owner, std::uint32_t member) const {
  return std::binary_search(pairs_.begin(), pairs_.end(), std::uint64_t{owner} << 32 | member);
}

BondTable variable_horizon_rows(const ParticleSet& p, const std::vector<OwnedBond>& bonds, HorizonMode mode,
                                bool with_damage, std::vector<std::uint8_t>* intact) {
  if (mode == HorizonMode::uniform) throw Error("variable_horizon_rows: the run has one horizon");
  const std::size_t n = p.size();
  const bool dual = mode == HorizonMode::dual_horizon;
  // Entries per row: own bonds, plus (dual horizon) the bonds others own towards it.
  std::vector<std::uint64_t> own_count(n, 0), dual_count(n, 0);
  for (const auto& b : bonds) {
    ++own_count[b.owner];
    if (dual) ++dual_count[b.neighbor];
  }
  BondTable t;
  t.particle_count = n;
  t.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) t.offsets[i + 1] = t.offsets[i] + own_count[i] + dual_count[i];
  const std::size_t total = t.offsets[n];
  t.neighbor.resize(total);
  t.xi_x.resize(total);
  t.xi_y.resize(total);
  t.rest_length.resize(total);
  t.stiffness.resize(total);
  t.critical_extension.resize(total);
  if (with_damage) t.damage_weight.resize(total);
  std::vector<std::uint8_t> states(total, 1);
  // Own bonds fill each row's front, dual entries follow in owner order.
  std::vector<std::uint64_t> next_own(t.offsets.begin(), t.offsets.end() - 1), next_dual(n);
  for (std::size_t i = 0; i < n; ++i) next_dual[i] = t.offsets[i] + own_count[i];
  const auto put = [&](std::uint64_t e, std::uint32_t from, std::uint32_t to, const OwnedBond& b, double stiffness,
                       float weight) {
    t.neighbor[e] = to;
    t.xi_x[e] = static_cast<float>(p.x[to] - p.x[from]);
    t.xi_y[e] = static_cast<float>(p.y[to] - p.y[from]);
    t.rest_length[e] = b.rest_length;
    t.stiffness[e] = stiffness;
    t.critical_extension[e] = b.critical_extension;
    if (with_damage) t.damage_weight[e] = weight;
    states[e] = b.intact ? 1 : 0;
  };
  for (const auto& b : bonds) {
    put(next_own[b.owner]++, b.owner, b.neighbor, b, b.stiffness, b.owner_weight);
    // The reaction on j: the same force [N], as a density of j's volume.
    if (dual)
      put(next_dual[b.neighbor]++, b.neighbor, b.owner, b, dual_entry_stiffness(p, b), b.neighbor_weight);
  }
  if (with_damage) {
    t.family_area.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (auto e = t.offsets[i]; e < t.offsets[i + 1]; ++e) t.family_area[i] += t.damage_weight[e];
  }
  if (intact) *intact = std::move(states);
  return t;
}

double row_stable_time_step(const BondTable& t, double density) {
  std::vector<double> row_stiffness(t.particle_count, 0.0);
  for (std::size_t i = 0; i < t.particle_count; ++i)
    for (auto e = t.offsets[i]; e < t.offsets[i + 1]; ++e) row_stiffness[i] += t.stiffness[e];
  return row_stable_time_step(row_stiffness, density);
}

double row_stable_time_step(const std::vector<double>& row_stiffness, double density) {
  double smallest = INFINITY;
  for (double k : row_stiffness)
    if (k > 0) smallest = std::min(smallest, std::sqrt(2.0 * density / k));
  return smallest;
}

}  // namespace pd::solver
