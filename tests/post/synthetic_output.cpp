#include "synthetic_output.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "results_format.hpp"
#include "vtk_output.hpp"

namespace fs = std::filesystem;

namespace pd::post::test {
namespace {
// `fields` with each of `edited` in place of the field of its name, or added.
std::vector<FieldValue> with_edits(std::vector<FieldValue> fields, const std::vector<FieldValue>& edited) {
  for (const auto& e : edited) {
    const auto same = std::find_if(fields.begin(), fields.end(), [&](const FieldValue& f) { return f.name == e.name; });
    if (same == fields.end()) fields.push_back(e);
    else *same = e;
  }
  return fields;
}
}  // namespace

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

Lattice split_right_of(const Lattice& l, double x_from) {
  Lattice out = l;
  out.x.clear(), out.y.clear();
  for (std::size_t i = 0; i < l.x.size(); ++i) {
    const double h = l.cell_size.empty() ? l.spacing : l.cell_size[i];
    if (l.x[i] <= x_from) {
      out.x.push_back(l.x[i]), out.y.push_back(l.y[i]), out.cell_size.push_back(h);
      continue;
    }
    for (const double dx : {-0.25 * h, 0.25 * h})
      for (const double dy : {-0.25 * h, 0.25 * h})
        out.x.push_back(l.x[i] + dx), out.y.push_back(l.y[i] + dy), out.cell_size.push_back(0.5 * h);
  }
  return out;
}

double on_step(double t, double time_step) { return std::ceil(t / time_step - 1e-6) * time_step; }

void write_solver_summary(const std::string& dir, const std::string& plane, bool quasi_static) {
  fs::create_directories(dir);
  std::ofstream f(fs::path(dir) / results::summary_file);
  f << "{\n  \"tool\": \"pd-solve test\",\n";
  if (quasi_static) f << "  \"mode\": \"quasi_static\",\n";
  f << "  \"scene_text\": \"[material]\\nplane = \\\"strain\\\"  # \\\"plane\\\": \\\"strain\\\"\",\n";
  f << "  \"model\": \"pmb\",\n";
  if (!plane.empty()) f << "  \"plane\": \"" << plane << "\",\n";
  f << "  \"material\": {\"youngs_modulus_Pa\": 3.24e9, \"nested\": [1, 2.5e-3, true, null]},\n";
  f << "  \"effects\": {\"damage\": true, \"surface_correction\": true},\n";
  f << "  \"stop_reason\": \"end time\"\n}\n";
}

void write_arrival_output(const std::string& dir, const Lattice& l,
                          const std::function<double(double, double)>& arrival, double end_time,
                          const SyntheticRun& run) {
  const std::size_t n = l.x.size();
  std::vector<double> times(n), damage(n, 0.0), energy(n, 0.0);
  double last = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = arrival(l.x[i], l.y[i]);
    times[i] = t < 0 || t > end_time ? -1.0 : on_step(t, run.time_step);
    damage[i] = times[i] >= 0 ? run.cracked_damage : 0.0;
    last = std::max(last, times[i]);
  }
  for (const auto& [i, t] : run.edited_times) times[i] = t;
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
  const std::vector<double> cell_size = l.cell_size.empty() ? std::vector<double>(n, l.spacing) : l.cell_size;
  std::vector<double> volume(n);
  for (std::size_t i = 0; i < n; ++i) volume[i] = cell_size[i] * cell_size[i];
  std::vector<PointArray> arrays = {
      {results::volume, 1, volume},
      {results::cell_size, 1, cell_size},
      {results::damage, 1, damage},
      {results::strain_energy_density, 1, energy},
      {results::displacement, 3, std::vector<double>(3 * n, 0.0)}};
  for (double th : run.thresholds) arrays.push_back({results::arrival_array_name(th), 1, times});
  std::vector<FieldValue> fields = {
      {results::field_youngs_modulus, {run.youngs_field.value_or(test_youngs)}},
      {results::field_density, {run.density_field.value_or(test_density)}},
      {results::field_material_poisson_ratio, {run.material_poisson_field.value_or(test_nu)}},
      {results::field_time_step, {run.time_step_field.value_or(run.time_step)}},
      {results::field_thresholds, run.thresholds},
      {results::field_end_time, {run.end_time_field.value_or(end_time)}},
      {results::field_horizon, {3 * l.spacing}},
      {results::field_spacing, {l.spacing}},
      {results::field_step, {std::round(end_time / run.time_step)}}};
  if (run.model_poisson_ratio) fields.push_back({results::field_poisson_ratio, {*run.model_poisson_ratio}});
  if (run.plane_strain_field) fields.push_back({results::field_plane_strain, {*run.plane_strain_field ? 1.0 : 0.0}});
  fields = with_edits(fields, run.edited_fields);
  fs::create_directories(dir);
  write_vtp((fs::path(dir) / results::arrival_file).string(), l.x, l.y, arrays, fields);
  if (run.summary) write_solver_summary(dir, run.plane);
}

