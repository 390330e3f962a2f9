#include "crack_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "error.hpp"
#include "units.hpp"

namespace pd::post {

DamageComparison compare_damage(const ArrivalData& run, const ArrivalData& reference, double band,
                                double damage_level) {
  if (!(band > 0) || !std::isfinite(band)) throw Error("--band must be a positive length");
  if (!(damage_level > 0 && damage_level <= 1))
    throw Error("--damage-level must be in (0, 1], not " + shortest_text(damage_level));
  // A band far below the spacing (1e-300 m) or far beyond the plate: before
  // 7 December 2026 the first put coordinate / band, far beyond any integer,
  // through the buckets' integer cast, the second found nothing outside.
  const auto [x_min, x_max] = std::minmax_element(run.x.begin(), run.x.end());
  const auto [y_min, y_max] = std::minmax_element(run.y.begin(), run.y.end());
  const double plate_size = run.x.empty() ? 0.0 : std::max(*x_max - *x_min, *y_max - *y_min);
  const double spacing = std::min(run.spacing, reference.spacing);
  char text[400] = "";
  if (band < 1e-3 * spacing)
    std::snprintf(text, sizeof text,
                  "--band %g mm is less than a thousandth of the spacing (%g mm): only damage at the very same "
                  "place lies within it; give the band with its unit (e.g. --band 1mm)",
                  band * 1e3, spacing * 1e3);
  else if (band > max_plate_sizes_away * std::max(plate_size, spacing))
    std::snprintf(text, sizeof text,
                  "--band %g mm is more than %g times the plate's size (%g mm): the whole plate lies within it, and "
                  "no damage outside; give the band with its unit (e.g. --band 1mm)",
                  band * 1e3, max_plate_sizes_away, plate_size * 1e3);
  if (text[0] != '\0') throw Error(text);
  // The buckets' keys are x / band as integers. Beyond 2^52 bands from the
  // origin a position's round-off is more than the band, so no distance
  // within it can be told, and past 2^63 the key's cast is undefined (before
  // 7 December 2026 positions of 1e16 m were put through it).
  constexpr double most_bands = 0x1p52;
  for (const ArrivalData* a : {&reference, &run})
    for (std::size_t p = 0; p < a->size(); ++p)
      if (std::max(std::abs(a->x[p]), std::abs(a->y[p])) / band >= most_bands) {
        std::snprintf(text, sizeof text,
                      "particle %zu is at (%g, %g) m, %.3g bands of %g mm from the origin: beyond 2^52 bands its "
                      "position's round-off exceeds the band, and no damage can be placed within it (an edited or "
                      "damaged file); give a run whose plate lies near the origin, as pd-mesh writes it",
                      p, a->x[p], a->y[p], std::max(std::abs(a->x[p]), std::abs(a->y[p])) / band, band * 1e3);
        throw file_error(a->path, text);
      }
  DamageComparison c;
  c.reference = reference.path;
  c.band = band;
  c.damage_level = damage_level;

  const auto bucket_key = [band](double x, double y) {
    const auto ix = static_cast<std::int64_t>(std::floor(x / band));
    const auto iy = static_cast<std::int64_t>(std::floor(y / band));
    return (static_cast<std::uint64_t>(ix) << 32) ^ static_cast<std::uint32_t>(iy);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> buckets;
  for (std::size_t p = 0; p < reference.size(); ++p)
    if (reference.damage[p] >= damage_level) {
      buckets[bucket_key(reference.x[p], reference.y[p])].push_back(static_cast<std::uint32_t>(p));
      ++c.reference_damaged;
    }

  const double band2 = band * band;
  for (std::size_t p = 0; p < run.size(); ++p) {
    if (run.damage[p] < damage_level) continue;
    ++c.damaged;
    bool near = false;
    for (int dy = -1; dy <= 1 && !near; ++dy)
      for (int dx = -1; dx <= 1 && !near; ++dx) {
        const auto it = buckets.find(bucket_key(run.x[p] + dx * band, run.y[p] + dy * band));
        if (it == buckets.end()) continue;
        for (auto q : it->second) {
          const double ex = run.x[p] - reference.x[q], ey = run.y[p] - reference.y[q];
          if (ex * ex + ey * ey <= band2) {
            near = true;
            break;
          }
        }
      }
    if (!near) {
      ++c.outside;
      c.area_outside += run.cell_size[p] * run.cell_size[p];
    }
  }
  return c;
}

}  // namespace pd::post
