#pragma once
// The bonds of a run, as the dynamic and the quasi-static solver both set
// them up: PMB constants, bond weights, surface-correction factors, the bond
// table, and the bonds the pre-cracks cut (theory.md Secs. 1-3).
#include <cstdint>
#include <string>
#include <vector>

#include "bonds.hpp"
#include "particle_file.hpp"
#include "pmb_material.hpp"
#include "scene.hpp"

namespace pd::solver {

struct RunBonds {
  PmbConstants pmb;
  std::vector<double> lambda;  // surface-correction factor per particle (1 when off)
  int lambda_iterations = 0;
  bool lambda_from_cache = false;
  // Cut bonds have zero stiffness (they carry no force whether or not damage is on).
  BondTable bonds;
  std::vector<std::uint8_t> intact;  // per bond: 0 for the bonds a pre-crack cut
  std::size_t precrack_cut = 0;
};

// `particle_file_hash` and `cache_path` key the surface-correction cache
// (empty cache path: compute, do not cache). `with_damage`: the table carries
// the damage weights.
RunBonds build_run_bonds(const Scene& scene, const ParticleSet& particles, const std::string& particle_file_hash,
                         const std::string& cache_path, bool with_damage);

}  // namespace pd::solver
