#include "mesh_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

namespace pd {

double area_error(const ParticleSet& p, const PlateGeometry& g) {
  double sum = 0;
  for (double v : p.volume) sum += v;
  const double exact = g.exact_area();
  return (sum - exact) / exact;
}

void print_mesh_summary(std::ostream& out, const ParticleSet& p, const PlateGeometry& g, const GridReport& r,
                        const StageTimes& times) {
  char line[512];
  const double dx2 = p.spacing * p.spacing;
  std::size_t by_region[3] = {0, 0, 0};
  for (auto region : p.region) ++by_region[region];
  std::snprintf(line, sizeof line, "grid %s, quadrature %s: %zu particles (%zu squares, %zu box quads, %zu box "
                "triangles, %zu other)\n", to_string(p.grid), to_string(p.quadrature), p.size(), by_region[0],
                r.free.quads * (p.grid == GridKind::nbnug), r.free.triangles * (p.grid == GridKind::nbnug),
                by_region[2]);
  out << line;
  if (p.grid == GridKind::nbnug) {
    std::snprintf(line, sizeof line, "boxes: %zu around %zu holes\n", r.boxes.size(), g.holes.size());
    out << line;
  }
  if (r.free.quads + r.free.triangles > 0) {
    const double count = static_cast<double>(r.free.quads + r.free.triangles);
    std::snprintf(line, sizeof line,
                  "free cells: %zu quads, %zu triangles; area / dx^2 min %.3f mean %.3f max %.3f; worst angle "
                  "quality %.3f; %zu curved edges\n",
                  r.free.quads, r.free.triangles, r.free.min_area / dx2, r.free.sum_area / count / dx2,
                  r.free.max_area / dx2, r.free.worst_quality, r.free.curved_edges);
    out << line;
  }
  if (!g.holes.empty()) {
    std::snprintf(line, sizeof line, "smallest centroid distance to a curved boundary: %.4g mm (%.3f dx)\n",
                  r.min_centroid_distance_to_curve * 1e3, r.min_centroid_distance_to_curve / p.spacing);
    out << line;
  }
  double sum = 0;
  for (double v : p.volume) sum += v;
  std::snprintf(line, sizeof line, "area check: sum of volumes %.12g mm^2, plate minus holes %.12g mm^2, "
                "relative difference %.2e\n", sum * 1e6, g.exact_area() * 1e6, area_error(p, g));
  out << line;
  if (!p.family_offsets.empty()) {
    std::size_t lo = SIZE_MAX, hi = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::size_t n = p.family_offsets[i + 1] - p.family_offsets[i];
      lo = std::min(lo, n), hi = std::max(hi, n);
    }
    std::snprintf(line, sizeof line, "families: horizon %.4g mm, %zu bonds, per particle min %zu mean %.1f max %zu\n",
                  p.horizon_nominal * 1e3, p.bond_count(), lo,
                  static_cast<double>(p.bond_count()) / std::max<std::size_t>(1, p.size()), hi);
    out << line;
  }
  std::string stages = "time:";
  double total = 0;
  for (const auto& [name, seconds] : times.seconds) {
    std::snprintf(line, sizeof line, " %s %.2f s,", name.c_str(), seconds);
    stages += line;
    total += seconds;
  }
  std::snprintf(line, sizeof line, " total %.2f s\n", total);
  out << stages << line;
}

}  // namespace pd
