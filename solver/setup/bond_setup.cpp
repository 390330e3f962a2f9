#include "bond_setup.hpp"

#include <cmath>

#include "bond_weights.hpp"
#include "precrack.hpp"
#include "surface_correction.hpp"

namespace pd::solver {

RunBonds build_run_bonds(const Scene& scene, const ParticleSet& p, Families families,
                         const std::string& particle_file_hash, const std::string& cache_path) {
  RunBonds r;
  const double horizon = uniform_horizon(p, scene.particle_file);
  r.pmb = pmb_constants(scene.material, horizon);
  r.families = std::move(families);
  // Bonds a pre-crack cuts are listed (their particles leave the stencil).
  r.families.make_listed(particles_cut_by(p, r.families, scene.precracks));
  r.energy_weight = bond_energy_weights(p, r.families, horizon, scene.bond_weights);
  auto correction = surface_correction_for_run(scene.effects.surface_correction,
                                               scene.bond_weights == BondWeights::distance_moment, r.families,
                                               r.energy_weight, horizon, particle_file_hash, cache_path);
  r.lambda = std::move(correction.lambda);
  r.lambda_iterations = correction.iterations;
  r.lambda_from_cache = correction.from_cache;
  r.listed_intact.assign(r.families.neighbors.size(), 1);
  r.precrack_cut = apply_precracks(p, r.families, scene.precracks, r.listed_intact);
  return r;
}

BondConstants bond_constants(const ParticleSet& p, const RunBonds& r, std::uint32_t i, const BondRef& b) {
  const auto j = b.neighbor;
  BondConstants c;
  c.rest_length = std::hypot(p.x[j] - p.x[i], p.y[j] - p.y[i]);
  c.intact = b.on_stencil || r.listed_intact[b.index];
  c.stiffness = c.intact ? 0.5 * (r.lambda[i] + r.lambda[j]) * r.pmb.micromodulus_area * r.energy_weight(b) /
                               (c.rest_length * c.rest_length)
                         : 0.0;
  c.damage_weight = static_cast<float>(b.partial_volume * p.volume[j]);
  return c;
}

double family_area(const ParticleSet& p, const RunBonds& r, std::uint32_t i) {
  double area = 0;
  r.families.for_each_bond(i, [&](const BondRef& b) {
    area += static_cast<double>(static_cast<float>(b.partial_volume * p.volume[b.neighbor]));
  });
  return area;
}

BondTable bond_table(const ParticleSet& p, const RunBonds& r, bool with_damage, std::vector<std::uint8_t>* intact,
                     const std::function<bool(std::uint32_t, std::uint32_t)>& keep) {
  BondTable t;
  const std::size_t n = p.size();
  t.particle_count = n;
  t.critical_stretch = r.pmb.critical_stretch;
  t.offsets.assign(n + 1, 0);
  if (with_damage) t.family_area.assign(n, 0.0);
  if (intact) intact->clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    r.families.for_each_bond(i, [&](const BondRef& b) {
      if (keep && !keep(i, b.neighbor)) return;
      const auto c = bond_constants(p, r, i, b);
      t.neighbor.push_back(b.neighbor);
      t.rest_length.push_back(c.rest_length);
      t.stiffness.push_back(c.stiffness);
      if (with_damage) t.damage_weight.push_back(c.damage_weight);
      if (intact) intact->push_back(c.intact ? 1 : 0);
    });
    t.offsets[i + 1] = t.neighbor.size();
    if (with_damage) t.family_area[i] = family_area(p, r, i);
  }
  return t;
}

double stable_time_step(const ParticleSet& p, const RunBonds& r, double density) {
  double smallest = INFINITY;
  const std::int64_t n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static) reduction(min : smallest)
  for (std::int64_t i = 0; i < n; ++i) {
    double stiffness_sum = 0;
    const auto particle = static_cast<std::uint32_t>(i);
    r.families.for_each_bond(particle, [&](const BondRef& b) { stiffness_sum += bond_constants(p, r, particle, b).stiffness; });
    if (stiffness_sum > 0) smallest = std::min(smallest, std::sqrt(2.0 * density / stiffness_sum));
  }
  return smallest;
}

}  // namespace pd::solver
