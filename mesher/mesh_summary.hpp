#pragma once
// The printed summary of a pd-mesh run: counts, cell quality, area check,
// narrow voids, families, the estimate made before meshing and time per stage.
#include <cstddef>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "feature_sizes.hpp"
#include "families.hpp"
#include "grids.hpp"
#include "resource_estimate.hpp"

namespace pd {

struct StageTimes {
  std::vector<std::pair<std::string, double>> seconds;  // stage name, wall time [s]
};

struct MeshRun {
  const ParticleSet& particles;
  const PlateGeometry& geometry;
  const GridReport& grid;
  const FamilyReport& families;
  const std::vector<NarrowVoid>& narrow_voids;
  const ResourceEstimate& estimate;         // before meshing, from the plate's area
  const ResourceEstimate& meshed_estimate;  // once meshed, before the families
  const StageTimes& times;
  std::size_t smoothed_box_cells = 0;  // box cells whose horizon --horizon-smoothing grew
};

void print_mesh_summary(std::ostream& out, const MeshRun& run);

// Relative difference between the sum of the particle volumes and the exact
// area of the plate (loading-layer particles, outside it, not counted).
double area_error(const ParticleSet& particles, const PlateGeometry& geometry);

}  // namespace pd
