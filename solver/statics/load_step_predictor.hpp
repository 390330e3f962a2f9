#pragma once
// The first guess of a load step's equilibrium (theory.md Sec. 4.11): the
// last step's displacement increment extrapolated to the new load factor
// when that step broke no bond, else the last equilibrium scaled to it.
#include <cstdint>
#include <vector>

namespace pd::solver {

// `u`: the last equilibrium (x block, then y block) [m], at the last of
// `factors_done` (none: at rest), overwritten on its free components (`free`
// 1) with the guess at `factor`; the prescribed ones are left to the
// problem's set_load_factor. `last_increment`: u_k - u_k-1 of the last step
// when it broke no bond (then u_k + (q - q_k) / (q_k - q_k-1) (u_k - u_k-1),
// exact where u depends on q linearly or along a straight line), empty
// otherwise (then u_k q / q_k, exact for a linear response from rest).
void predict_load_step(std::vector<double>& u, const std::vector<std::uint8_t>& free,
                       const std::vector<double>& last_increment, const std::vector<double>& factors_done,
                       double factor);

}  // namespace pd::solver
