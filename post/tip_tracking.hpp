#pragma once
// Crack tips: the tip of a branch at time t is its most advanced particle,
// the one farthest from the branch's origin among those cracked by t
// (theory.md Sec. 9). Sampled every solver time step.
#include <vector>

#include "arrival_data.hpp"
#include "crack_branches.hpp"

namespace pd::post {

struct TipPath {
  int branch = 0;
  std::vector<double> time;  // [s], start_time + k * time_step up to end_time
  std::vector<double> x, y;  // tip position [m]
};

TipPath track_tip(const CrackBranch& branch, const ArrivalData& data, double time_step);
std::vector<TipPath> track_tips(const CrackNetwork& network, const ArrivalData& data);

// Length of the tip's path (sum of its moves) [m].
double tip_path_length(const TipPath& path);

}  // namespace pd::post
