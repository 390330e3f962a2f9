#pragma once
// VTK XML PolyData (.vtp) and ParaView collection (.pvd) writing, shared by
// every tool. Files are written atomically. Points are particles (z = 0),
// one vertex cell each, so ParaView shows them with "Points" or "Point Gaussian".
#include <string>
#include <utility>
#include <vector>

namespace pd {

struct ParticleSet;

// One named point array: `components` values per point (1 = scalar, 3 = vector).
// The values are `values`, or, when `borrowed` is set, the points' values
// there (not copied: large runs write their arrays without a second copy).
struct PointArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
  bool single_precision = false;  // store as Float32 to halve snapshot size
  const double* borrowed = nullptr;
};

// One named field-data array (metadata attached to the whole data set).
struct FieldValue {
  std::string name;
  std::vector<double> values;
};

void write_vtp(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
               const std::vector<PointArray>& arrays, const std::vector<FieldValue>& fields = {});

// Writes a .pvd collection of (time [s], file name relative to the .pvd).
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& entries);

// The particle-file view for ParaView: point arrays volume, region, horizon,
// neighbors (family size), neighborhood_area (sum of phi_ij V_j), cell_size, material.
void write_particles_vtp(const std::string& path, const ParticleSet& particles);

}  // namespace pd
