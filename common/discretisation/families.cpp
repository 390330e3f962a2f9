#include "families.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "error.hpp"
#include "geometry.hpp"
#include "material_boundary.hpp"
#include "neighbor_search.hpp"

namespace pd {

FamilyBuilder::FamilyBuilder(const ParticleSet& p, Quadrature quadrature, const MaterialBoundary* boundary,
                             bool with_search)
    : p_(p), quadrature_(quadrature), boundary_(boundary) {
  measure_cells(nullptr);
  if (with_search) search_ = std::make_unique<NeighborSearch>(p.x, p.y);
}

FamilyBuilder::FamilyBuilder(const ParticleSet& p, Quadrature quadrature, const std::vector<std::uint8_t>& cells)
    : p_(p), quadrature_(quadrature), boundary_(nullptr) {
  if (cells.size() != p.size()) throw Error("FamilyBuilder: one mark per particle expected");
  measure_cells(&cells);
}

void FamilyBuilder::measure_cells(const std::vector<std::uint8_t>* cells) {
  const ParticleSet& p = p_;
  const std::size_t n = p.size();
  if (p.cell_offsets.size() != n + 1) throw Error("build_families: cells missing");
  // Largest centroid-to-vertex distance: a cell can meet disk(x_i, delta)
  // only if its centroid is within delta + that distance.
  reach_.resize(n);
  polygon_area_.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    if (cells && !(*cells)[j]) continue;
    const auto b = p.cell_offsets[j], e = p.cell_offsets[j + 1];
    reach_[j] = polygon_max_vertex_distance(&p.cell_vx[b], &p.cell_vy[b], e - b, {p.x[j], p.y[j]});
    polygon_area_[j] = std::fabs(polygon_signed_area(&p.cell_vx[b], &p.cell_vy[b], e - b));
    max_reach_ = std::max(max_reach_, reach_[j]);
  }
}

FamilyBuilder::~FamilyBuilder() = default;

double cell_reach(const ParticleSet& p, std::size_t j) {
  const auto b = p.cell_offsets[j], e = p.cell_offsets[j + 1];
  return polygon_max_vertex_distance(&p.cell_vx[b], &p.cell_vy[b], e - b, {p.x[j], p.y[j]});
}

std::vector<double> cell_reaches(const ParticleSet& p) {
  std::vector<double> reaches(p.size());
  for (std::size_t j = 0; j < p.size(); ++j) reaches[j] = cell_reach(p, j);
  return reaches;
}

double longest_possible_bond(const ParticleSet& p) {
  double horizon = 0, reach = 0;
  for (std::size_t j = 0; j < p.size(); ++j) {
    horizon = std::max(horizon, p.horizon[j]);
    reach = std::max(reach, cell_reach(p, j));
  }
  return horizon + reach;
}

double longest_possible_bond(const ParticleSet& p, const std::vector<double>& reaches) {
  if (reaches.size() != p.size()) throw Error("longest_possible_bond: the cell reaches are given for another particle count");
  double horizon = 0, reach = 0;
  for (std::size_t j = 0; j < p.size(); ++j) {
    horizon = std::max(horizon, p.horizon[j]);
    reach = std::max(reach, reaches[j]);
  }
  return horizon + reach;
}

double FamilyBuilder::search_radius(double delta) const {
  return quadrature_ == Quadrature::hhb ? delta + 0.5 * max_reach_ * std::sqrt(2.0) : delta + max_reach_;
}

std::uint64_t FamilyBuilder::family(Vec2 xi, double delta, std::uint32_t self, std::vector<std::uint32_t>& neighbors,
                                    std::vector<double>& factors, std::vector<std::uint32_t>& candidates) const {
  if (!search_) throw Error("FamilyBuilder::family: built without its search");
  search_->within(xi.x, xi.y, search_radius(delta), candidates);
  return family_among(xi, delta, self, candidates, neighbors, factors);
}

