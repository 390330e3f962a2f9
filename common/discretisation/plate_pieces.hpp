#pragma once
// The pieces a particle set falls into when only its bonds hold it together:
// one for a plate in one piece. The solver counts them with the pre-cracks'
// cuts (solver/setup/precrack.hpp), the mesher on the grid it wrote (a neck
// or a ligament left without a particle splits the plate).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pd {

// Each particle's piece, named by the smallest index of the piece's
// particles: union-find with path halving. `for_each_bond(i, join)` calls
// join(j) for every bond i-j that holds.
template <class ForEachBond>
std::vector<std::uint32_t> piece_roots(std::size_t particle_count, ForEachBond&& for_each_bond) {
  std::vector<std::uint32_t> parent(particle_count);
  for (std::size_t i = 0; i < particle_count; ++i) parent[i] = static_cast<std::uint32_t>(i);
  const auto root = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::uint32_t i = 0; i < particle_count; ++i)
    for_each_bond(i, [&](std::uint32_t j) {
      const std::uint32_t a = root(i), c = root(j);
      if (a != c) parent[a < c ? c : a] = a < c ? a : c;
    });
  for (std::uint32_t i = 0; i < particle_count; ++i) parent[i] = root(i);
  return parent;
}

}  // namespace pd
