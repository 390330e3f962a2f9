#include "outputs.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <utility>

#include "atomic_file.hpp"
#include "results_format.hpp"
#include "vtk_output.hpp"

namespace pd::solver {
namespace {
std::string snapshot_name(long step) {
  char name[64];
  std::snprintf(name, sizeof name, "%s/step_%08ld.vtp", results::snapshot_folder, step);
  return name;
}

std::string format_double(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

std::vector<FieldValue> material_fields(const Simulation& sim) {
  const auto& scene = sim.scene();
  std::vector<FieldValue> f;
  f.push_back({results::field_youngs_modulus, {scene.material.youngs_modulus}});
  f.push_back({results::field_density, {scene.material.density}});
  f.push_back({results::field_poisson_ratio, {sim.model().model_poisson_ratio}});
  f.push_back({results::field_material_poisson_ratio, {scene.material.poisson_ratio}});
  f.push_back({results::field_time_step, {sim.time_step()}});
  f.push_back({results::field_thresholds, scene.output.damage_thresholds});
  f.push_back({results::field_end_time, {sim.time()}});
  f.push_back({results::field_horizon, {sim.model().horizon}});
  f.push_back({results::field_plane_strain, {scene.material.plane == PlaneKind::strain ? 1.0 : 0.0}});
  return f;
}
}  // namespace

std::string write_snapshot(const std::string& output_dir, const Simulation& sim) {
  std::filesystem::create_directories(std::filesystem::path(output_dir) / results::snapshot_folder);
  const std::string name = snapshot_name(sim.step_index());
  // Float32, built directly from the state (no Float64 copies on the way).
  const std::size_t n = sim.particle_count();
  const auto& k = sim.kinematics();
  std::vector<PointArray> arrays(4);
  arrays[0] = {results::displacement, 3};
  arrays[0].float_values = float_vectors(n, [&](std::size_t i) { return std::pair{k.ux[i], k.uy[i]}; });
  arrays[1] = {results::velocity, 3};
  arrays[1].float_values = float_vectors(n, [&](std::size_t i) { return std::pair{k.vx[i], k.vy[i]}; });
  arrays[2] = {results::damage, 1};
  arrays[2].float_values = float_values_of(sim.damage().data(), n);
  arrays[3] = {results::strain_energy_density, 1};
  arrays[3].float_values = float_values_of(sim.strain_energy_density().data(), n);
  const std::vector<FieldValue> fields{{results::field_time, {sim.time()}},
                                       {results::field_step, {static_cast<double>(sim.step_index())}}};
  write_vtp((std::filesystem::path(output_dir) / name).string(), sim.reference_x(), sim.reference_y(), arrays,
            fields);
  return name;
}

void write_snapshot_collection(const std::string& output_dir, long interval, long last_step, double time_step) {
  write_snapshot_collection(output_dir, interval, last_step, [time_step](long s) { return s * time_step; });
}

void write_snapshot_collection(const std::string& output_dir, long interval, long last_step,
                               const std::function<double(long)>& time_of_step) {
  std::vector<std::pair<double, std::string>> entries;
  if (interval > 0)
    for (long s = 0; s <= last_step; s += interval) entries.emplace_back(time_of_step(s), snapshot_name(s));
  write_pvd((std::filesystem::path(output_dir) / results::snapshot_collection).string(), entries);
}

EnergyLog::EnergyLog(const Simulation& sim) {
  header_ = "time_s,step,kinetic_J,strain_J,external_work_J,total_minus_work_J,broken_bonds";
  for (const auto& load : sim.loads()) {
    if (load.spec.kind == LoadKind::initial_velocity) continue;
    header_ += ",reaction_x_" + load.spec.name + "_N,reaction_y_" + load.spec.name + "_N";
  }
  header_ += std::string(",") + results::energy_particles_column;
}

void EnergyLog::record(const Simulation& sim, const EnergyTotals& e) {
  std::ostringstream row;
  row << format_double(sim.time()) << ',' << sim.step_index() << ',' << format_double(e.kinetic) << ','
      << format_double(e.strain) << ',' << format_double(e.external_work) << ','
      << format_double(e.kinetic + e.strain - e.external_work) << ',' << sim.broken_bond_count();
  const auto& resultants = sim.load_resultants();
  for (std::size_t l = 0; l < sim.loads().size(); ++l) {
    if (sim.loads()[l].spec.kind == LoadKind::initial_velocity) continue;
    row << ',' << format_double(resultants[l].reaction_x) << ',' << format_double(resultants[l].reaction_y);
  }
  row << ',' << sim.particle_count();
  rows_.push_back(row.str());
}

void EnergyLog::write(const std::string& output_dir) const {
  write_atomically((std::filesystem::path(output_dir) / results::energy_file).string(), [&](std::ofstream& out) {
    out << header_ << '\n';
    for (const auto& r : rows_) out << r << '\n';
  });
}

void write_arrival(const std::string& output_dir, const Simulation& sim) {
  const std::size_t n = sim.particle_count();
  const ParticleSet& particles = sim.state().reference;
  std::vector<PointArray> arrays;
  // Arrays that exist already are borrowed, not copied (this file is written for the largest runs too).
  arrays.push_back({results::volume, 1, {}, particles.volume.data()});
  arrays.push_back({results::cell_size, 1, {}, particles.cell_size.data()});
  arrays.push_back({results::damage, 1, {}, sim.damage().data()});
  arrays.push_back({results::strain_energy_density, 1, sim.strain_energy_density()});
  arrays.push_back({results::displacement, 3, sim.displacement_xyz()});
  const auto& thresholds = sim.scene().output.damage_thresholds;
  for (std::size_t t = 0; t < thresholds.size(); ++t) {
    char name[64];
    std::snprintf(name, sizeof name, "%s%.2f", results::arrival_prefix, thresholds[t]);
    arrays.push_back({name, 1, {}, sim.arrival_times().data() + t * n});
  }
  auto fields = material_fields(sim);
  fields.push_back({results::field_spacing, {particles.spacing}});
  fields.push_back({results::field_time, {sim.time()}});
  fields.push_back({results::field_step, {static_cast<double>(sim.step_index())}});
  write_vtp((std::filesystem::path(output_dir) / results::arrival_file).string(), particles.x, particles.y, arrays,
            fields);
}

}  // namespace pd::solver
