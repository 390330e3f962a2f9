#pragma once
// Families (neighbour lists) and partial-volume factors, docs/theory.md Sec. 2.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <memory>

#include "cell_disk_memo.hpp"
#include "geometry.hpp"
#include "particle_file.hpp"

namespace pd {

class MaterialBoundary;
class NeighborSearch;

// The family of any point with its own horizon, against the cells of a
// particle set: the mesher builds every particle's family with it, and the
// solver can build the family of a particle it adds (refinement). Factors as
// in build_families below. Keeps references to `particles` (positions,
// horizons, cell sizes, cells) and `boundary`: they must outlive the builder.
class FamilyBuilder {
public:
  static constexpr std::uint32_t none = 0xffffffffu;  // `self` of a point that is not a particle of the set

  // `with_search`: builds the spatial search that `family` needs; a builder
  // that only takes its candidates given (`family_among`) does without it.
  FamilyBuilder(const ParticleSet& particles, Quadrature quadrature, const MaterialBoundary* boundary = nullptr,
                bool with_search = true);
  // A builder for `family_among` only (no boundary, no search) whose
  // candidates are among the particles marked 1 in `cells`: it measures
  // their cells only, not every cell of the set (a refinement split asks
  // about a few cells of a large set).
  FamilyBuilder(const ParticleSet& particles, Quadrature quadrature, const std::vector<std::uint8_t>& cells);
  ~FamilyBuilder();

  // Neighbours (sorted by index) and their partial-volume factors of a
  // particle at `x` with horizon `horizon` [m]; `self`, if it is an index of
  // the set, is left out. `candidates` is scratch space (one per thread).
  // Returns the number of bonds left out because they leave the material.
  std::uint64_t family(Vec2 x, double horizon, std::uint32_t self, std::vector<std::uint32_t>& neighbors,
                       std::vector<double>& factors, std::vector<std::uint32_t>& candidates) const;

  // The same, with the candidates given (sorted by index) instead of
  // searched: the family among them. Equal to `family` less the particles
  // not in `candidates` when these hold every particle whose cell can meet
  // the disk, for the analytic and full quadratures (a cell outside the
  // search radius at most touches the disk: factor 0). Not for hhb, whose
  // factor at the search radius is decided by the search's own round-off.
  // `areas` (optional): partial areas of four-vertex cells to look up; those
  // it lacks are computed and appended to `found_areas` (analytic quadrature).
  std::uint64_t family_among(Vec2 x, double horizon, std::uint32_t self, const std::vector<std::uint32_t>& candidates,
                             std::vector<std::uint32_t>& neighbors, std::vector<double>& factors,
                             const CellDiskMemo* areas = nullptr, CellDiskMemo::Found* found_areas = nullptr) const;

  // The candidates (in their order) whose cells can meet the disk of
  // radius `horizon` [m] about some point within `spread` [m] of `x`: a
  // superset of what family_among keeps for each such point (its first
  // test, for all of them at once: a parent's children share their candidates).
  void candidates_near(Vec2 x, double horizon, double spread, const std::vector<std::uint32_t>& candidates,
                       std::vector<std::uint32_t>& near) const;

private:
  // Reach and area of the cells marked in `cells` (null: every cell).
  void measure_cells(const std::vector<std::uint8_t>* cells);
  double search_radius(double horizon) const;
  const ParticleSet& p_;
  Quadrature quadrature_;
  const MaterialBoundary* boundary_;
  std::vector<double> reach_, polygon_area_;  // per cell: largest centroid-to-vertex distance, area
  double max_reach_ = 0;
  std::unique_ptr<NeighborSearch> search_;
};

struct FamilyReport {
  // Directed bonds left out because their segment leaves the material.
  std::uint64_t bonds_through_voids = 0;
};

// Fills family_offsets, neighbors and partial_volume from the cells and the
// per-particle horizons. Family of i: every j != i whose cell can meet the
// disk(x_i, horizon_i), kept if its factor is positive:
//   analytic: area(cell_j ∩ disk) / area(cell_j)  (exact polygon-disk area)
//   hhb:      [004:(12)] with cell_size_j (dx for squares, sqrt(V_j) otherwise, [004:(13),(14)])
//   full:     1 if |x_j - x_i| <= horizon_i
// With a `boundary`, j is also left out when the segment x_i -> x_j leaves
// the material (MaterialBoundary::segment_leaves_material, symmetric in i
// and j): no bond crosses a hole, a notch or a re-entrant outer boundary.
// Deterministic: families sorted by index whatever the thread count.
// `progress`, if given, is called now and then from one thread with the
// particles whose families are done and the particle count (for a progress
// line on long runs); it decides itself whether to print.
using FamilyProgress = std::function<void(std::size_t done, std::size_t total)>;
FamilyReport build_families(ParticleSet& particles, Quadrature quadrature, const MaterialBoundary* boundary = nullptr,
                            const FamilyProgress& progress = nullptr);

// An upper bound of every bond's length that build_families can give a
// particle set [m]: its largest horizon plus its largest distance from a
// cell's centroid to one of its vertices (a cell meets a particle's horizon
// disk only if its centroid is that near). Needs the cells only, which the
// particle file holds before its families.
double longest_possible_bond(const ParticleSet& particles);
// The same from each particle's cell reach (cell_reaches): a refinement event
// keeps the reaches of the particles that did not split (the same cell about
// the same centre) and measures the children's only.
double longest_possible_bond(const ParticleSet& particles, const std::vector<double>& reaches);
// Per particle: the largest distance from its centre to a vertex of its cell [m].
double cell_reach(const ParticleSet& particles, std::size_t j);
std::vector<double> cell_reaches(const ParticleSet& particles);

// Family size of a square far from every boundary on a lattice of spacing
// dx with horizon m dx, counted cell by cell (an upper bound per particle for
// any grid of about dx cells; used to estimate a grid's size before meshing).
std::size_t interior_family_size(double horizon_factor, Quadrature quadrature);

}  // namespace pd
