#pragma once
// Damage of one run measured against another run's crack (e.g. a coarse or
// adaptive run against the fine run of the same plate): how much of this
// run's damage lies away from where the reference run is damaged
// (docs/post.md, "Comparing with a reference run").
#include <cstddef>
#include <string>

#include "arrival_data.hpp"

namespace pd::post {

struct DamageComparison {
  std::string reference;             // the reference run's arrival.vtp
  double band = 0;                   // [m] half-width of the band around the reference's damage
  double damage_level = 0;           // a particle is damaged at final damage >= this
  std::size_t reference_damaged = 0; // particles of the reference at or above the level
  std::size_t damaged = 0;           // particles of this run at or above the level
  std::size_t outside = 0;           // ... of them farther than `band` from every damaged reference particle
  double area_outside = 0;           // [m^2] their cells (cell_size squared)
};

// Brute force would be O(N M); a grid of buckets of side `band` over the
// reference's damaged particles makes each query look at 3 x 3 buckets.
DamageComparison compare_damage(const ArrivalData& run, const ArrivalData& reference, double band,
                                double damage_level);

}  // namespace pd::post
