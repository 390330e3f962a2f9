#include "bonds.hpp"

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

BondTable build_bond_table(const ParticleSet& p, const PmbConstants& pmb, const std::vector<double>& lambda,
                           const std::vector<double>& energy_weights, bool with_damage) {
  BondTable t;
  const std::size_t n = p.size();
  t.particle_count = n;
  t.critical_stretch = pmb.critical_stretch;
  t.offsets = p.family_offsets;
  t.neighbor = p.neighbors;
  const std::size_t bonds = p.bond_count();
  t.rest_length.resize(bonds);
  t.stiffness.resize(bonds);
  if (with_damage) {
    t.damage_weight.resize(bonds);
    t.family_area.assign(n, 0.0);
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double family_area = 0;
    for (auto k = t.offsets[i]; k < t.offsets[i + 1]; ++k) {
      const auto j = t.neighbor[k];
      const double length = std::hypot(p.x[j] - p.x[i], p.y[j] - p.y[i]);
      const double area = p.partial_volume[k] * p.volume[j];
      t.rest_length[k] = length;
      t.stiffness[k] = 0.5 * (lambda[i] + lambda[j]) * pmb.micromodulus_area * energy_weights[k] / (length * length);
      if (with_damage) {
        t.damage_weight[k] = static_cast<float>(area);
        // Sum the stored float weights, as the kernel does.
        family_area += static_cast<double>(t.damage_weight[k]);
      }
    }
    if (with_damage) t.family_area[i] = family_area;
  }
  return t;
}

}  // namespace pd::solver
