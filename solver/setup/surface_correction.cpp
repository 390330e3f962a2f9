#include "surface_correction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "atomic_file.hpp"
#include "binary_codec.hpp"
#include "error.hpp"
#include "state_surface_correction.hpp"

namespace pd::solver {

namespace {

using moments::K;
using moments::Matrix;
using moments::add_outer;
using moments::cholesky;
using moments::cholesky_solve;
Harmonics full_disk_moments(double horizon) { return moments::full_disk(horizon); }

bool intact(const BondRef& b, const std::vector<std::uint8_t>& listed_intact) {
  return b.on_stencil || listed_intact[b.index];
}

// ---- Part 2: the directional shape of listed particle i (false: none).
bool directional_shape(const ParticleSet& p, const Families& families, const PerBond<double>& weight,
                       const std::vector<std::uint8_t>& listed_intact, std::uint32_t i, Harmonics& d) {
  Harmonics own{};  // sum_j E_ij h(n_ij) over all intact bonds
  Matrix gram{};    // sum of E_ij h h^T over the intact bonds to listed particles
  families.for_each_bond(i, [&](const BondRef& b) {
    if (!intact(b, listed_intact)) return;
    const auto j = b.neighbor;
    const Harmonics h = bond_harmonics(p.x[j] - p.x[i], p.y[j] - p.y[i]);
    const double e = weight(b);
    for (std::size_t k = 0; k < K; ++k) own[k] += e * h[k];
    if (!families.on_stencil[j]) add_outer(gram, e, h);
  });
  if (!cholesky(gram)) return false;
  Harmonics rhs{};  // keep the zeroth moment, remove the others
  for (std::size_t k = 1; k < K; ++k) rhs[k] = -own[k];
  d = cholesky_solve(gram, rhs);
  bool acceptable = true;
  families.for_each_bond(i, [&](const BondRef& b) {
    const auto j = b.neighbor;
    if (!intact(b, listed_intact) || families.on_stencil[j]) return;
    if (1 + harmonic_sum(d, bond_harmonics(p.x[j] - p.x[i], p.y[j] - p.y[i])) < lowest_shape)
      acceptable = false;
  });
  return acceptable;
}

}  // namespace

// ---- Part 3: the scalar factors by fixed-point iteration, on the shaped bonds.
int iterate_scalar_factors(const ParticleSet& p, const Families& families, const PerBond<double>& weight,
                           const std::vector<std::uint8_t>& listed_intact, const DirectionalShapes& shapes,
                           double horizon, double tolerance, std::vector<double>& lambda,
                           const ScalarFactorExchange* exchange) {
  constexpr int max_iterations = 10000;
  const std::size_t n = families.particle_count;
  const double target = full_disk_moments(horizon)[0];
  // Per bond of a shaped particle, in for_each_bond order: S_i(n), S_j(n).
  std::vector<std::uint64_t> first(n + 1, 0);
  for (std::uint32_t i = 0; i < n; ++i) first[i + 1] = first[i] + (shapes.has(i) ? families.family_size(i) : 0);
  std::vector<std::array<double, 2>> bond_shapes(first[n]);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(n); ++i) {
    const auto particle = static_cast<std::uint32_t>(i);
    if (!shapes.has(particle)) continue;
    auto out = first[particle];
    families.for_each_bond(particle, [&](const BondRef& b) {
      const auto j = b.neighbor;
      bond_shapes[out++] = {shape(shapes, particle, j, p.x[j] - p.x[i], p.y[j] - p.y[i]),
                       shape(shapes, j, particle, p.x[j] - p.x[i], p.y[j] - p.y[i])};
    });
  }
  lambda.assign(n, 1.0);
  std::vector<double> next(n);
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    double largest_change = 0;
#pragma omp parallel for schedule(static) reduction(max : largest_change)
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(n); ++i) {
      double w = 0;
      const bool has_shapes = shapes.has(static_cast<std::uint32_t>(i));
      auto k = first[i];
      families.for_each_bond(static_cast<std::uint32_t>(i), [&](const BondRef& b) {
        const std::array<double, 2> s = has_shapes ? bond_shapes[k++] : std::array<double, 2>{1, 1};
        if (intact(b, listed_intact)) w += 0.5 * (lambda[i] * s[0] + lambda[b.neighbor] * s[1]) * weight(b);
      });
      if (!(w > 0)) {
        next[i] = lambda[i];  // an isolated particle has no bonds to correct
        continue;
      }
      next[i] = lambda[i] * target / w;
      largest_change = std::max(largest_change, std::fabs(next[i] - lambda[i]) / lambda[i]);
    }
    lambda.swap(next);
    if (exchange) {
      exchange->update_ghosts(lambda);
      largest_change = exchange->largest(largest_change);
    }
    if (largest_change < tolerance) return iteration;
  }
  std::ostringstream m;
  m << "surface correction did not converge to " << tolerance << " in " << max_iterations << " iterations";
  throw Error(m.str());
}

