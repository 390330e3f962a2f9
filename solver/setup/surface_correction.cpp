#include "surface_correction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "atomic_file.hpp"
#include "binary_codec.hpp"
#include "error.hpp"

namespace pd::solver {

namespace {

constexpr std::size_t K = std::tuple_size<Harmonics>::value;

// int_disk |xi| dA: the zeroth moment of the continuum's full disk (the factor
// 1/4 c eps^2 common to W_i and W0 drops out); its other four moments vanish.
Harmonics full_disk_moments(double horizon) { return {2.0 * M_PI * horizon * horizon * horizon / 3.0, 0, 0, 0, 0}; }

bool intact(const BondRef& b, const std::vector<std::uint8_t>& listed_intact) {
  return b.on_stencil || listed_intact[b.index];
}

// A symmetric K x K matrix, row-major, and its sum of e h h^T.
using Matrix = std::array<double, K * K>;
void add_outer(Matrix& a, double e, const Harmonics& h) {
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t m = 0; m < K; ++m) a[k * K + m] += e * h[k] * h[m];
}

// Cholesky factor L (lower, in place) of a symmetric positive definite matrix.
// False when it is too close to singular for five moments to be set
// independently: some pivot squared falls below 1e-4 times its diagonal entry
// (that row's harmonic is almost a combination of the previous ones over the
// bond directions at hand).
bool cholesky(Matrix& a) {
  constexpr double floor = 1e-4;
  for (std::size_t k = 0; k < K; ++k) {
    double d = a[k * K + k];
    for (std::size_t m = 0; m < k; ++m) d -= a[k * K + m] * a[k * K + m];
    if (!(d > floor * a[k * K + k])) return false;
    a[k * K + k] = std::sqrt(d);
    for (std::size_t r = k + 1; r < K; ++r) {
      double s = a[r * K + k];
      for (std::size_t m = 0; m < k; ++m) s -= a[r * K + m] * a[k * K + m];
      a[r * K + k] = s / a[k * K + k];
    }
  }
  return true;
}

Harmonics cholesky_solve(const Matrix& l, Harmonics b) {
  for (std::size_t k = 0; k < K; ++k) {
    for (std::size_t m = 0; m < k; ++m) b[k] -= l[k * K + m] * b[m];
    b[k] /= l[k * K + k];
  }
  for (std::size_t k = K; k-- > 0;) {
    for (std::size_t m = k + 1; m < K; ++m) b[k] -= l[m * K + k] * b[m];
    b[k] /= l[k * K + k];
  }
  return b;
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

// ---- Part 3: the scalar factors by fixed-point iteration, on the shaped bonds.
int scalar_factors(const ParticleSet& p, const Families& families, const PerBond<double>& weight,
                   const std::vector<std::uint8_t>& listed_intact, const DirectionalShapes& shapes,
                   double horizon, double tolerance, std::vector<double>& lambda) {
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
    if (largest_change < tolerance) return iteration;
  }
  throw Error("surface correction did not converge to " + std::to_string(tolerance) + " in " +
              std::to_string(max_iterations) + " iterations");
}

}  // namespace

Harmonics angular_quadrature_factor(const Families& families, const PerBond<double>& weight, double horizon) {
  if (families.levels.empty() || families.levels[0].size() == 0 || families.stencil_particle_count(0) == 0)
    return {1, 0, 0, 0, 0};
  const StencilLevel& level = families.levels[0];
  Matrix gram{};
  for (std::size_t o = 0; o < level.size(); ++o)
    add_outer(gram, weight.stencil[0][o], bond_harmonics(static_cast<double>(level.di[o]), static_cast<double>(level.dj[o])));
  if (!cholesky(gram)) throw Error("surface correction: the interior stencil has too few bond directions");
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
                                                   double tolerance) {
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
  result.iterations =
      scalar_factors(p, families, weight, listed_intact, shapes, horizon, tolerance, result.correction.lambda);
  return result;
}

namespace {
constexpr char cache_magic[8] = {'P', 'D', 'S', 'C', 'F', '0', '0', '2'};

std::string cache_key(const std::string& hash, double horizon, const std::string& weights,
                      const std::vector<PrecrackSpec>& precracks, double tolerance, std::size_t n) {
  char text[512];
  std::snprintf(text, sizeof text,
                "particles=%s horizon=%.17g weights=%s tolerance=%.3g n=%zu method=angular+shapes+isotropic "
                "lowest=%.17g precracks=",
                hash.c_str(), horizon, weights.c_str(), tolerance, n, lowest_shape);
  std::string key = text;
  for (const auto& crack : precracks) {
    std::snprintf(text, sizeof text, "[%.17g,%.17g;%.17g,%.17g]", crack.from.x, crack.from.y, crack.to.x,
                  crack.to.y);
    key += text;
  }
  return key;
}

// write_keyed_payload's layout; the payload: lambda (n doubles), the shapes'
// rows (n uint32), the number of shaped particles (uint64) and their d_i (5
// doubles each).
void write_cache_payload(BinaryWriter& w, const SurfaceCorrection& c) {
  w.values(c.lambda);
  w.values(c.shapes.row);
  w.scalar<std::uint64_t>(c.shapes.count());
  w.values(c.shapes.coefficients);
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
    DirectionalShapes shapes;
    payload.values(lambda, n, "lambda");
    payload.values(shapes.row, n, "shape rows");
    const auto rows = payload.scalar<std::uint64_t>("shape count");
    if (rows > n) return false;
    payload.values(shapes.coefficients, rows, "shapes");
    if (payload.remaining() != 0) return false;
    if (BinaryReader(in, 8, path).scalar<std::uint64_t>("checksum") != payload.checksum()) return false;
    for (auto r : shapes.row)
      if (r != DirectionalShapes::none && r >= rows) return false;
    c.lambda.swap(lambda);
    c.shapes = std::move(shapes);
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

SurfaceCorrectionResult surface_correction_for_run(const Scene& scene, const ParticleSet& p,
                                                   const Families& families, PerBond<double>& energy_weights,
                                                   const std::vector<std::uint8_t>& listed_intact, double horizon,
                                                   const std::string& particle_file_hash,
                                                   const std::string& cache_path) {
  SurfaceCorrectionResult result;
  if (!scene.effects.surface_correction) {
    result.correction.lambda.assign(families.particle_count, 1.0);
    return result;
  }
  const Harmonics angular = angular_quadrature_factor(families, energy_weights, horizon);
  apply_angular_factor(p, families, angular, energy_weights);
  constexpr double tolerance = 1e-7;
  const std::string key = cache_key(particle_file_hash, horizon, to_string(scene.bond_weights), scene.precracks,
                                    tolerance, families.particle_count);
  if (!cache_path.empty() && read_cache(cache_path, key, families.particle_count, result.correction)) {
    result.from_cache = true;
  } else {
    result = compute_surface_correction(p, families, energy_weights, listed_intact, horizon, tolerance);
    if (!cache_path.empty()) write_cache(cache_path, key, result.correction);
  }
  result.correction.angular = angular;
  return result;
}

}  // namespace pd::solver
