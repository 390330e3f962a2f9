#include "bond_setup.hpp"

#include <algorithm>
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
                  std::to_string(p.horizon[i]) + " m); variable horizons need model.dual_horizon "
                  "(theory.md Sec. 6)");
  return delta;
}

namespace {

// The largest ratio of the horizons at a bond's two ends over all bonds (1
// on one horizon): one pass over the families, at set-up.
double largest_bonded_horizon_ratio(const ParticleSet& p, const Families& families) {
  double largest = 1;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    families.for_each_bond(i, [&](const BondRef& b) {
      if (b.neighbor >= p.size()) return;  // (a stencil's cell beyond a slab's band)
      const double hi = p.horizon[i], hj = p.horizon[b.neighbor];
      largest = std::max(largest, std::max(hi / hj, hj / hi));
    });
  return largest;
}

}  // namespace

BondSetup build_bond_setup(const Scene& scene, const ParticleSet& p, Families families,
                           const SetupOptions& options) {
  BondSetup r;
  if (options.plate_horizons) {
    r.horizon_mode = options.plate_horizons->mode;
    r.horizon = options.plate_horizons->horizon;
  } else {
    r.horizon_mode = horizon_mode(scene, p);
    r.horizon = r.horizon_mode == HorizonMode::uniform ? uniform_horizon(p, scene.particle_file) : largest_horizon(p);
  }
  r.families = std::move(families);
  // Only ordinary PD needs it (its warning, dynamic_run.cpp); no pass otherwise.
  if (r.horizon_mode == HorizonMode::ordinary_variable)
    r.largest_bonded_horizon_ratio = largest_bonded_horizon_ratio(p, r.families);
  // Bonds a pre-crack cuts are listed (their particles leave the stencil).
  PrecrackCuts cuts;
  cuts.particle_count = p.size();
  if (options.precrack_cuts) {
    cuts = *options.precrack_cuts;
  } else if (!scene.precracks.empty()) {
    cuts = precrack_cuts(p, r.families, scene.precracks, scene.path,
                         options.part_of_plate ? &r.bonds_cut_per_crack : nullptr);
  }
  // (A collector that listed the cut particles leaves none on a stencil.)
  if (std::any_of(cuts.particles.begin(), cuts.particles.end(),
                  [&](std::uint32_t i) { return r.families.on_stencil[i] != 0; }))
    r.families.make_listed(cuts.particles);
  std::size_t computed = 0;
  r.energy_weight = bond_energy_weights(p, r.families, scene.bond_weights, options.earlier_weights, &computed,
                                        options.moment_memo);
  r.listed_intact.assign(r.families.neighbors.size(), 1);
  r.precrack_cut = apply_precrack_cuts(r.families, cuts, r.listed_intact);
  // Whether the plate holds together (a warning in the plan): the pre-cracks
  // may cut it apart, and a grid may leave a neck or a ligament without a
  // particle. Once per run, on a set-up of the whole plate (not on a slab's
  // band, not again at a refinement event, which hands its cuts over).
  if (!options.precrack_cuts && !options.part_of_plate) {
    r.pieces = plate_pieces(r.families, r.listed_intact);
    r.pieces_without_cuts = r.pieces.count;
    if (r.pieces.count > 1 && r.precrack_cut > 0)
      r.pieces_without_cuts = plate_pieces(r.families, std::vector<std::uint8_t>(r.listed_intact.size(), 1)).count;
  }
  // (The families and, without the surface correction's factor, the weights
  // come later, from the simulation: KeptBondWeights.)
  if (options.keep_weights) {
    KeptBondWeights& kept = *options.keep_weights;
    kept = KeptBondWeights{};
    kept.computed = computed;
    kept.precrack_cuts = std::move(cuts);
    if (scene.effects.surface_correction) kept.energy_weight = r.energy_weight;
  }
  // The correction sees the pre-cracks' faces (cut bonds count as missing);
  // when on, it also folds its angular factor into the weights.
  SurfaceCorrectionResult correction;
  try {
    correction = surface_correction_for_run(scene, p, r.families, r.energy_weight, r.listed_intact, r.horizon,
                                            options.particle_file_hash, options.surface_correction_cache,
                                            options.coupled_factors, options.deferred_cache,
                                            options.shared_surface_correction_cache,
                                            options.shared_surface_correction_kept_back);
  } catch (const Error& e) {
    throw Error(scene.source_of("effects.surface_correction") + ": key 'effects.surface_correction' = true on " + scene.particle_file + ": " + e.what());
  }
  r.lambda = std::move(correction.correction.lambda);
  r.shapes = std::move(correction.correction.shapes);
  r.dilatation_shapes = std::move(correction.correction.dilatation);
  r.lambda_iterations = correction.iterations;
  r.lambda_from_cache = correction.from_cache;
  return r;
}

