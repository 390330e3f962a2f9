#pragma once
// The bonds of a run, as every model and both solution methods set them up:
// the compact families, the quadrature weights, the surface-correction
// factors and the bonds the pre-cracks cut (theory.md Secs. 2-3). A model
// turns them into its per-bond constants (bond_constants<Model>), which is
// the one place where a bond's stiffness is formed.
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bond_table.hpp"
#include "bond_weights.hpp"
#include "compact_families.hpp"
#include "horizon_mode.hpp"
#include "particle_file.hpp"
#include "precrack.hpp"
#include "scene.hpp"
#include "surface_correction.hpp"

namespace pd::solver {

// The bond weights of a set-up (before the surface correction's factor) and
// the families they belong to, kept for the set-up of a later particle set
// that shares most of them (adaptive refinement; theory.md Sec. 8.4). Handed
// over by the simulation when its force field is made (one process): the
// weights moved out of the set-up, which the force field is done with (a
// copy before the factor when the surface correction folds it in), and the
// families the force field keeps for the run (a refinement run's always do),
// not copied.
struct KeptBondWeights {
  // The families: those of the simulation's force field (alive as long as
  // that simulation), else the set-up's, moved here.
  const Families* simulation_families = nullptr;
  Families own_families;
  const Families& families() const { return simulation_families ? *simulation_families : own_families; }
  PerBond<double> energy_weight;
  std::size_t computed = 0;  // listed bonds whose weights this set-up computed (the rest were taken over)
  PrecrackCuts precrack_cuts;  // the bonds the pre-cracks cut (empty without them)
};

// What a later set-up needs of the dual-horizon rows of the general
// particles of a lattice split (lattice_kernel.hpp) besides the rows
// themselves (adaptive refinement, theory.md Sec. 8.7): their entries'
// states at set-up (the pre-cracks' cuts; the run's breaks are not in it)
// and each particle's lattice membership. Empty when the set-up had no
// lattice. The table stays the simulation's (Simulation::lattice_general_rows):
// a copy of it would cost as much as the rows it saves building.
struct KeptGeneralRows {
  std::vector<std::uint8_t> intact;
  std::vector<std::uint8_t> is_lattice;
  std::size_t copied = 0;  // rows this set-up copied from the earlier set (the others were built)
};

// The dual-horizon row stiffness sums of an earlier particle set (the stable
// step's, dual_horizon_row_stiffness) to take over where a refinement event
// left a particle's row alone (theory.md Sec. 8.6).
struct EarlierRowStiffness {
  const std::vector<double>* sums = nullptr;  // per particle of the earlier set [N/m^4]
  // Per particle: the earlier set's particle with the same row (the same
  // bonds with the same constants, and the same dual entries in the same
  // order), or Families::none: its sum is computed.
  std::vector<std::uint32_t> same_row;
  // The earlier set's families: a particle whose family changed between a
  // stencil and a list (another order of its bonds) is computed.
  const Families* families = nullptr;
  // Per particle: its particle in the earlier set, or Families::none for a
  // child (new): whose stencil membership (rows_changed_by_event) and
  // lattice membership (KeptGeneralRows) it had.
  std::vector<std::uint32_t> origin;
  // The earlier set's general particles' rows (the lattice split), copied
  // with the new indices where the row and the lattice membership of its
  // particles are the same (theory.md Sec. 8.7): the table (its simulation's,
  // alive during this set-up) and what its set-up kept; null: all built.
  const BondTable* general_table = nullptr;
  const KeptGeneralRows* general_rows = nullptr;
  // Per particle, once found: 1 where its row may differ from its earlier
  // particle's (changed_rows, variable_horizon_bonds.hpp), for both the row
  // sums and the general rows of the set-up.
  mutable std::vector<std::uint8_t> changed_rows;
  // The refined set's longest possible bond [m] (longest_possible_bond,
  // families.hpp): the reach of particles_near. The simulation's copy of the
  // particles has no cells to form it from.
  double longest_bond = 0;
};

// The dual-horizon row stiffness sums of a set-up, kept for a later one.
struct KeptRowStiffness {
  std::vector<double> sums;  // per particle [N/m^4]; empty when the force field did not form them
  std::size_t computed = 0;  // sums this set-up computed (the rest were taken over)
};

// The whole plate's horizon mode and horizon (the largest with variable
// horizons), for a set-up on a part of it (a slab's band), whose particles
// alone may show another: a band of equal horizons in a plate whose
// horizons differ, a band without the plate's largest.
struct PlateHorizons {
  HorizonMode mode = HorizonMode::uniform;
  double horizon = 0;  // [m]
};

// Where set-up may keep what it computes, and what it may use.
struct SetupOptions {
  std::string surface_correction_cache;  // file for cached lambda; empty = compute, do not cache
  std::string particle_file_hash;        // cache key
  // Where factors that would replace a cache file of other factors wait for
  // the run's checks (DeferredCacheWrite; null: the cache is written at once).
  DeferredCacheWrite* deferred_cache = nullptr;
  // A cache of another folder whose factors fit this set-up (a switching
  // scene's quasi-static part: the dynamic part's in OUTDIR); empty: none.
  std::string shared_surface_correction_cache;
  // Factors kept back from that cache (not yet written there), read instead
  // of it where their key fits; null: none.
  const DeferredCacheWrite* shared_surface_correction_kept_back = nullptr;
  // Lattice squares through the structured-lattice kernel (lattice_kernel.hpp);
  // false = every particle through the neighbour lists (for comparisons).
  bool lattice_kernel = true;
  // Weights of an earlier set to take over where they are the same (null: compute all).
  const EarlierBondWeights* earlier_weights = nullptr;
  // Receives the families and weights of this set-up (null: not kept; one process only).
  KeptBondWeights* keep_weights = nullptr;
  // Distance moments of four-vertex cells kept across the set-ups of a run
  // (bond_weights.hpp; null: computed every time).
  CellDiskMemo* moment_memo = nullptr;
  // The bonds the pre-cracks cut, found before the families were collected
  // (precrack_cuts_after_event), whose particles the collector listed
  // (EarlierBondWeights::listed; null: found here).
  const PrecrackCuts* precrack_cuts = nullptr;
  // Dual-horizon row stiffness sums of an earlier set to take over (null: compute all),
  // and where to keep this set's (null: not kept). Bond-based dual-horizon runs on one process.
  const EarlierRowStiffness* earlier_row_stiffness = nullptr;
  KeptRowStiffness* keep_row_stiffness = nullptr;
  // Where to keep the general particles' rows of the lattice split (null: not kept).
  KeptGeneralRows* keep_general_rows = nullptr;
  // With the lattice kernel, the general particles' bonds among themselves
  // each pair once in single precision (LatticeModelSetup::general_pairs_in_float);
  // false = the double lists, each direction on its own (for comparisons).
  bool general_pairs_in_float = true;
  // The surface correction's factors whose fixed point couples the whole
  // plate (a bond-based model's scalar factors, surface_correction.hpp part
  // 3; the state-based dilatation factors, state_surface_correction.hpp);
  // false leaves them out (1, 0) for a distributed run to iterate on its
  // slabs (iterate_scalar_factors, iterate_dilatation_factors).
  bool coupled_factors = true;
  // The particles are a part of the plate (a slab's band): a pre-crack may
  // cut none of their bonds; BondSetup::bonds_cut_per_crack has the counts
  // for the caller to check on the whole plate (require_precrack_cuts).
  bool part_of_plate = false;
  // With part_of_plate: the whole plate's horizons (null: the particles').
  const PlateHorizons* plate_horizons = nullptr;
  // What the particle set is, for messages ("a fixed time.step above the
  // stable limit of NAME").
  std::string particle_set_name = "this particle set";
  // The simulation starts at rest (Simulation::start_at_rest: the initial
  // velocities, the forces and damage at rest, the arrivals and external work
  // at t = 0). false: a run's state is carried to it at once
  // (Simulation::continue_from, which evaluates the forces then), as on a
  // refinement event's refined set, whose evaluation at rest would be thrown away.
  bool start_at_rest = true;
  // One process: the force field keeps the set-up's families until
  // ForceField::release_families_kept_for_restart, for a restart between one
  // process and several, whose bond states go family by family through them
  // (runs/checkpoint_layout.hpp). Without it a lattice run keeps none.
  bool keep_families = false;
};

struct BondSetup {
  double horizon = 0;          // delta [m]; with variable horizons the largest
  HorizonMode horizon_mode = HorizonMode::uniform;
  std::vector<double> lambda;  // scalar surface-correction factor per particle (1 when off)
  // Direction-dependent shapes of the particles with listed families
  // (surface_correction.hpp); a bond with a stencil particle at either end
  // uses the scalar factors only.
  DirectionalShapes shapes;
  // The state-based model's dilatation factors (theory.md Sec. 5.7); empty
  // for bond-based models and without the correction.
  DirectionalShapes dilatation_shapes;
  int lambda_iterations = 0;
  bool lambda_from_cache = false;
  Families families;               // particles with a cut bond have listed families
  // E_ij of bond_weights.hpp [m^3], times the surface correction's angular
  // factor kappa(n_ij) when the correction is on (surface_correction.hpp).
  PerBond<double> energy_weight;
  std::vector<std::uint8_t> listed_intact;  // per listed bond: 0 if a pre-crack cut it
  std::size_t precrack_cut = 0;             // directed bonds cut
  std::vector<std::uint64_t> bonds_cut_per_crack;  // SetupOptions::part_of_plate only
  // The pieces the intact bonds hold together, and their count without the
  // pre-cracks' cuts: with pre-cracks, on the whole plate only (else 0).
  PlatePieces pieces;
  std::size_t pieces_without_cuts = 0;
  // Ordinary PD on variable horizons only (else 1): the largest ratio of the
  // horizons of a bond's two ends, max(delta_i / delta_j, delta_j / delta_i),
  // for the plan's warning that such a run does not conserve energy.
  double largest_bonded_horizon_ratio = 1;
};

// What set-up found, for the plan and summary.json.
struct SetupFacts {
  std::uint64_t bond_count = 0;  // directed bonds
  std::size_t precrack_cut = 0;  // directed bonds cut by pre-cracks
  int lambda_iterations = 0;     // of the surface correction (0 when off or cached)
  bool lambda_from_cache = false;
  HorizonMode horizon_mode = HorizonMode::uniform;
  PlatePieces pieces;                   // BondSetup::pieces
  std::size_t pieces_without_cuts = 0;  // BondSetup::pieces_without_cuts
  double largest_bonded_horizon_ratio = 1;  // BondSetup::largest_bonded_horizon_ratio (all processes)
};
inline SetupFacts facts_of(const BondSetup& setup) {
  return {setup.families.bond_count(), setup.precrack_cut, setup.lambda_iterations, setup.lambda_from_cache,
          setup.horizon_mode, setup.pieces, setup.pieces_without_cuts, setup.largest_bonded_horizon_ratio};
}

// `families`: those of `particles` (compact_families, or collected while
// reading the particle file).
BondSetup build_bond_setup(const Scene& scene, const ParticleSet& particles, Families families,
                           const SetupOptions& options);

// The horizon of a constant-horizon particle set; pd::Error if horizons differ
// (variable horizons go through horizon_mode.hpp instead).
double uniform_horizon(const ParticleSet& particles, const std::string& where);

// phi_ij A_j of the bond b [m^2], in single precision as the kernels hold
// it (BondConstants::damage_weight): the same for every model.
inline float bond_damage_weight(const ParticleSet& p, const BondRef& b) {
  return static_cast<float>(b.partial_volume * p.volume[b.neighbor]);
}

// The constants of the directed bond b of particle i (bond_table.hpp): a cut
// bond has zero stiffness (it carries no force whether or not damage is on).
struct BondConstants {
  double rest_length = 0;    // |xi_ij| [m]
  double stiffness = 0;      // k_ij [N/m^4], with the surface correction g_ij (surface_correction.hpp)
  // k_ij with i's own factor lambda_i S_i(n) for g_ij when the model's W_i
  // holds its own end's share of a bond's energy (Model::energy_at_own_end,
  // theory.md Sec. 5.7), else the stiffness.
  double energy_stiffness = 0;
  float damage_weight = 0;   // phi_ij A_j [m^2]
  bool intact = true;        // false if a pre-crack cut it
};
template <class Model>
BondConstants bond_constants(const ParticleSet& p, const BondSetup& setup, const typename Model::Constants& model,
                             std::uint32_t i, const BondRef& b) {
  const auto j = b.neighbor;
  BondConstants c;
  const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i];
  c.rest_length = std::hypot(dx, dy);
  c.intact = b.on_stencil || setup.listed_intact[b.index];
  c.stiffness = c.intact ? Model::bond_stiffness(model, bond_correction(setup.lambda, setup.shapes, i, j, dx, dy),
                                                 setup.energy_weight(b), c.rest_length)
                         : 0.0;
  c.energy_stiffness = c.stiffness;
  if constexpr (Model::energy_at_own_end)
    if (c.intact)
      c.energy_stiffness = Model::bond_stiffness(model, own_correction(setup.lambda, setup.shapes, i, j, dx, dy),
                                                 setup.energy_weight(b), c.rest_length);
  c.damage_weight = bond_damage_weight(p, b);
  return c;
}

