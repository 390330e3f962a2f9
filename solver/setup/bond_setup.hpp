#pragma once
// The bonds of a run, as the dynamic and the quasi-static solver both set
// them up: PMB constants, bond weights, surface-correction factors, and the
// bonds the pre-cracks cut (theory.md Secs. 1-3), over the compact families
// (families.hpp). Every per-bond constant comes from `bond_constants`.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bond_table.hpp"
#include "compact_families.hpp"
#include "particle_file.hpp"
#include "pmb.hpp"
#include "scene.hpp"

namespace pd::solver {

struct RunBonds {
  PmbConstants pmb;
  std::vector<double> lambda;  // surface-correction factor per particle (1 when off)
  int lambda_iterations = 0;
  bool lambda_from_cache = false;
  Families families;               // particles with a cut bond have listed families
  PerBond<double> energy_weight;   // E_ij of bond_weights.hpp [m^3]
  std::vector<std::uint8_t> listed_intact;  // per listed bond: 0 if a pre-crack cut it
  std::size_t precrack_cut = 0;             // directed bonds cut
};

// `particle_file_hash` and `cache_path` key the surface-correction cache
// (empty cache path: compute, do not cache). `families`: those of `particles`
// (compact_families, or collected while reading the file).
RunBonds build_run_bonds(const Scene& scene, const ParticleSet& particles, Families families,
                         const std::string& particle_file_hash, const std::string& cache_path);

// The constants of the directed bond b of particle i (bonds.hpp): a cut bond
// has zero stiffness (it carries no force whether or not damage is on).
struct BondConstants {
  double rest_length = 0;    // |xi_ij| [m]
  double stiffness = 0;      // k_ij [N/m^4]
  float damage_weight = 0;   // phi_ij A_j [m^2]
  bool intact = true;        // false if a pre-crack cut it
};
BondConstants bond_constants(const ParticleSet& particles, const RunBonds& bonds, std::uint32_t i, const BondRef& b);

// sum_j phi_ij A_j over i's family [m^2], summed over the float damage weights as the kernels do.
double family_area(const ParticleSet& particles, const RunBonds& bonds, std::uint32_t i);

// The bond table of all particles, with the bonds i -> j for which keep(i, j)
// holds (all when keep is empty). `intact` (if not null) receives the bonds'
// states: 0 for cut bonds. family_area covers whole families, kept bonds or not.
BondTable bond_table(const ParticleSet& particles, const RunBonds& bonds, bool with_damage,
                     std::vector<std::uint8_t>* intact = nullptr,
                     const std::function<bool(std::uint32_t, std::uint32_t)>& keep = {});

// Stable time step (theory.md Sec. 4, Silling & Askari 2005): dt_i = sqrt(2 rho / sum_j k_ij),
// the smallest over the particles [s].
double stable_time_step(const ParticleSet& particles, const RunBonds& bonds, double density);

}  // namespace pd::solver
