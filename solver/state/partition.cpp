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

int SlabCuts::slab_of(double position) const {
  return static_cast<int>(std::lower_bound(cuts.begin(), cuts.end(), position) - cuts.begin());
}

FamilyLength file_family_lengths(const ParticleSet& p) {
  return [&p](std::uint32_t i) { return p.family_offsets[i + 1] - p.family_offsets[i]; };
}

SlabCuts slab_cuts(const ParticleSet& p, const FamilyLength& family_length, int size, const std::string& where) {
  SlabCuts slabs;
  slabs.axis = (p.xmax - p.xmin) >= (p.ymax - p.ymin) ? 0 : 1;
  const std::vector<double>& position = slabs.axis == 0 ? p.x : p.y;
  const std::size_t n = p.size();

  // Particles in order along the axis; particles at the same position stay
  // together, so that a cut is a position and every process computes the
  // same owners from the same file.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return position[a] < position[b]; });
  double total = 0;
  for (std::uint32_t i = 0; i < n; ++i) total += static_cast<double>(family_length(i));

  int slab = 0;
  double before = 0;  // bonds of the particles before the current position
  for (std::size_t k = 0; k < n;) {
    std::size_t end = k;
    double bonds = 0;
    while (end < n && position[order[end]] == position[order[k]]) bonds += family_length(order[end++]);
    // Start the next slab here when the slabs so far hold their share.
    if (k > 0 && slab + 1 < size && before >= total * (slab + 1) / size) {
      const double below = position[order[k - 1]], above = position[order[k]];
      // Half-way, unless that rounds onto the position above (two adjacent
      // doubles): a particle belongs to the slab above a cut when it lies above it.
      const double half_way = 0.5 * (below + above);
      slabs.cuts.push_back(half_way < above ? half_way : below);
      ++slab;
    }
    before += bonds;
    k = end;
  }
  if (slab + 1 != size)
    throw Error(where + ": cannot cut " + std::to_string(n) + " particles into " + std::to_string(size) +
                " slabs of balanced bonds along " + (slabs.axis == 0 ? "x" : "y") +
                "; run on fewer processes (mpirun -np)");
  return slabs;
}

namespace {

// The owned particles and ghosts of `rank` on the particles of `families`
// (set numbering), each particle's slab from its position; ids in the
// partition are `global_id`'s (identity when empty). `set_index`, if given:
// per local particle, its index in the set.
Partition partition_from_slabs(const ParticleSet& p, const Families& families, const SlabCuts& slabs, int rank,
                               const std::vector<std::uint32_t>& global_id, std::size_t whole_count,
                               GhostReach reach, std::vector<std::uint32_t>* set_index) {
  Partition part;
  part.rank = rank;
  part.size = static_cast<int>(slabs.cuts.size()) + 1;
  part.whole_count = whole_count;
  part.axis = slabs.axis;
  part.cuts = slabs.cuts;
  const std::vector<double>& position = part.axis == 0 ? p.x : p.y;
  const std::size_t n = p.size();
  const auto global = [&](std::uint32_t i) { return global_id.empty() ? i : global_id[i]; };
  std::vector<int> owner(n, 0);
  for (std::size_t i = 0; i < n; ++i) owner[i] = slabs.slab_of(position[i]);

  std::vector<std::uint32_t> local_index;
  std::vector<std::uint8_t> ghost(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (owner[i] != rank) continue;
    part.owned.push_back(global(i));
    local_index.push_back(i);
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
      part.ghosts.push_back(global(i));
      part.ghost_owner.push_back(owner[i]);
      local_index.push_back(i);
    }
  if (set_index) *set_index = std::move(local_index);
  return part;
}

}  // namespace

Partition slab_partition(const ParticleSet& p, const Families& families, int rank, int size,
                         const std::string& where, GhostReach reach) {
  const SlabCuts slabs =
      slab_cuts(p, [&families](std::uint32_t i) { return families.family_size(i); }, size, where);
  return partition_from_slabs(p, families, slabs, rank, {}, p.size(), reach, nullptr);
}

Partition slab_partition_of_part(const ParticleSet& p, const Families& families,
                                 const std::vector<std::uint32_t>& global_id,
                                 const std::vector<std::uint8_t>& family_complete, std::size_t whole_count,
                                 const SlabCuts& slabs, int rank, const std::string& where,
                                 std::vector<std::uint32_t>& part_index, GhostReach reach) {
  if (global_id.size() != p.size() || family_complete.size() != p.size())
    throw Error(where + ": " + std::to_string(global_id.size()) + " global ids for " + std::to_string(p.size()) +
                " particles of a part of the plate");
  Partition part = partition_from_slabs(p, families, slabs, rank, global_id, whole_count, reach, &part_index);
  const std::size_t whole_families = reach == GhostReach::bonds_both_ways ? part.local_count() : part.owned.size();
  for (std::size_t k = 0; k < whole_families; ++k)
    if (!family_complete[part_index[k]])
      throw Error(where + ": particle " + std::to_string(global_id[part_index[k]]) +
                  (k < part.owned.size() ? " of process " : ", a ghost of process ") + std::to_string(rank) +
                  (k < part.owned.size() ? "'s slab has" : "'s slab, has") +
                  " a family that reaches out of the particles read");
  return part;
}

}  // namespace pd::solver