void write_arrival_output(const std::string& dir, const Lattice& l,
                          const std::function<double(double, double)>& arrival, double end_time,
                          const std::vector<double>& thresholds) {
  SyntheticRun run;
  run.thresholds = thresholds;
  write_arrival_output(dir, l, arrival, end_time, run);
}

void write_quasi_static_output(const std::string& dir, const Lattice& l, const QuasiStaticRun& run) {
  fs::create_directories(dir);
  const std::size_t n = l.x.size();
  // Without max_damage given, every row's is the damage field's largest
  // value, as final_state.vtp holds it (pd-post compares the last row's).
  double largest_damage = 0;
  for (std::size_t i = 0; i < n; ++i) largest_damage = std::max(largest_damage, run.damage(l.x[i], l.y[i]));
  {
    std::ofstream f(fs::path(dir) / results::load_steps_file);
    f.precision(15);  // as pd-solve writes them, to the last digit it keeps
    f << "step,load_factor,minimisations,iterations,relative_residual,converged,strain_energy_J,potential_energy_J,"
         "pairs_broken,broken_bonds,max_damage,left_reaction_x_N,left_reaction_y_N,right_reaction_x_N,"
         "right_reaction_y_N\n";
    for (std::size_t k = 0; k < run.load_factors.size(); ++k)
      f << k + 1 << ',' << run.load_factors[k] << ",1,10,1e-7,1,0.5,-0.5,0,0,"
        << (run.max_damage.empty() ? largest_damage : run.max_damage[k]) << ',' << -run.right_reaction_x[k]
        << ",0," << run.right_reaction_x[k] << ",0\n";
  }
  // The fields at load factor f: the final ones times f / (last load factor).
  auto fields = [&](double scale) {
    std::vector<double> u(3 * n, 0.0), d(n);
    for (std::size_t i = 0; i < n; ++i) {
      u[3 * i] = scale * run.ux(l.x[i], l.y[i]);
      u[3 * i + 1] = scale * run.uy(l.x[i], l.y[i]);
      d[i] = run.damage(l.x[i], l.y[i]);
    }
    return std::make_pair(u, d);
  };
  const double last = run.load_factors.back();
  if (run.final_state) {
    const auto [u, d] = fields(1.0);
    write_vtp((fs::path(dir) / results::final_state_file).string(), l.x, l.y,
              {{results::displacement, 3, u},
               {results::damage, 1, d},
               {results::damage_load_factor, 1, std::vector<double>(n, -1.0)},
               {results::volume, 1, std::vector<double>(n, l.spacing * l.spacing)}},
              with_edits({{results::field_load_factor, {last}},
                          {results::field_spacing, {l.spacing}},
                          {results::field_horizon, {3 * l.spacing}}},
                         run.edited_state_fields));
  }
  std::vector<std::pair<double, std::string>> entries;
  for (std::size_t s = 0; s < run.snapshot_factors.size(); ++s) {
    const double factor = run.snapshot_factors[s];
    auto [u, d] = fields(factor / last);
    // Single precision, as pd-solve writes its snapshots.
    std::vector<PointArray> arrays = {{results::displacement, 3}, {results::damage, 1}};
    arrays[0].float_values.assign(u.begin(), u.end());
    arrays[1].float_values.assign(d.begin(), d.end());
    char name[64];
    std::snprintf(name, sizeof name, "%s/step_%08zu.vtp", results::snapshot_folder, s + 1);
    fs::create_directories(fs::path(dir) / results::snapshot_folder);
    write_vtp((fs::path(dir) / name).string(), l.x, l.y, arrays,
              {{results::field_load_factor, {factor}}, {results::field_step, {double(s + 1)}}});
    entries.emplace_back(factor, name);
  }
  if (!entries.empty()) write_pvd((fs::path(dir) / results::snapshot_collection).string(), entries);
  if (run.summary) write_solver_summary(dir, "", true);
}

std::string fresh_dir(const std::string& name) {
  // One parent folder per process: CTest runs test cases in parallel.
  const fs::path p = fs::path(PD_POST_TEST_TMPDIR) / std::to_string(::getpid()) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

}  // namespace pd::post::test