// sum_j phi_ij A_j over i's family [m^2], summed over the float damage weights as the kernels do.
double family_area(const ParticleSet& particles, const BondSetup& setup, std::uint32_t i);

// The constants of any bond of a particle set, as a model forms them
// (bond_constants_of<Model>): what set-up code that is not itself a template
// over the model (the bond table, the lattice kernel's checks) calls.
using BondConstantsOf = std::function<BondConstants(std::uint32_t i, const BondRef& b)>;

template <class Model>
BondConstantsOf bond_constants_of(const ParticleSet& p, const BondSetup& setup,
                                  const typename Model::Constants& model) {
  return [&p, &setup, model](std::uint32_t i, const BondRef& b) { return bond_constants<Model>(p, setup, model, i, b); };
}

// The bond table of all particles, with the bonds i -> j for which keep(i, j)
// holds (all when keep is empty). `intact` (if not null) receives the bonds'
// states: 0 for cut bonds. family_area covers whole families, kept bonds or not.
// `critical_stretch`: the model's s0.
BondTable bond_table(const ParticleSet& particles, const BondSetup& setup, const BondConstantsOf& constants,
                     double critical_stretch, bool with_damage, std::vector<std::uint8_t>* intact = nullptr,
                     const std::function<bool(std::uint32_t, std::uint32_t)>& keep = {});

