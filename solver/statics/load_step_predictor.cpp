#include "load_step_predictor.hpp"

namespace pd::solver {

void predict_load_step(std::vector<double>& u, const std::vector<std::uint8_t>& free,
                       const std::vector<double>& last_increment, const std::vector<double>& factors_done,
                       double factor) {
  if (factors_done.empty()) return;  // at rest: nothing to go on (the first step starts from 0)
  const double last = factors_done.back();
  const double before = factors_done.size() > 1 ? factors_done[factors_done.size() - 2] : 0.0;
  if (!last_increment.empty() && last != before) {
    // Along the last step's increment: elastic steps follow a nearly straight
    // path (geometric nonlinearity only), so the guess is off by the path's
    // curvature times the steps' product, not by the step itself.
    const double ratio = (factor - last) / (last - before);
    for (std::size_t c = 0; c < u.size(); ++c)
      if (free[c]) u[c] += ratio * last_increment[c];
    return;
  }
  if (last == 0) return;
  // Scaled (after bonds broke the last increment holds the crack's opening,
  // which the next step does not repeat).
  const double scale = factor / last;
  for (std::size_t c = 0; c < u.size(); ++c)
    if (free[c]) u[c] *= scale;
}

}  // namespace pd::solver