Harmonics angular_quadrature_factor(const Families& families, const PerBond<double>& weight, double horizon) {
  if (families.levels.empty() || families.levels[0].size() == 0 || families.stencil_particle_count(0) == 0)
    return {1, 0, 0, 0, 0};
  const StencilLevel& level = families.levels[0];
  Matrix gram{};
  for (std::size_t o = 0; o < level.size(); ++o)
    add_outer(gram, weight.stencil[0][o], bond_harmonics(static_cast<double>(level.di[o]), static_cast<double>(level.dj[o])));
  if (!cholesky(gram))
    throw Error("the surface correction's angular factor needs more bond directions than the " +
                std::to_string(level.size()) +
                " bonds of the interior stencil give (horizon factors below 2, e.g. --horizon-factor 1.5, have too "
                "few); use a larger horizon factor or set effects.surface_correction = false");
  return cholesky_solve(gram, full_disk_moments(horizon));
}

void apply_angular_factor(const ParticleSet& p, const Families& families, const Harmonics& angular,
                          PerBond<double>& weight) {
  for (std::size_t l = 0; l < families.levels.size(); ++l) {
    const StencilLevel& level = families.levels[l];
    for (std::size_t o = 0; o < level.size(); ++o)
      weight.stencil[l][o] *= harmonic_sum(angular, bond_harmonics(static_cast<double>(level.di[o]),
                                                                   static_cast<double>(level.dj[o])));
  }
  for (std::uint32_t i = 0; i < families.particle_count; ++i)
    for (auto b = families.offsets[i]; b < families.offsets[i + 1]; ++b) {
      const auto j = families.neighbors[b];
      weight.listed[b] *= harmonic_sum(angular, bond_harmonics(p.x[j] - p.x[i], p.y[j] - p.y[i]));
    }
}

SurfaceCorrectionResult compute_surface_correction(const ParticleSet& p, const Families& families,
                                                   const PerBond<double>& weight,
                                                   const std::vector<std::uint8_t>& listed_intact, double horizon,
                                                   double tolerance, bool scalar_factors) {
  SurfaceCorrectionResult result;
  const std::size_t n = families.particle_count;
  std::vector<Harmonics> d(n);
  enum : std::uint8_t { unshaped, shaped, fallback };
  std::vector<std::uint8_t> kind(n, unshaped);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(n); ++i) {
    const auto particle = static_cast<std::uint32_t>(i);
    if (families.on_stencil[particle] || families.family_size(particle) == 0) continue;
    kind[particle] = directional_shape(p, families, weight, listed_intact, particle, d[particle]) ? shaped : fallback;
  }
  DirectionalShapes& shapes = result.correction.shapes;
  shapes.row.assign(n, DirectionalShapes::none);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (kind[i] == fallback) ++result.fallbacks;
    if (kind[i] != shaped) continue;
    shapes.row[i] = static_cast<std::uint32_t>(shapes.coefficients.size());
    shapes.coefficients.push_back(d[i]);
  }
  if (!scalar_factors) {
    result.correction.lambda.assign(n, 1.0);
    return result;
  }
  result.iterations = iterate_scalar_factors(p, families, weight, listed_intact, shapes, horizon, tolerance,
                                             result.correction.lambda);
  return result;
}

