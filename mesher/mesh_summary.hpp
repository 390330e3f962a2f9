#pragma once
// The printed summary of a pd-mesh run: counts, cell quality, area check,
// families and time per stage.
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "grids.hpp"

namespace pd {

struct StageTimes {
  std::vector<std::pair<std::string, double>> seconds;  // stage name, wall time [s]
};

void print_mesh_summary(std::ostream& out, const ParticleSet& particles, const PlateGeometry& geometry,
                        const GridReport& report, const StageTimes& times);

// Relative difference between the sum of the particle volumes and the exact
// area of the plate minus the holes.
double area_error(const ParticleSet& particles, const PlateGeometry& geometry);

}  // namespace pd
