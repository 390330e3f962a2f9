#include "surface_correction.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "atomic_file.hpp"
#include "checksum.hpp"
#include "error.hpp"

namespace pd::solver {

SurfaceCorrectionResult compute_surface_correction(const Families& families, const PerBond<double>& weight,
                                                   double horizon, double tolerance) {
  const std::int64_t n = static_cast<std::int64_t>(families.particle_count);
  // The factor 1/4 c eps^2 is common to W_i and W0 and drops out.
  const double target = 2.0 * M_PI * horizon * horizon * horizon / 3.0;  // int_disk |xi| dA

  SurfaceCorrectionResult result;
  result.lambda.assign(families.particle_count, 1.0);
  std::vector<double> next(families.particle_count);
  for (int iteration = 1; iteration <= 10000; ++iteration) {
    double largest_change = 0;
#pragma omp parallel for schedule(static) reduction(max : largest_change)
    for (std::int64_t i = 0; i < n; ++i) {
      double w = 0;
      families.for_each_bond(static_cast<std::uint32_t>(i), [&](const BondRef& b) {
        w += 0.5 * (result.lambda[i] + result.lambda[b.neighbor]) * weight(b);
      });
      if (!(w > 0)) {
        next[i] = result.lambda[i];  // an isolated particle has no bonds to correct
        continue;
      }
      next[i] = result.lambda[i] * target / w;
      largest_change = std::max(largest_change, std::fabs(next[i] - result.lambda[i]) / result.lambda[i]);
    }
    result.lambda.swap(next);
    result.iterations = iteration;
    if (largest_change < tolerance) return result;
  }
  throw Error("surface correction did not converge to " + std::to_string(tolerance) + " in 10000 iterations");
}

namespace {
constexpr char cache_magic[8] = {'P', 'D', 'S', 'C', 'F', '0', '0', '1'};

std::string cache_key(const std::string& hash, double horizon, const std::string& weights, double tolerance,
                      std::size_t n) {
  char text[512];
  std::snprintf(text, sizeof text, "particles=%s horizon=%.17g weights=%s tolerance=%.3g n=%zu loading=isotropic",
                hash.c_str(), horizon, weights.c_str(), tolerance, n);
  return text;
}

bool read_cache(const std::string& path, const std::string& key, std::vector<double>& lambda) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  char magic[8];
  std::uint64_t key_size = 0;
  if (!in.read(magic, 8) || std::memcmp(magic, cache_magic, 8) != 0) return false;
  if (!in.read(reinterpret_cast<char*>(&key_size), 8) || key_size != key.size()) return false;
  std::string stored(key_size, '\0');
  if (!in.read(stored.data(), static_cast<std::streamsize>(key_size)) || stored != key) return false;
  std::vector<double> values(lambda.size());
  std::uint64_t checksum = 0;
  if (!in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(values.size() * 8))) return false;
  if (!in.read(reinterpret_cast<char*>(&checksum), 8)) return false;
  if (checksum != checksum_of(values.data(), values.size() * 8)) return false;
  lambda.swap(values);
  return true;
}
}  // namespace

SurfaceCorrectionResult cached_surface_correction(const Families& families, const PerBond<double>& weights,
                                                  double horizon, const std::string& weights_name,
                                                  const std::string& hash, const std::string& cache_path,
                                                  double tolerance) {
  const std::string key = cache_key(hash, horizon, weights_name, tolerance, families.particle_count);
  SurfaceCorrectionResult result;
  result.lambda.resize(families.particle_count);
  if (read_cache(cache_path, key, result.lambda)) {
    result.from_cache = true;
    return result;
  }
  result = compute_surface_correction(families, weights, horizon, tolerance);
  write_atomically(cache_path, [&](std::ofstream& out) {
    const std::uint64_t key_size = key.size();
    const std::uint64_t checksum = checksum_of(result.lambda.data(), result.lambda.size() * 8);
    out.write(cache_magic, 8);
    out.write(reinterpret_cast<const char*>(&key_size), 8);
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    out.write(reinterpret_cast<const char*>(result.lambda.data()), static_cast<std::streamsize>(result.lambda.size() * 8));
    out.write(reinterpret_cast<const char*>(&checksum), 8);
  });
  return result;
}

SurfaceCorrectionResult surface_correction_for_run(bool enabled, BondWeights weights, const Families& families,
                                                   const PerBond<double>& energy_weights, double horizon,
                                                   const std::string& particle_file_hash,
                                                   const std::string& cache_path) {
  if (!enabled) return {std::vector<double>(families.particle_count, 1.0), 0, false};
  if (cache_path.empty()) return compute_surface_correction(families, energy_weights, horizon);
  return cached_surface_correction(families, energy_weights, horizon,
                                   to_string(weights), particle_file_hash,
                                   cache_path);
}

}  // namespace pd::solver
