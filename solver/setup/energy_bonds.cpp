#include "energy_bonds.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace pd::solver {
namespace {

// What one direction i -> j of a pair contributes to one row of the energy
// table (the row of i as "own", the row of j as "partner").
struct HalfBond {
  std::uint32_t neighbor;
  double area_stiffness;  // A_i k_ij / 2 contributed by one direction
  float damage_weight;
};

// The state-based model's half (theory.md Sec. 5.6) adds the direction's own
// constants (W_i's stiffness, the dilatation weight w_ij = V_ij/|xi_ij|) to
// i's row, and A_i w_ij to j's row, which that row divides by A_j. Only OSB
// pays for the larger halves.
struct StateHalfBond : HalfBond {
  double own_energy_stiffness;  // k^W_ij [N/m^4] on i's row, 0 on j's
  double own_volume_over_length;  // w_ij [m] on i's row, 0 on j's
  double area_volume_over_length;  // A_i w_ij [m^3] on j's row, 0 on i's
};

// Index of the bond j -> i among j's bonds, or -1.
std::int64_t reverse_bond(const BondTable& bonds, std::uint32_t i, std::uint32_t j) {
  for (auto b = bonds.offsets[j]; b < bonds.offsets[j + 1]; ++b)
    if (bonds.neighbor[b] == i) return static_cast<std::int64_t>(b);
  return -1;
}

template <class Half>
BondTable symmetrised(BondTable bonds, const std::vector<double>& x, const std::vector<double>& y,
                      const std::vector<double>& area) {
  constexpr bool state_based = std::is_same_v<Half, StateHalfBond>;
  const std::size_t n = bonds.particle_count;
  // Each directed bond i -> j gives half of A_i k_ij to both directions of the
  // pair: all halves in one array by row (CSR, sized exactly: no per-row
  // vectors, no growth slack; this is the peak of the set-up's memory).
  std::vector<std::uint64_t> start(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      ++start[i + 1];
      ++start[bonds.neighbor[b] + 1];
    }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<Half> halves(start[n]);
  {
    std::vector<std::uint64_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
        const auto j = bonds.neighbor[b];
        // The energy's stiffness: W_i's own share (energy_stiffness_of), which
        // is the force's stiffness unless the model splits it (Sec. 5.7).
        const double half = 0.5 * area[i] * bonds.energy_stiffness_of(b);
        Half own{}, partner{};
        own.neighbor = j;
        own.area_stiffness = half;
        own.damage_weight = bonds.damage_weight[b];
        partner.neighbor = static_cast<std::uint32_t>(i);
        partner.area_stiffness = half;
        partner.damage_weight = 0.0f;
        if constexpr (state_based) {
          own.own_energy_stiffness = bonds.energy_stiffness_of(b);
          own.own_volume_over_length = bonds.volume_over_length[b];
          partner.area_volume_over_length = area[i] * bonds.volume_over_length[b];
        }
        halves[next[i]++] = own;
        halves[next[j]++] = partner;
      }
  }
  // The halves hold all the output needs but the positions: the input goes now.
  const double critical_stretch = bonds.critical_stretch;
  std::vector<double> family_area = std::move(bonds.family_area);
  std::vector<double> weighted_volume = std::move(bonds.weighted_volume);
  bonds = BondTable();
  // Each row by neighbour; a pair's two halves are merged into one bond.
  std::uint64_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto first = halves.begin() + static_cast<std::ptrdiff_t>(start[i]);
    const auto last = halves.begin() + static_cast<std::ptrdiff_t>(start[i + 1]);
    std::sort(first, last, [](const Half& a, const Half& b) { return a.neighbor < b.neighbor; });
    for (auto h = first; h != last; ++h)
      if (h == first || h->neighbor != (h - 1)->neighbor) ++count;
  }
  BondTable t;
  t.particle_count = n;
  t.critical_stretch = critical_stretch;
  t.family_area = std::move(family_area);
  t.offsets.assign(n + 1, 0);
  t.neighbor.reserve(count);
  t.xi_x.reserve(count);
  t.xi_y.reserve(count);
  t.rest_length.reserve(count);
  t.stiffness.reserve(count);
  t.damage_weight.reserve(count);
  if constexpr (state_based) {
    t.weighted_volume = std::move(weighted_volume);
    t.energy_stiffness.reserve(count);
    t.volume_over_length.reserve(count);
    t.partner_volume_over_length.reserve(count);
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (auto k = start[i]; k < start[i + 1]; ++k) {
      const Half& h = halves[k];
      if (k > start[i] && h.neighbor == halves[k - 1].neighbor) {
        t.stiffness.back() += h.area_stiffness / area[i];
        t.damage_weight.back() += h.damage_weight;
        if constexpr (state_based) {
          t.energy_stiffness.back() += h.own_energy_stiffness;
          t.volume_over_length.back() += h.own_volume_over_length;
          t.partner_volume_over_length.back() += h.area_volume_over_length / area[i];
        }
        continue;
      }
      const double dx = x[h.neighbor] - x[i], dy = y[h.neighbor] - y[i];
      t.neighbor.push_back(h.neighbor);
      t.xi_x.push_back(static_cast<float>(dx));
      t.xi_y.push_back(static_cast<float>(dy));
      t.rest_length.push_back(std::sqrt(dx * dx + dy * dy));
      t.stiffness.push_back(h.area_stiffness / area[i]);
      t.damage_weight.push_back(h.damage_weight);
      if constexpr (state_based) {
        t.energy_stiffness.push_back(h.own_energy_stiffness);
        t.volume_over_length.push_back(h.own_volume_over_length);
        t.partner_volume_over_length.push_back(h.area_volume_over_length / area[i]);
      }
    }
    t.offsets[i + 1] = t.neighbor.size();
  }
  return t;
}

}  // namespace

BondTable energy_bond_table(BondTable bonds, const std::vector<double>& x, const std::vector<double>& y,
                            const std::vector<double>& area) {
  if (bonds.volume_over_length.empty()) return symmetrised<HalfBond>(std::move(bonds), x, y, area);
  return symmetrised<StateHalfBond>(std::move(bonds), x, y, area);
}

double largest_stiffness_asymmetry(const BondTable& bonds, const std::vector<double>& area) {
  double largest = 0;
  for (std::uint32_t i = 0; i < bonds.particle_count; ++i)
    for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
      const auto j = bonds.neighbor[b];
      const auto r = reverse_bond(bonds, i, j);
      const double a = area[i] * bonds.stiffness[b];
      const double c = r < 0 ? 0.0 : area[j] * bonds.stiffness[static_cast<std::size_t>(r)];
      const double scale = std::max(a, c);
      if (scale > 0) largest = std::max(largest, std::fabs(a - c) / scale);
    }
  return largest;
}

}  // namespace pd::solver