std::uint64_t FamilyBuilder::family_among(Vec2 xi, double delta, std::uint32_t self,
                                          const std::vector<std::uint32_t>& candidates,
                                          std::vector<std::uint32_t>& neighbors, std::vector<double>& factors,
                                          const CellDiskMemo* areas, CellDiskMemo::Found* found_areas) const {
  const ParticleSet& p = p_;
  neighbors.clear();
  factors.clear();
  std::uint64_t through_voids = 0;
  // Only particles near the boundary can have a bond that leaves the material.
  const bool near_boundary = boundary_ != nullptr && boundary_->near(xi, search_radius(delta));
  for (const auto j : candidates) {
    if (j == self) continue;
    const double dx = p.x[j] - xi.x, dy = p.y[j] - xi.y;
    double factor = 0;
    switch (quadrature_) {
      case Quadrature::analytic: {
        if (!hypot_at_most(dx, dy, delta + reach_[j])) break;
        const auto cb = p.cell_offsets[j], ce = p.cell_offsets[j + 1];
        // A cell entirely inside the disk is exactly 1 (no round-off from the
        // sector sums); so is one whose reach round its centroid is, by a
        // margin far above round-off (no vertex need be measured).
        const double inner = delta - reach_[j];
        if ((reach_[j] < 0.5 * delta && dx * dx + dy * dy < inner * inner * (1 - 1e-6)) ||
            polygon_within_distance(&p.cell_vx[cb], &p.cell_vy[cb], ce - cb, xi, delta)) {
          factor = 1.0;
          break;
        }
        // The memo's key is the area computation's own inputs; one call site either way.
        const bool memoised = areas && ce - cb == 4;
        CellDiskMemo::Key key;
        const double* known = nullptr;
        if (memoised) {
          key = CellDiskMemo::key(&p.cell_vx[cb], &p.cell_vy[cb], xi, delta);
          known = areas->find(key);
        }
        const double area =
            known ? *known : polygon_disk_intersection_area(&p.cell_vx[cb], &p.cell_vy[cb], ce - cb, xi, delta);
        if (memoised && !known) found_areas->emplace_back(key, area);
        factor = area / polygon_area_[j];
        factor = std::min(factor, 1.0);
        if (factor < 1e-12) factor = 0;  // tangent contacts: no measurable area
        break;
      }
      case Quadrature::hhb:
        factor = hhb_factor(std::hypot(dx, dy), delta, p.cell_size[j]);
        break;
      case Quadrature::full:
        factor = hypot_at_most(dx, dy, delta) ? 1.0 : 0.0;
        break;
    }
    if (factor <= 0) continue;
    if (near_boundary && boundary_->segment_leaves_material(xi, {p.x[j], p.y[j]})) {
      ++through_voids;
      continue;
    }
    neighbors.push_back(j);
    factors.push_back(factor);
  }
  return through_voids;
}

void FamilyBuilder::candidates_near(Vec2 x, double horizon, double spread,
                                    const std::vector<std::uint32_t>& candidates,
                                    std::vector<std::uint32_t>& near) const {
  near.clear();
  for (const auto j : candidates) {
    // A cell that meets disk(y, horizon) with |y - x| <= spread has its
    // centroid within horizon + reach + spread of x (family_among's first
    // test and the triangle inequality); the margin is far above round-off.
    const double limit = (horizon + reach_[j] + spread) * (1 + 1e-9);
    if (hypot_at_most(p_.x[j] - x.x, p_.y[j] - x.y, limit)) near.push_back(j);
  }
}

FamilyReport build_families(ParticleSet& p, Quadrature quadrature, const MaterialBoundary* boundary,
                            const FamilyProgress& progress) {
  const std::size_t n = p.size();
  const FamilyBuilder builder(p, quadrature, boundary);

  // Rows are processed in blocks; each block's bonds are kept in order and
  // the blocks concatenated, so the result does not depend on scheduling.
  constexpr std::size_t block = 2048;
  const std::size_t blocks = (n + block - 1) / block;
  std::vector<std::vector<std::uint32_t>> block_neighbors(blocks);
  std::vector<std::vector<double>> block_factors(blocks);
  std::vector<std::uint64_t> family_size(n, 0);
  std::vector<std::uint64_t> block_through_voids(blocks, 0);
  std::atomic<std::size_t> done{0};

#pragma omp parallel
  {
    std::vector<std::uint32_t> candidates, neighbors;
    std::vector<double> factors;
    const bool reports = progress && omp_get_thread_num() == 0;
#pragma omp for schedule(dynamic, 1)
    for (std::size_t b = 0; b < blocks; ++b) {
      auto& out_n = block_neighbors[b];
      auto& out_f = block_factors[b];
      const std::size_t end = std::min(n, (b + 1) * block);
      for (std::size_t i = b * block; i < end; ++i) {
        block_through_voids[b] += builder.family({p.x[i], p.y[i]}, p.horizon[i], static_cast<std::uint32_t>(i),
                                                 neighbors, factors, candidates);
        out_n.insert(out_n.end(), neighbors.begin(), neighbors.end());
        out_f.insert(out_f.end(), factors.begin(), factors.end());
        family_size[i] = neighbors.size();
      }
      const std::size_t now_done = done += end - b * block;
      if (reports) progress(now_done, n);
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
