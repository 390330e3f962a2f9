#pragma once
// Crack tips: the tip of a branch at time t is its most advanced particle,
// the one farthest from the branch's origin among those cracked by t
// ([Peng, Chen, Bobaru 2023, App. 2]). Sampled every solver time step from the time the
// branch has a tip of its own (tip_start_time) to its end.
#include <vector>

#include "arrival_data.hpp"
#include "crack_branches.hpp"

namespace pd::post {

struct TipPath {
  int branch = 0;
  std::vector<double> time;  // [s], tip_start_time + k * time_step up to end_time
  std::vector<double> x, y;  // tip position [m]
  // Where the branch's length is measured from [m]: its origin (a child's
  // branching point, where a crack of its own started), or for a pre-crack
  // the tip it grows from (the first sample).
  double start_x = 0, start_y = 0;
};

// First time at which a branch has a tip: the arrival of its first particle
// (a child's branching point can lie where only its parent had cracked, so
// a tip there would stand still and then jump onto the child's particles);
// for a pre-crack (particles cracked at t = 0), the last step before it grows.
double tip_start_time(const CrackBranch& branch, const ArrivalData& data, double time_step);

TipPath track_tip(const CrackBranch& branch, const ArrivalData& data, double time_step);
std::vector<TipPath> track_tips(const CrackNetwork& network, const ArrivalData& data);

// Length of the crack a tip path traced [m]: the polyline from its start
// through the tip's positions with vertices at least `min_step` apart
// (pd-post: two horizons),
// so that the tip's hops among the particles of the damage band (sideways
// and back, below a horizon) do not count. A straight path gives its chord.
double tip_path_length(const TipPath& path, double min_step);

}  // namespace pd::post
