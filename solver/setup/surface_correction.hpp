#pragma once
// Surface correction (theory.md Sec. 3): bond factors that make the strain
// energy of the discretised body under any homogeneous deformation that of
// the continuum, next to edges, holes and pre-crack faces as in the bulk.
//
// Everything is computed once from the geometry (positions, cells, partial
// volumes, delta, the bonds pre-cracks cut): W_i and the continuum value are
// both proportional to c eps^2, so no model constant enters. Under a
// homogeneous strain, W_i is a combination of five angular moments of the
// particle's weighted family,
//   m_i = sum_j g_ij E_ij h(n_ij),   h(n) = (1, cos 2t, sin 2t, cos 4t, sin 4t),
// n = (cos t, sin t) the bond direction; the continuum's full disk has
//   T = (2 pi delta^3 / 3, 0, 0, 0, 0).
// Three parts:
//
//  1. Angular quadrature factor kappa(n) = b . h(n), one function for the
//     particle set, folded into the bond weights (E_ij -> kappa(n_ij) E_ij):
//     the interior squares' family (the stencil) then has exactly the moments
//     T. Without it the stencil is up to 3 % too stiff or too soft depending
//     on the strain's direction at m = 3 (cell-centre directions; the own
//     cell that no family holds).
//  2. Directional shape S_i(n) = 1 + d_i . h(n) of each particle whose family
//     is a list (not the stencil: the boundary layer of edges, holes and
//     pre-crack faces, free cells), from its own family: with S_i on its bonds
//     to other listed particles, its own moments sum_j S_i E_ij h have the
//     zeroth moment of its family and no others (an isotropic neighbourhood).
//     Bonds with a stencil particle at either end use S = 1, so the lattice
//     kernel's particles only ever see scalar factors. A particle whose bonds
//     to listed particles cannot carry five moments (too few directions:
//     corners, notch tips), or whose S_i would fall below
//     lowest_shape at one of those bonds, keeps S = 1.
//  3. Scalar factors lambda_i (the energy method, [Peng, Chen, Bobaru 2023,
//     Sec. 2]) on the shaped bonds, calibrated on the isotropic expansion
//     (every bond stretches equally) by fixed-point iteration:
//       sum_j (lambda_i S_i(n_ij) + lambda_j S_j(n_ij)) / 2 E_ij = T_0.
//
// A bond's factor is g_ij = (lambda_i S_i(n_ij) + lambda_j S_j(n_ij)) / 2.
// Each particle's isotropic energy is the continuum's (part 3), and summed
// over the body each particle's own share lambda_i S_i E_ij has isotropic
// moments, so the total strain energy under any homogeneous strain is the
// continuum's where A_i E_ij = A_j E_ji (exactly on uniform grids).
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bond_weights.hpp"
#include "compact_families.hpp"
#include "harmonic_moments.hpp"
#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::solver {

// Smallest directional shape S_i(n) accepted at a bond (part 2).
inline constexpr double lowest_shape = 0.25;

// The directional shapes S_i(n) = 1 + d_i . h(n) of the particles that have one.
struct DirectionalShapes {
  static constexpr std::uint32_t none = 0xffffffffu;
  std::vector<std::uint32_t> row;      // per particle: its row of `coefficients`, or none (all none when empty)
  std::vector<Harmonics> coefficients;  // d_i, one row per shaped particle, in particle order
  bool has(std::uint32_t i) const { return !row.empty() && row[i] != none; }
  std::size_t count() const { return coefficients.size(); }
};

// S_i(n) of particle i in the bond i -> j (direction (dx, dy)): 1 + d_i . h(n)
// when both have a directional shape, else 1.
inline double shape(const DirectionalShapes& shapes, std::uint32_t i, std::uint32_t j, double dx, double dy) {
  if (!shapes.has(i) || !shapes.has(j)) return 1.0;
  return 1.0 + harmonic_sum(shapes.coefficients[shapes.row[i]], bond_harmonics(dx, dy));
}

// lambda_i S_i(n): particle i's own factor in the bond i -> j with direction
// (dx, dy) = x_j - x_i.
inline double own_correction(const std::vector<double>& lambda, const DirectionalShapes& shapes,
                             std::uint32_t i, std::uint32_t j, double dx, double dy) {
  return lambda[i] * shape(shapes, i, j, dx, dy);
}

// g_ij = (lambda_i S_i(n) + lambda_j S_j(n)) / 2 of the bond i -> j with
// direction (dx, dy) = x_j - x_i.
inline double bond_correction(const std::vector<double>& lambda, const DirectionalShapes& shapes,
                              std::uint32_t i, std::uint32_t j, double dx, double dy) {
  return 0.5 * (own_correction(lambda, shapes, i, j, dx, dy) + own_correction(lambda, shapes, j, i, dx, dy));
}

// D_ij = 1 + (d_i + d_j) . h(n) / 2 of the bond i -> j with direction
// (dx, dy), the dilatation factor of the state-based model (theory.md
// Sec. 5.7, state_surface_correction.hpp): 1 unless both ends have a row.
inline double dilatation_factor(const DirectionalShapes& d, std::uint32_t i, std::uint32_t j, double dx, double dy) {
  if (!d.has(i) || !d.has(j)) return 1.0;
  const Harmonics h = bond_harmonics(dx, dy);
  return 1.0 + 0.5 * (harmonic_sum(d.coefficients[d.row[i]], h) + harmonic_sum(d.coefficients[d.row[j]], h));
}

