#include "energy_bonds.hpp"

#include <algorithm>
#include <cmath>

namespace pd::solver {
namespace {

struct HalfBond {
  std::uint32_t neighbor;
  double area_stiffness;  // A_i k_ij / 2 contributed by one direction
  float damage_weight;
};

// Index of the bond j -> i among j's bonds, or -1.
std::int64_t reverse_bond(const BondTable& bonds, std::uint32_t i, std::uint32_t j) {
  for (auto b = bonds.offsets[j]; b < bonds.offsets[j + 1]; ++b)
    if (bonds.neighbor[b] == i) return static_cast<std::int64_t>(b);
  return -1;
}

}  // namespace

BondTable energy_bond_table(BondTable bonds, const std::vector<double>& x, const std::vector<double>& y,
                            const std::vector<double>& area) {
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
  std::vector<HalfBond> halves(start[n]);
  {
    std::vector<std::uint64_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      for (auto b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b) {
        const auto j = bonds.neighbor[b];
        const double half = 0.5 * area[i] * bonds.stiffness[b];
        halves[next[i]++] = {j, half, bonds.damage_weight[b]};
        halves[next[j]++] = {static_cast<std::uint32_t>(i), half, 0.0f};
      }
  }
  // The halves hold all the output needs but the positions: the input goes now.
  const double critical_stretch = bonds.critical_stretch;
  std::vector<double> family_area = std::move(bonds.family_area);
  bonds = BondTable();
  // Each row by neighbour; a pair's two halves are merged into one bond.
  std::uint64_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto first = halves.begin() + static_cast<std::ptrdiff_t>(start[i]);
    const auto last = halves.begin() + static_cast<std::ptrdiff_t>(start[i + 1]);
    std::sort(first, last, [](const HalfBond& a, const HalfBond& b) { return a.neighbor < b.neighbor; });
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
  for (std::size_t i = 0; i < n; ++i) {
    for (auto k = start[i]; k < start[i + 1]; ++k) {
      const HalfBond& h = halves[k];
      if (k > start[i] && h.neighbor == halves[k - 1].neighbor) {
        t.stiffness.back() += h.area_stiffness / area[i];
        t.damage_weight.back() += h.damage_weight;
        continue;
      }
      const double dx = x[h.neighbor] - x[i], dy = y[h.neighbor] - y[i];
      t.neighbor.push_back(h.neighbor);
      t.xi_x.push_back(static_cast<float>(dx));
      t.xi_y.push_back(static_cast<float>(dy));
      t.rest_length.push_back(std::sqrt(dx * dx + dy * dy));
      t.stiffness.push_back(h.area_stiffness / area[i]);
      t.damage_weight.push_back(h.damage_weight);
    }
    t.offsets[i + 1] = t.neighbor.size();
  }
  return t;
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
