#include "run_bonds.hpp"

#include "bond_weights.hpp"
#include "precrack.hpp"
#include "surface_correction.hpp"

namespace pd::solver {

RunBonds build_run_bonds(const Scene& scene, const ParticleSet& p, const std::string& particle_file_hash,
                         const std::string& cache_path, bool with_damage) {
  RunBonds r;
  const double horizon = uniform_horizon(p, scene.particle_file);
  r.pmb = pmb_constants(scene.material, horizon);
  const auto energy_weights = bond_energy_weights(p, horizon, scene.bond_weights);
  auto correction = surface_correction_for_run(scene.effects.surface_correction,
                                               scene.bond_weights == BondWeights::distance_moment, p,
                                               energy_weights, horizon, particle_file_hash, cache_path);
  r.lambda = std::move(correction.lambda);
  r.lambda_iterations = correction.iterations;
  r.lambda_from_cache = correction.from_cache;
  r.bonds = build_bond_table(p, r.pmb, r.lambda, energy_weights, with_damage);
  r.intact.assign(r.bonds.size(), 1);
  r.precrack_cut = apply_precracks(p, r.bonds, scene.precracks, r.intact);
  for (std::size_t b = 0; b < r.intact.size(); ++b)
    if (!r.intact[b]) r.bonds.stiffness[b] = 0;
  return r;
}

}  // namespace pd::solver
