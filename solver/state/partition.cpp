#include "partition.hpp"

#include <algorithm>
#include <numeric>

#include "error.hpp"

namespace pd::solver {

std::vector<std::uint32_t> Partition::local_ids() const {
  std::vector<std::uint32_t> ids(owned);
  ids.insert(ids.end(), ghosts.begin(), ghosts.end());
  return ids;
}

Partition slab_partition(const ParticleSet& p, const Families& families, int rank, int size,
                         const std::string& where, GhostReach reach) {
  Partition part;
  part.rank = rank;
  part.size = size;
  part.whole_count = p.size();
  part.axis = (p.xmax - p.xmin) >= (p.ymax - p.ymin) ? 0 : 1;
  const std::vector<double>& position = part.axis == 0 ? p.x : p.y;
  const std::size_t n = p.size();

  // Particles in order along the axis; particles at the same position stay
  // together, so that a cut is a position and every process computes the
  // same owners from the same file.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return position[a] < position[b]; });
  double total = 0;
  for (std::uint32_t i = 0; i < n; ++i) total += static_cast<double>(families.family_size(i));

  std::vector<int> owner(n, 0);
  int slab = 0;
  double before = 0;  // bonds of the particles before the current position
  for (std::size_t k = 0; k < n;) {
    std::size_t end = k;
    double bonds = 0;
    while (end < n && position[order[end]] == position[order[k]]) bonds += families.family_size(order[end++]);
    // Start the next slab here when the slabs so far hold their share.
    if (k > 0 && slab + 1 < size && before >= total * (slab + 1) / size) {
      part.cuts.push_back(0.5 * (position[order[k - 1]] + position[order[k]]));
      ++slab;
    }
    for (std::size_t m = k; m < end; ++m) owner[order[m]] = slab;
    before += bonds;
    k = end;
  }
  if (slab + 1 != size)
    throw Error(where + ": cannot cut " + std::to_string(n) + " particles into " + std::to_string(size) +
                " slabs of balanced bonds along " + (part.axis == 0 ? "x" : "y") +
                "; run on fewer processes (mpirun -np)");

  std::vector<std::uint8_t> ghost(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (owner[i] != rank) continue;
    part.owned.push_back(i);
    part.owned_bonds += families.family_size(i);
    families.for_each_bond(i, [&](const BondRef& b) {
      if (owner[b.neighbor] != rank) ghost[b.neighbor] = 1;
    });
  }
  if (reach == GhostReach::bonds_both_ways)
    for (std::uint32_t j = 0; j < n; ++j) {
      if (owner[j] == rank) continue;
      families.for_each_bond(j, [&](const BondRef& b) {
        if (owner[b.neighbor] == rank) ghost[j] = 1;
      });
    }
  for (std::uint32_t i = 0; i < n; ++i)
    if (ghost[i]) {
      part.ghosts.push_back(i);
      part.ghost_owner.push_back(owner[i]);
    }
  return part;
}

}  // namespace pd::solver
