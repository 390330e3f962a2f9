#include "bond_table.hpp"

#include <cmath>

#include "error.hpp"

namespace pd::solver {

double uniform_horizon(const ParticleSet& p, const std::string& where) {
  if (p.size() == 0) throw Error(where + ": the particle set is empty");
  const double delta = p.horizon[0];
  for (std::size_t i = 1; i < p.size(); ++i)
    if (std::fabs(p.horizon[i] - delta) > 1e-9 * delta)
      throw Error(where + ": particles have different horizons (e.g. " + std::to_string(delta) + " m and " +
                  std::to_string(p.horizon[i]) + " m); variable horizons need the dual-horizon model, "
                  "which is not implemented yet");
  return delta;
}

}  // namespace pd::solver
