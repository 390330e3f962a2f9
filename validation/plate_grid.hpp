#pragma once
// A particle grid of a .geo plate built in-process, exactly as pd-mesh builds
// it (mesher/main.cpp): grid, spatial sort, families, boundary sets within one
// horizon of each boundary curve.
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "plate_geometry.hpp"
#include "scene.hpp"

namespace pd::validation {

struct PlateGridSpec {
  std::string geometry_file;      // .geo, lengths in mm
  GridKind grid = GridKind::nbnug;
  double spacing = 0;             // dx [m]
  double horizon = 0;             // delta [m]
  Quadrature quadrature = Quadrature::analytic;
  // NB-NUG boxes meshed at dx / box_refinement (pd-mesh --box-spacing), their
  // cells with the horizon delta / box_refinement; 1: the boxes at dx.
  int box_refinement = 1;
};

// pd-mesh --loading-layer: the sides with a fictitious loading layer, and its
// depth [m] (0: one horizon).
struct LoadingLayers {
  std::vector<std::string> edges;
  double depth = 0;
};

// Refuses, naming the geometry file, a grid of `spec` on `geometry` that
// would need more memory than is available (pd-mesh's estimate, finer NB-NUG
// boxes included): called by make_plate_grid, and by the tools for every
// grid they will build before they make their output folder.
void check_grid_fits_memory(const PlateGridSpec& spec, const PlateGeometry& geometry);

// The plate of `geometry_file` (lengths in mm), its curves sampled at
// `spacing` [m]: for the checks a tool makes before its output folder.
PlateGeometry plate_geometry_of(const std::string& geometry_file, double spacing);

// The particle set, and the plate geometry (metres) in `geometry` if given.
ParticleSet make_plate_grid(const PlateGridSpec& spec, PlateGeometry* geometry = nullptr,
                            const LoadingLayers& layers = {});

const char* grid_name(GridKind grid);  // "uniform", "free", "NB-NUG"

// The C1/C2 loading: x-displacement -u on the set `left_set` and +u on
// `right_set` [m] (by default the edge strips one horizon wide), y free.
std::vector<solver::LoadSpec> opposite_edge_displacements(double u, const std::string& left_set = "left",
                                                          const std::string& right_set = "right");

}  // namespace pd::validation
