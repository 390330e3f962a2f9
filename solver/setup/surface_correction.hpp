#pragma once
// Surface correction by the energy method (theory.md Sec. 3, [Peng, Chen,
// Bobaru 2023, Sec. 2]): one factor lambda_i per particle such that, under a
// reference homogeneous strain, every particle's strain energy density
// W_i = sum_j 0.5 (lambda_i + lambda_j) w_ij equals the continuum value W0.
//
// Reference strain: isotropic expansion eps_xx = eps_yy = eps (every bond
// stretches by exactly eps, whatever its direction). A single scalar factor
// per particle cannot correct a uniaxial strain along x and along y at once
// near an edge; the isotropic state is the direction-neutral choice. W0 is
// the continuum closed form over the full disk of radius delta:
//   W0 = int_disk 1/4 c eps^2 |xi| dA = pi c eps^2 delta^3 / 6  (= 1.5 E eps^2, plane stress).
// Because W_i and W0 are both proportional to c eps^2, lambda depends only on
// the geometry (positions, areas, phi, delta).
#include <string>
#include <vector>

#include "bond_weights.hpp"
#include "compact_families.hpp"

namespace pd::solver {

struct SurfaceCorrectionResult {
  std::vector<double> lambda;
  int iterations = 0;
  bool from_cache = false;
};

// Fixed-point iteration lambda_i <- lambda_i W0 / W_i from lambda = 1 until
// every lambda changes by less than `tolerance` (relative). `energy_weights` =
// E_ij of bond_weights.hpp: under the isotropic expansion W_i = 1/4 c eps^2
// sum_j 0.5 (lambda_i + lambda_j) E_ij and W0 = 1/4 c eps^2 (2 pi delta^3 / 3).
SurfaceCorrectionResult compute_surface_correction(const Families& families,
                                                   const PerBond<double>& energy_weights, double horizon,
                                                   double tolerance = 1e-7);

// Same, cached in `cache_path` under a key made of `particle_file_hash`, the
// horizon, the weighting (`weights_name`) and the tolerance; a missing, stale or corrupt cache is recomputed
// and rewritten (atomically).
SurfaceCorrectionResult cached_surface_correction(const Families& families,
                                                  const PerBond<double>& energy_weights, double horizon,
                                                  const std::string& weights_name,
                                                  const std::string& particle_file_hash,
                                                  const std::string& cache_path, double tolerance = 1e-7);

// What a run uses: lambda = 1 everywhere when the scene has the surface
// correction off; otherwise computed, through the cache when `cache_path` is
// not empty (shared by the dynamic and the quasi-static solver).
SurfaceCorrectionResult surface_correction_for_run(bool enabled, BondWeights weights, const Families& families,
                                                   const PerBond<double>& energy_weights, double horizon,
                                                   const std::string& particle_file_hash,
                                                   const std::string& cache_path);

}  // namespace pd::solver
