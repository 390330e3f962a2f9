#include "synthetic_output.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "results_format.hpp"
#include "vtk_output.hpp"

namespace fs = std::filesystem;

namespace pd::post::test {

Lattice make_lattice(double width, double height, double spacing, const std::vector<Hole>& holes) {
  Lattice l;
  l.width = width, l.height = height, l.spacing = spacing;
  const int nx = static_cast<int>(std::lround(width / spacing));
  const int ny = static_cast<int>(std::lround(height / spacing));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5) * spacing, y = (j + 0.5) * spacing;
      bool inside = false;
      for (const auto& h : holes) inside |= std::hypot(x - h.x, y - h.y) < h.r;
      if (!inside) l.x.push_back(x), l.y.push_back(y);
    }
  return l;
}

double on_step(double t) { return std::ceil(t / test_time_step - 1e-6) * test_time_step; }

void write_arrival_output(const std::string& dir, const Lattice& l,
                          const std::function<double(double, double)>& arrival, double end_time,
                          const std::vector<double>& thresholds) {
  const std::size_t n = l.x.size();
  std::vector<double> times(n), damage(n, 0.0), energy(n, 0.0);
  double last = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = arrival(l.x[i], l.y[i]);
    times[i] = t < 0 || t > end_time ? -1.0 : on_step(t);
    damage[i] = times[i] >= 0 ? 1.0 : 0.0;
    last = std::max(last, times[i]);
  }
  // A made-up strain energy density, only for the pictures: peaks of
  // 1e6 J/m^3 (1 mm wide) at the final crack tips over 2e3 J/m^3, none on the crack.
  std::vector<std::size_t> tips;
  for (std::size_t i = 0; i < n; ++i)
    if (times[i] >= 0 && times[i] >= last - 0.2e-6) tips.push_back(i);
  for (std::size_t i = 0; i < n; ++i) {
    double d2 = 1e300;
    for (auto k : tips) d2 = std::min(d2, std::pow(l.x[i] - l.x[k], 2) + std::pow(l.y[i] - l.y[k], 2));
    energy[i] = times[i] >= 0 ? 0.0 : 2e3 + 1e6 * std::exp(-d2 / 1e-6);
  }
  std::vector<PointArray> arrays = {
      {results::volume, 1, std::vector<double>(n, l.spacing * l.spacing)},
      {results::cell_size, 1, std::vector<double>(n, l.spacing)},
      {results::damage, 1, damage},
      {results::strain_energy_density, 1, energy},
      {results::displacement, 3, std::vector<double>(3 * n, 0.0)}};
  for (double th : thresholds) {
    char name[64];
    std::snprintf(name, sizeof name, "%s%.2f", results::arrival_prefix, th);
    arrays.push_back({name, 1, times});
  }
  const std::vector<FieldValue> fields = {
      {results::field_youngs_modulus, {test_youngs}},
      {results::field_density, {test_density}},
      {results::field_poisson_ratio, {1.0 / 3.0}},
      {results::field_material_poisson_ratio, {test_nu}},
      {results::field_time_step, {test_time_step}},
      {results::field_thresholds, thresholds},
      {results::field_end_time, {end_time}},
      {results::field_horizon, {3 * l.spacing}},
      {results::field_spacing, {l.spacing}}};
  fs::create_directories(dir);
  write_vtp((fs::path(dir) / results::arrival_file).string(), l.x, l.y, arrays, fields);
}

std::string fresh_dir(const std::string& name) {
  // One parent folder per process: CTest runs test cases in parallel.
  const fs::path p = fs::path(PD_POST_TEST_TMPDIR) / std::to_string(::getpid()) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

}  // namespace pd::post::test