double family_area(const ParticleSet& p, const BondSetup& r, std::uint32_t i) {
  double area = 0;
  r.families.for_each_bond(i, [&](const BondRef& b) { area += static_cast<double>(bond_damage_weight(p, b)); });
  return area;
}

BondTable bond_table(const ParticleSet& p, const BondSetup& setup, const BondConstantsOf& constants,
                     double critical_stretch, bool with_damage, std::vector<std::uint8_t>* intact,
                     const std::function<bool(std::uint32_t, std::uint32_t)>& keep) {
  BondTable t;
  const std::size_t n = p.size();
  t.particle_count = n;
  t.critical_stretch = critical_stretch;
  t.offsets.assign(n + 1, 0);
  if (with_damage) t.family_area.assign(n, 0.0);
  if (intact) intact->clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    setup.families.for_each_bond(i, [&](const BondRef& b) {
      if (keep && !keep(i, b.neighbor)) return;
      const auto c = constants(i, b);
      t.neighbor.push_back(b.neighbor);
      t.xi_x.push_back(static_cast<float>(p.x[b.neighbor] - p.x[i]));
      t.xi_y.push_back(static_cast<float>(p.y[b.neighbor] - p.y[i]));
      t.rest_length.push_back(c.rest_length);
      t.stiffness.push_back(c.stiffness);
      // The energy's stiffness only once one differs (bond-based models and
      // runs without the correction never hold it).
      if (t.energy_stiffness.empty() && c.energy_stiffness != c.stiffness) t.energy_stiffness = t.stiffness;
      if (!t.energy_stiffness.empty()) {
        t.energy_stiffness.resize(t.stiffness.size());
        t.energy_stiffness.back() = c.energy_stiffness;
      }
      if (with_damage) t.damage_weight.push_back(c.damage_weight);
      if (intact) intact->push_back(c.intact ? 1 : 0);
    });
    t.offsets[i + 1] = t.neighbor.size();
    if (with_damage) t.family_area[i] = family_area(p, setup, i);
  }
  // The lists grew by doubling: up to half of their capacity would stay
  // unused for the whole run (a table of a few bonds per particle, as the
  // lattice kernel's general particles keep, is kept to the end).
  BondTable::for_each_entry_array([&t](const char*, auto member) { (t.*member).shrink_to_fit(); });
  if (intact) intact->shrink_to_fit();
  return t;
}

void add_dilatation_weights(const ParticleSet& p, const BondSetup& setup, BondTable& t) {
  t.volume_over_length.clear();
  t.volume_over_length.reserve(t.size());
  t.weighted_volume.assign(t.particle_count, 0.0);
  for (std::uint32_t i = 0; i < t.particle_count; ++i) {
    setup.families.for_each_bond(i, [&](const BondRef& b) {
      const double volume = dilatation_volume(p, setup, i, b);
      const double rest = std::hypot(p.x[b.neighbor] - p.x[i], p.y[b.neighbor] - p.y[i]);
      t.volume_over_length.push_back(volume / rest);
      t.weighted_volume[i] += volume;
    });
    if (t.volume_over_length.size() != t.offsets[i + 1])
      throw Error("add_dilatation_weights: the bond table does not hold every bond of the families");
  }
}

}  // namespace pd::solver
