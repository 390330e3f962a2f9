#include "mesh_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "loading_layer.hpp"
#include "units.hpp"

namespace pd {

double area_error(const ParticleSet& p, const PlateGeometry& g) {
  double sum = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!in_loading_layer(p, g, i)) sum += p.volume[i];
  const double exact = g.exact_area();
  return (sum - exact) / exact;
}

void print_mesh_summary(std::ostream& out, const MeshRun& run) {
  const auto& p = run.particles;
  const auto& g = run.geometry;
  const auto& r = run.grid;
  char line[1024];
  const double dx = p.spacing, dx2 = dx * dx;
  std::size_t by_region[3] = {0, 0, 0};
  for (auto region : p.region) ++by_region[region];
  const bool nbnug = p.grid == GridKind::nbnug;
  // A global free mesh has neither lattice squares nor boxes: its cells are counted by shape alone.
  if (p.grid == GridKind::free)
    std::snprintf(line, sizeof line, "grid %s, quadrature %s: %zu particles (the cells of one free mesh: %zu quads, %zu "
                  "triangles)\n", to_string(p.grid), to_string(p.quadrature), p.size(), r.free.quads, r.free.triangles);
  else
    std::snprintf(line, sizeof line, "grid %s, quadrature %s: %zu particles (%zu squares, %zu free quads, %zu free "
                  "triangles, %zu other)\n", to_string(p.grid), to_string(p.quadrature), p.size(), by_region[0],
                  r.free.quads * nbnug, r.free.triangles * nbnug, by_region[2]);
  out << line;
  if (nbnug) {
    std::snprintf(line, sizeof line, "free regions: %zu (boxes around holes, bands along the other boundaries off the "
                  "lattice lines)\n", r.free_regions);
    out << line;
  }
  if (r.free.quads + r.free.triangles > 0) {
    const double count = static_cast<double>(r.free.quads + r.free.triangles);
    std::snprintf(line, sizeof line,
                  "free cells: %zu quads, %zu triangles; area / dx^2 min %.3f mean %.3f max %.3f; worst angle "
                  "quality %.3f",
                  r.free.quads, r.free.triangles, r.free.min_area / dx2, r.free.sum_area / count / dx2,
                  r.free.max_area / dx2, r.free.worst_quality);
    out << line;
    if (r.free.curved_edges > 0) out << "; " << r.free.curved_edges << " edges on curved boundaries";
    out << "\n";
  }
  if (r.graded.enabled() && r.free.quads + r.free.triangles > 0) {
    std::snprintf(line, sizeof line,
                  "graded: target size %.4g mm at the curved boundaries to %.4g mm at %.4g mm from them; cell sizes "
                  "sqrt(area) %.4g to %.4g mm\n",
                  r.graded.fine * 1e3, r.graded.coarse * 1e3, r.graded.length * 1e3, std::sqrt(r.free.min_area) * 1e3,
                  std::sqrt(r.free.max_area) * 1e3);
    out << line;
  }
  if (r.min_distance_to_curved < 1e300) {
    std::snprintf(line, sizeof line, "smallest centroid distance to a curved boundary: %.4g mm (%.3f dx)\n",
                  r.min_distance_to_curved * 1e3, r.min_distance_to_curved / dx);
    out << line;
  }
  if (r.min_distance_to_straight_off_lattice < 1e300) {
    std::snprintf(line, sizeof line,
                  "smallest centroid distance to a straight boundary off the lattice lines: %.4g mm (%.3f dx)\n",
                  r.min_distance_to_straight_off_lattice * 1e3, r.min_distance_to_straight_off_lattice / dx);
    out << line;
  }
  double sum = 0, layer_area = 0;
  std::size_t layer_particles = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (in_loading_layer(p, g, i))
      layer_area += p.volume[i], ++layer_particles;
    else
      sum += p.volume[i];
  if (layer_particles > 0) {
    std::snprintf(line, sizeof line, "loading layers: %zu particles, %.12g mm^2 outside the plate (not in the area check)\n",
                  layer_particles, layer_area * 1e6);
    out << line;
  }
  std::snprintf(line, sizeof line, "area check: sum of volumes %.12g mm^2, plate %.12g mm^2, relative difference %.2e\n",
                sum * 1e6, g.exact_area() * 1e6, area_error(p, g));
  out << line;
  for (const auto& v : run.narrow_voids) {
    std::snprintf(line, sizeof line, "narrow void: %s, %.4g mm wide (%.3g dx); ", v.name.c_str(), v.width * 1e3,
                  v.width / dx);
    out << line;
    if (p.grid != GridKind::uniform) {
      out << "resolved exactly: the cells follow its boundary\n";
    } else if (v.resolved_width <= 0) {
      out << "the uniform grid removes no cell for it (no cell centre lies inside): only the bond rule sees it\n";
    } else {
      std::snprintf(line, sizeof line, "the uniform grid resolves it as %.4g mm (%.3g dx) of removed cells\n",
                    v.resolved_width * 1e3, v.resolved_width / dx);
      out << line;
    }
  }
  if (!p.family_offsets.empty()) {
    std::size_t lo = SIZE_MAX, hi = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::size_t n = p.family_offsets[i + 1] - p.family_offsets[i];
      lo = std::min(lo, n), hi = std::max(hi, n);
    }
    // With a refinement region the horizons range from the finest square's to
    // the nominal one; with --horizon-smoothing some squares have more than m x their side.
    const double smallest = *std::min_element(p.horizon.begin(), p.horizon.end());
    if (smallest < p.horizon_nominal * (1 - 1e-9)) {
      const double m = p.horizon_nominal / p.spacing;
      std::size_t smoothed = 0;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.region[i] == static_cast<std::uint8_t>(Region::uniform_square) &&
            p.horizon[i] > m * p.cell_size[i] * (1 + 1e-9))
          ++smoothed;
      // Box cells below the nominal horizon: a box meshed finer (--box-spacing).
      // Free cells of the global free grid below it: a graded mesh (--graded-spacing).
      std::size_t fine_box_cells = 0, fine_squares = 0, graded_cells = 0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.horizon[i] >= p.horizon_nominal * (1 - 1e-9)) continue;
        if (p.region[i] == static_cast<std::uint8_t>(Region::box_free_mesh)) ++fine_box_cells;
        if (p.region[i] == static_cast<std::uint8_t>(Region::uniform_square)) ++fine_squares;
        if (p.region[i] == static_cast<std::uint8_t>(Region::other)) ++graded_cells;
      }
      std::snprintf(line, sizeof line, "horizons: %.4g to %.4g mm (m x own size:", smallest * 1e3,
                    p.horizon_nominal * 1e3);
      out << line;
      if (fine_squares > 0) out << " " << fine_squares << " squares of the refinement region";
      if (fine_squares > 0 && fine_box_cells > 0) out << ",";
      if (fine_box_cells > 0) out << " " << fine_box_cells << " box cells of the box spacing";
      if (graded_cells > 0) out << " " << graded_cells << " graded free cells (at their centroid's target size)";
      if (smoothed > 0) out << "; " << smoothed << " squares with a smoothed horizon, larger";
      if (run.smoothed_box_cells > 0)
        out << "; " << run.smoothed_box_cells << " box cells with a smoothed horizon, larger";
      out << ")\n";
    }
    std::snprintf(line, sizeof line,
                  "families: horizon %.4g mm, %zu bonds, per particle min %zu mean %.1f max %zu; %llu bonds through "
                  "voids left out\n",
                  p.horizon_nominal * 1e3, p.bond_count(), lo,
                  static_cast<double>(p.bond_count()) / std::max<std::size_t>(1, p.size()), hi,
                  static_cast<unsigned long long>(run.families.bonds_through_voids));
    out << line;
  }
  std::snprintf(line, sizeof line, "estimate before meshing: %.3g particles, %.3g bonds, %s of memory, %s file\n",
                run.estimate.particles, run.estimate.bonds, format_bytes(run.estimate.memory_bytes).c_str(),
                format_bytes(run.estimate.file_bytes).c_str());
  out << line;
  std::snprintf(line, sizeof line, "estimate once meshed: %.3g particles, %.3g bonds, %s of memory, %s file\n",
                run.meshed_estimate.particles, run.meshed_estimate.bonds,
                format_bytes(run.meshed_estimate.memory_bytes).c_str(),
                format_bytes(run.meshed_estimate.file_bytes).c_str());
  out << line;
  std::string stages = "time:";
  double total = 0;
  for (const auto& [name, seconds] : run.times.seconds) {
    std::snprintf(line, sizeof line, " %s %.2f s,", name.c_str(), seconds);
    stages += line;
    total += seconds;
  }
  std::snprintf(line, sizeof line, " total %.2f s\n", total);
  out << stages << line;
}

}  // namespace pd
