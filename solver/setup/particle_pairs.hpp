#pragma once
// Lists of particle pairs (i < j): the broken pairs that adaptive refinement
// carries from one particle set to the next (runs/adaptive_refinement.hpp,
// ForceField::broken_pairs, inherited_broken_pairs).
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace pd::solver {

using ParticlePair = std::pair<std::uint32_t, std::uint32_t>;

// `pairs` sorted (by i, then j) and without repeats, as std::sort and
// std::unique leave them: counted into one bucket per first particle, each
// bucket (a particle's partners, a few tens at most) sorted on its own. A
// crack's thousands of pairs cost a pass each, not a comparison sort.
inline std::vector<ParticlePair> sorted_unique_pairs(const std::vector<ParticlePair>& pairs) {
  std::vector<ParticlePair> sorted(pairs.size());
  if (pairs.empty()) return sorted;
  std::uint32_t last = 0;
  for (const auto& p : pairs) last = std::max(last, p.first);
  std::vector<std::size_t> start(std::size_t{last} + 2, 0);
  for (const auto& p : pairs) ++start[std::size_t{p.first} + 1];
  for (std::size_t a = 0; a + 1 < start.size(); ++a) start[a + 1] += start[a];
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (const auto& p : pairs) sorted[next[p.first]++] = p;
  for (std::size_t a = 0; a + 1 < start.size(); ++a)
    if (start[a + 1] - start[a] > 1)
      std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(start[a]),
                sorted.begin() + static_cast<std::ptrdiff_t>(start[a + 1]));
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  return sorted;
}

}  // namespace pd::solver