// V_ij of the dilatation of a state-based model (theory.md Secs. 5.2, 5.7):
// phi_ij A_j times the surface correction's dilatation factor D_ij, 0 across
// a pre-crack [m^2]. m_i is its sum over i's family.
inline double dilatation_volume(const ParticleSet& p, const BondSetup& setup, std::uint32_t i, const BondRef& b) {
  if (!(b.on_stencil || setup.listed_intact[b.index])) return 0.0;
  const auto j = b.neighbor;
  return b.partial_volume * p.volume[j] *
         dilatation_factor(setup.dilatation_shapes, i, j, p.x[j] - p.x[i], p.y[j] - p.y[i]);
}

// Fills t.volume_over_length and t.weighted_volume of a table built by
// bond_table (same bond order, no `keep`), for a state-based model: the
// dilatation's quadrature is the exact partial volumes phi_ij A_j, the same
// as the damage index's, times the dilatation factors of the surface
// correction (dilatation_volume; theory.md Secs. 5.2, 5.7).
void add_dilatation_weights(const ParticleSet& particles, const BondSetup& setup, BondTable& t);

// Stable time step of a state-based model (theory.md Sec. 5): the bound of
// stable_time_step below (a Gershgorin bound on the stiffness) with the
// dilatation's coupling added, dt_i = 2 sqrt(rho / R_i) with
// R_i = 2 sum_j k_ij + 16 |a| (g_i^2 / m_i^2 + sum_j (V_ij/|xi_ij|) g_j / m_j^2),
// g_i = sum_j V_ij / |xi_ij|; the smallest over the particles [s]. Streamed
// over the families as stable_time_step: no table of every bond (the lattice
// path never holds one; it would take 40 bytes per directed bond at its peak).
// `update_ghosts` (a process's local particles: owned ones with their whole
// families, then ghosts with none): gives every ghost its owner's
// g_j / m_j^2, the one value of a neighbour the bound reads (collective); a
// ghost's own bound is then 0 and not taken.
template <class Model>
double state_based_stable_time_step(const ParticleSet& p, const BondSetup& setup,
                                    const typename Model::Constants& model, double density,
                                    const std::function<void(std::vector<double>&)>* update_ghosts = nullptr) {
  const std::int64_t n = static_cast<std::int64_t>(p.size());
  const auto volume_over_length = [&](std::uint32_t i, const BondRef& b) {
    return dilatation_volume(p, setup, i, b) / std::hypot(p.x[b.neighbor] - p.x[i], p.y[b.neighbor] - p.y[i]);
  };
  std::vector<double> g(p.size(), 0.0), g_over_m2(p.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    const auto particle = static_cast<std::uint32_t>(i);
    double sum = 0, m = 0;  // g_i and m_i = sum_j V_ij
    setup.families.for_each_bond(particle, [&](const BondRef& b) {
      sum += volume_over_length(particle, b);
      m += dilatation_volume(p, setup, particle, b);
    });
    g[i] = sum;
    g_over_m2[i] = m > 0 ? sum / (m * m) : 0.0;
  }
  if (update_ghosts) (*update_ghosts)(g_over_m2);
  const double a = std::fabs(Model::dilatation_coefficient(model));
  double smallest = INFINITY;
#pragma omp parallel for schedule(static) reduction(min : smallest)
  for (std::int64_t i = 0; i < n; ++i) {
    const auto particle = static_cast<std::uint32_t>(i);
    double stiffness_sum = 0, neighbours = 0;
    setup.families.for_each_bond(particle, [&](const BondRef& b) {
      stiffness_sum += bond_constants<Model>(p, setup, model, particle, b).stiffness;
      neighbours += volume_over_length(particle, b) * g_over_m2[b.neighbor];
    });
    const double r = 2.0 * stiffness_sum + 16.0 * a * (g[i] * g_over_m2[i] + neighbours);
    if (r > 0) smallest = std::min(smallest, 2.0 * std::sqrt(density / r));
  }
  return smallest;
}

// Stable time step (theory.md Sec. 4, Silling & Askari 2005): dt_i = sqrt(2 rho / sum_j k_ij),
// the smallest over the particles [s].
template <class Model>
double stable_time_step(const ParticleSet& p, const BondSetup& setup, const typename Model::Constants& model,
                        double density) {
  double smallest = INFINITY;
  const std::int64_t n = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static) reduction(min : smallest)
  for (std::int64_t i = 0; i < n; ++i) {
    double stiffness_sum = 0;
    const auto particle = static_cast<std::uint32_t>(i);
    setup.families.for_each_bond(particle, [&](const BondRef& b) {
      stiffness_sum += bond_constants<Model>(p, setup, model, particle, b).stiffness;
    });
    if (stiffness_sum > 0) smallest = std::min(smallest, std::sqrt(2.0 * density / stiffness_sum));
  }
  return smallest;
}

}  // namespace pd::solver
