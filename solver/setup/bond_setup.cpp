#include "bond_setup.hpp"

#include <cmath>

#include "error.hpp"
#include "precrack.hpp"
#include "surface_correction.hpp"

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

BondSetup build_bond_setup(const Scene& scene, const ParticleSet& p, Families families,
                           const SetupOptions& options) {
  BondSetup r;
  r.horizon = uniform_horizon(p, scene.particle_file);
  r.families = std::move(families);
  // Bonds a pre-crack cuts are listed (their particles leave the stencil).
  r.families.make_listed(particles_cut_by(p, r.families, scene.precracks));
  r.energy_weight = bond_energy_weights(p, r.families, r.horizon, scene.bond_weights);
  auto correction = surface_correction_for_run(scene.effects.surface_correction, scene.bond_weights, r.families,
                                               r.energy_weight, r.horizon, options.particle_file_hash,
                                               options.surface_correction_cache);
  r.lambda = std::move(correction.lambda);
  r.lambda_iterations = correction.iterations;
  r.lambda_from_cache = correction.from_cache;
  r.listed_intact.assign(r.families.neighbors.size(), 1);
  r.precrack_cut = apply_precracks(p, r.families, scene.precracks, r.listed_intact);
  return r;
}

double family_area(const ParticleSet& p, const BondSetup& r, std::uint32_t i) {
  double area = 0;
  r.families.for_each_bond(i, [&](const BondRef& b) {
    area += static_cast<double>(static_cast<float>(b.partial_volume * p.volume[b.neighbor]));
  });
  return area;
}

}  // namespace pd::solver