struct SurfaceCorrection {
  Harmonics angular{1, 0, 0, 0, 0};  // b of kappa(n) (part 1)
  std::vector<double> lambda;         // per particle (part 3); 1 when the correction is off
  DirectionalShapes shapes;          // part 2; empty when the correction is off
  // The state-based model's dilatation factors d_i (theory.md Sec. 5.7);
  // empty for bond-based models and when the correction is off.
  DirectionalShapes dilatation;
};

struct SurfaceCorrectionResult {
  SurfaceCorrection correction;
  int iterations = 0;         // of the scalar factors (0 when cached)
  std::size_t fallbacks = 0;  // listed particles that keep S = 1 (not counted when cached)
  bool from_cache = false;
};

// The relative change of every factor below which the iterations of part 3
// (and of the state-based dilatation factors) stop.
inline constexpr double surface_correction_tolerance = 1e-7;

// Part 1: b of kappa(n) from the stencil of the particle file's spacing
// (families.levels[0]), with the weights `energy_weights`; (1, 0, 0, 0, 0)
// when there is no stencil.
Harmonics angular_quadrature_factor(const Families& families, const PerBond<double>& energy_weights,
                                    double horizon);

// Multiplies every bond weight by kappa(n_ij).
void apply_angular_factor(const ParticleSet& particles, const Families& families, const Harmonics& angular,
                          PerBond<double>& energy_weights);

// Parts 2 and 3 on weights that already carry kappa. Bonds that carry force:
// all stencil bonds, and the listed bonds with listed_intact[b.index] != 0 (a
// pre-crack cuts the others). The scalar iteration stops when every factor
// changes by less than `tolerance`, relative. Without `scalar_factors` part 3
// is left out (lambda = 1, no iterations): a distributed run iterates it on
// its slabs (iterate_scalar_factors with an exchange).
SurfaceCorrectionResult compute_surface_correction(const ParticleSet& particles, const Families& families,
                                                   const PerBond<double>& energy_weights,
                                                   const std::vector<std::uint8_t>& listed_intact, double horizon,
                                                   double tolerance = surface_correction_tolerance,
                                                   bool scalar_factors = true);

// What a factor iteration whose fixed point couples the whole plate (the
// scalar factors here, the state-based dilatation factors,
// state_surface_correction.hpp) needs from the other processes of a
// distributed run (docs/solver.md, "Running on several processes (MPI)"):
// each process updates the particles whose families it holds (its owned
// ones; a ghost has no family locally and keeps its value), then
// `update_ghosts` gives every ghost its owner's new value (one value per
// local particle) and `largest` takes the largest change over all
// processes, so that every process stops at the same iteration.
struct ScalarFactorExchange {
  std::function<void(std::vector<double>&)> update_ghosts;
  std::function<double(double)> largest;
};

// Part 3 alone (theory.md Sec. 3): lambda from 1 by the fixed point
// lambda_i <- lambda_i T_0 / W_i, every particle's update reading only its
// own family's previous factors. With `exchange` on a process's local
// particles (owned ones with their whole families, then ghosts with none),
// each owned factor takes the same operations in the same order as on the
// whole plate, so the factors equal a one-process run's bit for bit.
// Returns the iterations; pd::Error when it does not converge.
int iterate_scalar_factors(const ParticleSet& particles, const Families& families,
                           const PerBond<double>& energy_weights, const std::vector<std::uint8_t>& listed_intact,
                           const DirectionalShapes& shapes, double horizon, double tolerance,
                           std::vector<double>& lambda, const ScalarFactorExchange* exchange = nullptr);

// Factors computed (or read from another folder's cache) that the folder's
// cache does not hold: kept back until the run that computed them has passed
// its checks, then written, so that a run refused after its set-up leaves the
// folder as it found it: an earlier run's cache, which its --restart reads,
// as it was, and no cache where there was none (before 7 December 2026 a
// refused run left its factors in a folder without a cache).
struct DeferredCacheWrite {
  std::string path, key;  // empty: nothing kept back
  SurfaceCorrection factors;
  // Writes the factors kept back, once (atomically); nothing when none are.
  void write();
};

// What a run uses. With the correction off: kappa = 1, lambda = 1, no
// shapes, `energy_weights` unchanged. On: kappa is applied to
// `energy_weights`, then parts 2 and 3 are computed (for the state-based
// model its own factors instead, state_surface_correction.hpp), through the cache file
// `cache_path` when it is not empty (keyed by `particle_file_hash`, the
// horizon, the bond weighting, the pre-cracks and the method; a missing,
// stale or corrupt cache is recomputed and rewritten atomically; with
// `deferred`, the cache file is not written here: the factors wait there for
// DeferredCacheWrite::write). `shared_cache`: a cache of another
// folder read where `cache_path` does not hold these factors (a switching
// scene's quasi-static part takes its dynamic part's); the factors found
// there are written to `cache_path` as computed ones are.
// `shared_kept_back`: factors kept back from `shared_cache` (not yet written
// there), read instead of it where their key fits.
// Without `coupled_factors` the factors whose fixed point couples the whole
// plate are left out (part 3's scalar factors, 1; the state-based model's
// dilatation factors, 0) for a distributed run to iterate on its slabs, and
// the cache is neither read nor written.
SurfaceCorrectionResult surface_correction_for_run(const Scene& scene, const ParticleSet& particles,
                                                   const Families& families, PerBond<double>& energy_weights,
                                                   const std::vector<std::uint8_t>& listed_intact, double horizon,
                                                   const std::string& particle_file_hash,
                                                   const std::string& cache_path, bool coupled_factors = true,
                                                   DeferredCacheWrite* deferred = nullptr,
                                                   const std::string& shared_cache = {},
                                                   const DeferredCacheWrite* shared_kept_back = nullptr);

}  // namespace pd::solver
