#include "families.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"
#include "geometry.hpp"
#include "material_boundary.hpp"
#include "neighbor_search.hpp"

namespace pd {

FamilyReport build_families(ParticleSet& p, Quadrature quadrature, const MaterialBoundary* boundary) {
  const std::size_t n = p.size();
  if (p.cell_offsets.size() != n + 1) throw Error("build_families: cells missing");
  // Largest centroid-to-vertex distance: a cell can meet disk(x_i, delta)
  // only if its centroid is within delta + that distance.
  std::vector<double> reach(n), polygon_area(n);
  double max_reach = 0, max_horizon = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const auto b = p.cell_offsets[j], e = p.cell_offsets[j + 1];
    reach[j] = polygon_max_vertex_distance(&p.cell_vx[b], &p.cell_vy[b], e - b, {p.x[j], p.y[j]});
    polygon_area[j] = std::fabs(polygon_signed_area(&p.cell_vx[b], &p.cell_vy[b], e - b));
    max_reach = std::max(max_reach, reach[j]);
    max_horizon = std::max(max_horizon, p.horizon[j]);
  }
  const NeighborSearch search(p.x, p.y);

  // Rows are processed in blocks; each block's bonds are kept in order and
  // the blocks concatenated, so the result does not depend on scheduling.
  constexpr std::size_t block = 2048;
  const std::size_t blocks = (n + block - 1) / block;
  std::vector<std::vector<std::uint32_t>> block_neighbors(blocks);
  std::vector<std::vector<double>> block_factors(blocks);
  std::vector<std::uint64_t> family_size(n, 0);
  std::vector<std::uint64_t> block_through_voids(blocks, 0);

#pragma omp parallel
  {
    std::vector<std::uint32_t> candidates;
#pragma omp for schedule(dynamic, 1)
    for (std::size_t b = 0; b < blocks; ++b) {
      auto& out_n = block_neighbors[b];
      auto& out_f = block_factors[b];
      for (std::size_t i = b * block; i < std::min(n, (b + 1) * block); ++i) {
        const double delta = p.horizon[i];
        const Vec2 xi{p.x[i], p.y[i]};
        const double search_radius =
            quadrature == Quadrature::hhb ? delta + 0.5 * max_reach * std::sqrt(2.0) : delta + max_reach;
        search.within(xi.x, xi.y, search_radius, candidates);
        // Only particles near the boundary can have a bond that leaves the material.
        const bool near_boundary = boundary != nullptr && boundary->near(xi, search_radius);
        for (const auto j : candidates) {
          if (j == i) continue;
          const double distance = std::hypot(p.x[j] - xi.x, p.y[j] - xi.y);
          double factor = 0;
          switch (quadrature) {
            case Quadrature::analytic: {
              if (distance > delta + reach[j]) break;
              const auto cb = p.cell_offsets[j], ce = p.cell_offsets[j + 1];
              // A cell entirely inside the disk is exactly 1 (no round-off from the sector sums).
              if (polygon_max_vertex_distance(&p.cell_vx[cb], &p.cell_vy[cb], ce - cb, xi) <= delta) {
                factor = 1.0;
                break;
              }
              factor = polygon_disk_intersection_area(&p.cell_vx[cb], &p.cell_vy[cb], ce - cb, xi, delta) /
                       polygon_area[j];
              factor = std::min(factor, 1.0);
              if (factor < 1e-12) factor = 0;  // tangent contacts: no measurable area
              break;
            }
            case Quadrature::hhb:
              factor = hhb_factor(distance, delta, p.cell_size[j]);
              break;
            case Quadrature::full:
              factor = distance <= delta ? 1.0 : 0.0;
              break;
          }
          if (factor <= 0) continue;
          if (near_boundary && boundary->segment_leaves_material(xi, {p.x[j], p.y[j]})) {
            ++block_through_voids[b];
            continue;
          }
          out_n.push_back(j);
          out_f.push_back(factor);
          ++family_size[i];
        }
      }
    }
  }
  p.family_offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) p.family_offsets[i + 1] = p.family_offsets[i] + family_size[i];
  p.neighbors.clear();
  p.partial_volume.clear();
  p.neighbors.reserve(p.family_offsets[n]);
  p.partial_volume.reserve(p.family_offsets[n]);
  for (std::size_t b = 0; b < blocks; ++b) {
    p.neighbors.insert(p.neighbors.end(), block_neighbors[b].begin(), block_neighbors[b].end());
    p.partial_volume.insert(p.partial_volume.end(), block_factors[b].begin(), block_factors[b].end());
    std::vector<std::uint32_t>().swap(block_neighbors[b]);
    std::vector<double>().swap(block_factors[b]);
  }
  p.quadrature = quadrature;
  FamilyReport report;
  for (auto count : block_through_voids) report.bonds_through_voids += count;
  return report;
}

std::size_t interior_family_size(double m, Quadrature quadrature) {
  // Cells are unit squares centred on integer points, the particle at the origin.
  const long reach = static_cast<long>(std::ceil(m)) + 1;
  std::size_t count = 0;
  for (long j = -reach; j <= reach; ++j)
    for (long i = -reach; i <= reach; ++i) {
      if (i == 0 && j == 0) continue;
      const double centre = std::hypot(static_cast<double>(i), static_cast<double>(j));
      // Distance from the origin to the nearest point of the cell.
      const double nearest = std::hypot(std::max(0.0, std::fabs(static_cast<double>(i)) - 0.5),
                                        std::max(0.0, std::fabs(static_cast<double>(j)) - 0.5));
      const bool member = quadrature == Quadrature::analytic ? nearest < m
                          : quadrature == Quadrature::hhb    ? centre < m + 0.5
                                                             : centre <= m;
      count += member;
    }
  return count;
}

}  // namespace pd
