#pragma once
// A particle grid of a .geo plate built in-process, exactly as pd-mesh builds
// it (mesher/main.cpp): grid, spatial sort, families, boundary sets within one
// horizon of each boundary curve.
#include <string>

#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd::validation {

struct PlateGridSpec {
  std::string geometry_file;      // .geo, lengths in mm
  GridKind grid = GridKind::nbnug;
  double spacing = 0;             // dx [m]
  double horizon = 0;             // delta [m]
  Quadrature quadrature = Quadrature::analytic;
};

// The particle set, and the plate geometry (metres) in `geometry` if given.
ParticleSet make_plate_grid(const PlateGridSpec& spec, PlateGeometry* geometry = nullptr);

const char* grid_name(GridKind grid);  // "uniform", "free", "NB-NUG"

}  // namespace pd::validation
