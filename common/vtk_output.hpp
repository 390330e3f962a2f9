#pragma once
// VTK XML PolyData (.vtp) and ParaView collection (.pvd) writing, shared by
// every tool. Files are written atomically. Points are particles (z = 0),
// one vertex cell each, so ParaView shows them with "Points" or "Point Gaussian".
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace pd {

struct ParticleSet;

// One named point array: `components` values per point (1 = scalar, 3 = vector).
// The values are `values` (Float64), or, when `borrowed` is set, the points'
// values there (Float64, not copied: large runs write their arrays without a
// second copy), or, when `float_values` is not empty, those (Float32: half
// the size; build them with float_values_of / float_vectors), or, when
// `float_fill` is set, Float32 values made one piece of the file at a time
// (write_vtp): float_fill(first, count, into) writes the values of points
// first .. first + count - 1 into `into` (components each), so that the
// whole array never exists in memory (the snapshots of large runs).
struct PointArray {
  std::string name;
  int components = 1;
  std::vector<double> values{};
  const double* borrowed = nullptr;
  std::vector<float> float_values{};
  std::function<void(std::size_t first, std::size_t count, float* into)> float_fill{};
};

// Float32 copies for PointArray::float_values, made without a Float64 copy in
// between: scalars, and 2D vectors xy(i) -> (x, y) written as (x, y, 0).
std::vector<float> float_values_of(const double* values, std::size_t count);
template <class XY>
std::vector<float> float_vectors(std::size_t points, const XY& xy) {
  std::vector<float> v(3 * points, 0.0f);
  for (std::size_t i = 0; i < points; ++i) {
    const auto [x, y] = xy(i);
    v[3 * i] = static_cast<float>(x);
    v[3 * i + 1] = static_cast<float>(y);
  }
  return v;
}
// The same as PointArray::float_fill, piece by piece: scalars from `values`,
// and 2D vectors from x and y (written as (x, y, 0)).
std::function<void(std::size_t, std::size_t, float*)> float_fill_of(const double* values);
std::function<void(std::size_t, std::size_t, float*)> float_fill_of(const double* x, const double* y);

// One named field-data array (metadata attached to the whole data set):
// `values` (Float64), or, when `text` is not empty, that one text (a VTK
// string array of one value: the run's identifier, which no double holds).
struct FieldValue {
  std::string name;
  std::vector<double> values;
  std::string text{};
};

// Large point sets are written in pieces of at most vtp_piece_points points
// (VTK XML streaming: one <Piece> after the other in the same file, which
// every VTK reader reads as one data set), so that the points, the vertex
// cells and the float_fill arrays made for the file exist for one piece at a
// time; a smaller set is one piece.
inline constexpr std::size_t vtp_piece_points = std::size_t{1} << 16;
void write_vtp(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
               const std::vector<PointArray>& arrays, const std::vector<FieldValue>& fields = {});

// Writes a .pvd collection of (time [s], file name relative to the .pvd).
// `run_id`, when not empty, goes into the Collection element as its attribute
// run_id (a solver run's identifier, docs/formats.md): ParaView reads only
// the DataSet elements' attributes, so it ignores it.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& entries,
               const std::string& run_id = {});

// The particle-file view for ParaView: point arrays volume, region, horizon,
// neighbors (family size), neighborhood_area (sum of phi_ij V_j), cell_size, material.
void write_particles_vtp(const std::string& path, const ParticleSet& particles);

// Whether `path` is such a view (its XML head names the array
// neighborhood_area, which only this view has): pd-mesh replaces only a view
// of an earlier run under --vtk's name, not a run's arrival.vtp or a
// snapshot, nor another file.
bool is_particle_view(const std::string& path);

}  // namespace pd