namespace {
constexpr char cache_magic[8] = {'P', 'D', 'S', 'C', 'F', '0', '0', '3'};

// The method names the factors: the bond-based models' (parts 2 and 3) or the
// state-based model's moment equations (state_surface_correction.hpp).
std::string cache_key(const std::string& hash, double horizon, const std::string& weights,
                      const std::vector<PrecrackSpec>& precracks, double tolerance, std::size_t n, bool state_based) {
  char text[512];
  std::snprintf(text, sizeof text,
                "particles=%s horizon=%.17g weights=%s tolerance=%.3g n=%zu method=%s "
                "lowest=%.17g precracks=",
                hash.c_str(), horizon, weights.c_str(), tolerance, n,
                state_based ? "angular+state-moments(distortion5,dilatation2)" : "angular+shapes+isotropic",
                lowest_shape);
  std::string key = text;
  for (const auto& crack : precracks) {
    std::snprintf(text, sizeof text, "[%.17g,%.17g;%.17g,%.17g]", crack.from.x, crack.from.y, crack.to.x,
                  crack.to.y);
    key += text;
  }
  return key;
}

// write_keyed_payload's layout; the payload: lambda (n doubles), then two
// sets of directional factors, the shapes and the dilatation factors, each
// as its rows (n uint32, or none when the set is empty: a uint64 0 first),
// the number of rows (uint64) and the coefficients (5 doubles each).
void write_shapes(BinaryWriter& w, const DirectionalShapes& s) {
  w.scalar<std::uint64_t>(s.row.size());
  w.values(s.row);
  w.scalar<std::uint64_t>(s.count());
  w.values(s.coefficients);
}
void write_cache_payload(BinaryWriter& w, const SurfaceCorrection& c) {
  w.values(c.lambda);
  write_shapes(w, c.shapes);
  write_shapes(w, c.dilatation);
}

// A set of directional factors as write_shapes wrote it; false if inconsistent.
bool read_shapes(BinaryReader& r, std::size_t n, DirectionalShapes& s) {
  const auto rows = r.scalar<std::uint64_t>("row count");
  if (rows != 0 && rows != n) return false;
  r.values(s.row, rows, "shape rows");
  const auto count = r.scalar<std::uint64_t>("shape count");
  if (count > n) return false;
  r.values(s.coefficients, count, "shapes");
  for (auto row : s.row)
    if (row != DirectionalShapes::none && row >= count) return false;
  return true;
}

// The cached factors, or false when the cache is absent, of another key,
// damaged or inconsistent: the factors are then computed again, so a bad
// cache costs time, never a wrong result.
bool read_cache(const std::string& path, const std::string& key, std::size_t n, SurfaceCorrection& c) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return false;
  const auto size = static_cast<std::uint64_t>(std::max<std::streamoff>(in.tellg(), 0));
  in.seekg(0);
  try {
    BinaryReader head(in, size, path);
    char magic[8];
    head.bytes(magic, 8, "magic");
    if (std::memcmp(magic, cache_magic, 8) != 0) return false;
    if (head.scalar<std::uint64_t>("key length") != key.size() || head.string(key.size(), "key") != key) return false;
    // What follows the key: the payload, then its 8-byte checksum.
    BinaryReader payload(in, head.remaining() - std::min<std::uint64_t>(head.remaining(), 8), path);
    std::vector<double> lambda;
    DirectionalShapes shapes, dilatation;
    payload.values(lambda, n, "lambda");
    if (!read_shapes(payload, n, shapes) || !read_shapes(payload, n, dilatation)) return false;
    if (payload.remaining() != 0) return false;
    if (BinaryReader(in, 8, path).scalar<std::uint64_t>("checksum") != payload.checksum()) return false;
    c.lambda.swap(lambda);
    c.shapes = std::move(shapes);
    c.dilatation = std::move(dilatation);
    return true;
  } catch (const Error&) {
    return false;  // truncated: computed again
  }
}

void write_cache(const std::string& path, const std::string& key, const SurfaceCorrection& c) {
  write_atomically(path, [&](std::ofstream& out) {
    write_keyed_payload(out, cache_magic, key, [&](BinaryWriter& w) { write_cache_payload(w, c); });
  });
}
}  // namespace

void DeferredCacheWrite::write() {
  if (path.empty()) return;
  write_cache(path, key, factors);
  *this = DeferredCacheWrite{};
}

SurfaceCorrectionResult surface_correction_for_run(const Scene& scene, const ParticleSet& p,
                                                   const Families& families, PerBond<double>& energy_weights,
                                                   const std::vector<std::uint8_t>& listed_intact, double horizon,
                                                   const std::string& particle_file_hash,
                                                   const std::string& cache_path, bool coupled_factors,
                                                   DeferredCacheWrite* deferred, const std::string& shared_cache,
                                                   const DeferredCacheWrite* shared_kept_back) {
  SurfaceCorrectionResult result;
  if (!scene.effects.surface_correction) {
    result.correction.lambda.assign(families.particle_count, 1.0);
    return result;
  }
  const Harmonics angular = angular_quadrature_factor(families, energy_weights, horizon);
  apply_angular_factor(p, families, angular, energy_weights);
  constexpr double tolerance = surface_correction_tolerance;
  const bool state_based = scene.model == ModelType::osb;
  if (!coupled_factors) {
    result = state_based
                 ? compute_state_surface_correction(p, families, energy_weights, listed_intact, horizon, tolerance, false)
                 : compute_surface_correction(p, families, energy_weights, listed_intact, horizon, tolerance, false);
    result.correction.angular = angular;
    return result;
  }
  const std::string key = cache_key(particle_file_hash, horizon, to_string(scene.bond_weights), scene.precracks,
                                    tolerance, families.particle_count, state_based);
  if (!cache_path.empty() && read_cache(cache_path, key, families.particle_count, result.correction)) {
    result.from_cache = true;
  } else if (!cache_path.empty() && !shared_cache.empty() &&
             (shared_kept_back && shared_kept_back->path == shared_cache && shared_kept_back->key == key
                  ? (result.correction = shared_kept_back->factors, true)
                  : read_cache(shared_cache, key, families.particle_count, result.correction))) {
    // Another folder's factors of the same set-up: this folder's copy waits
    // for the run's checks as computed factors do, so that a refused run
    // leaves nothing new here.
    result.from_cache = true;
    if (deferred) *deferred = DeferredCacheWrite{cache_path, key, result.correction};
    else write_cache(cache_path, key, result.correction);
  } else {
    result = state_based
                 ? compute_state_surface_correction(p, families, energy_weights, listed_intact, horizon, tolerance)
                 : compute_surface_correction(p, families, energy_weights, listed_intact, horizon, tolerance);
    if (!cache_path.empty() && deferred) *deferred = DeferredCacheWrite{cache_path, key, result.correction};
    else if (!cache_path.empty()) write_cache(cache_path, key, result.correction);
  }
  result.correction.angular = angular;
  return result;
}

}  // namespace pd::solver
