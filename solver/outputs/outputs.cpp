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
  add_run_id_field(f, scene);
  return f;
}

// The per-particle arrays of the whole plate in the particle file's order:
// the simulation's own on one process; on several, gathered from their
// owners onto the root (docs/formats.md: the root holds the whole plate's
// output arrays while it writes; the other processes get nothing).
struct WholePlate {
  std::size_t count = 0;
  const std::vector<double>* x = nullptr;  // [m]
  const std::vector<double>* y = nullptr;
  std::vector<double> gathered_x, gathered_y;
  const double *ux = nullptr, *uy = nullptr, *vx = nullptr, *vy = nullptr;
  const double *damage = nullptr, *energy_density = nullptr;
  const double *volume = nullptr, *cell_size = nullptr, *arrival = nullptr;  // with_arrival only
  std::vector<std::vector<double>> gathered;  // what the pointers point into on several processes
};

// (Filled in place: the pointers point into `w`.)
void whole_plate(const Simulation& sim, bool with_arrival, WholePlate& w) {
  const auto& k = sim.kinematics();
  const ParticleSet& p = sim.state().reference;
  if (!sim.distributed()) {
    w.count = sim.particle_count();
    w.x = &p.x;
    w.y = &p.y;
    w.ux = k.ux.data(), w.uy = k.uy.data(), w.vx = k.vx.data(), w.vy = k.vy.data();
    w.damage = sim.damage().data();
    w.energy_density = sim.strain_energy_density().data();
    w.volume = p.volume.data(), w.cell_size = p.cell_size.data(), w.arrival = sim.arrival_times().data();
    return;
  }
  const Communicator& comm = sim.communicator();
  const std::size_t owned = sim.owned_count();
  const auto gather = [&](const double* local) {
    w.gathered.emplace_back();
    comm.gather_owned(local, owned, 1, w.gathered.back());
    return w.gathered.back().data();
  };
  w.gathered.reserve(16);  // (the pointers must not move)
  comm.gather_owned(p.x.data(), owned, 1, w.gathered_x);
  comm.gather_owned(p.y.data(), owned, 1, w.gathered_y);
  w.x = &w.gathered_x;
  w.y = &w.gathered_y;
  w.count = w.gathered_x.size();
  w.ux = gather(k.ux.data()), w.uy = gather(k.uy.data()), w.vx = gather(k.vx.data()), w.vy = gather(k.vy.data());
  w.damage = gather(sim.damage().data());
  w.energy_density = gather(sim.strain_energy_density().data());
  if (with_arrival) {
    w.volume = gather(p.volume.data());
    w.cell_size = gather(p.cell_size.data());
    std::vector<double> arrival;
    const std::size_t n = sim.particle_count();
    for (std::size_t t = 0; t < sim.scene().output.damage_thresholds.size(); ++t) {
      std::vector<double> one;
      comm.gather_owned(sim.arrival_times().data() + t * n, owned, 1, one);
      arrival.insert(arrival.end(), one.begin(), one.end());
    }
    w.gathered.push_back(std::move(arrival));
    w.arrival = w.gathered.back().data();
  }
}
}  // namespace

void add_run_id_field(std::vector<FieldValue>& fields, const Scene& scene) {
  if (!scene.run_id.empty()) fields.push_back({results::field_run_id, {}, scene.run_id});
}

std::string snapshot_name(long step) {
  char name[64];
  std::snprintf(name, sizeof name, "%s/step_%08ld.vtp", results::snapshot_folder, step);
  return name;
}

long snapshot_step_of(const std::string& name) {
  if (name.size() != 17 || name.compare(0, 5, "step_") != 0 || name.compare(13, 4, ".vtp") != 0 ||
      name.find_first_not_of("0123456789", 5) != 13)
    return -1;
  return std::stol(name.substr(5, 8));
}

std::string write_snapshot(const std::string& output_dir, const Simulation& sim, bool with_cell_size) {
  const std::string name = snapshot_name(sim.step_index());
  WholePlate w;
  whole_plate(sim, false, w);
  if (!sim.communicator().is_root()) return name;
  // (Named as a result path is: a folder replaced by a file during the run
  // is "cannot make its folder ...", not the library's "filesystem error".)
  const std::string path = (std::filesystem::path(output_dir) / name).string();
  create_folder_for(path);
  // Float32, made from the state one piece of the file at a time (no
  // whole-plate copies on the way).
  std::vector<PointArray> arrays(4);
  arrays[0] = {results::displacement, 3};
  arrays[0].float_fill = float_fill_of(w.ux, w.uy);
  arrays[1] = {results::velocity, 3};
  arrays[1].float_fill = float_fill_of(w.vx, w.vy);
  arrays[2] = {results::damage, 1};
  arrays[2].float_fill = float_fill_of(w.damage);
  arrays[3] = {results::strain_energy_density, 1};
  arrays[3].float_fill = float_fill_of(w.energy_density);
  // (A refined run is on one process, where the reference set holds the sizes.)
  if (with_cell_size && !sim.distributed())
    arrays.push_back({results::cell_size, 1, {}, sim.state().reference.cell_size.data()});
  std::vector<FieldValue> fields{{results::field_time, {sim.time()}},
                                 {results::field_step, {static_cast<double>(sim.step_index())}}};
  add_run_id_field(fields, sim.scene());
  write_vtp(path, *w.x, *w.y, arrays, fields);
  return name;
}

void write_snapshot_collection(const std::string& output_dir, const std::string& run_id, long interval, long last_step,
                               double time_step) {
  write_snapshot_collection(output_dir, run_id, interval, last_step, [time_step](long s) { return s * time_step; });
}

void write_snapshot_collection(const std::string& output_dir, const std::string& run_id, long interval, long last_step,
                               const std::function<double(long)>& time_of_step, bool with_last_step) {
  std::vector<std::pair<double, std::string>> entries;
  if (interval > 0) {
    for (long s = 0; s <= last_step; s += interval) entries.emplace_back(time_of_step(s), snapshot_name(s));
    if (with_last_step && last_step % interval != 0)
      entries.emplace_back(time_of_step(last_step), snapshot_name(last_step));
  }
  write_pvd((std::filesystem::path(output_dir) / results::snapshot_collection).string(), entries, run_id);
}

void write_run_table(const std::string& path, const std::string& header, const std::vector<std::string>& rows,
                     const std::string& run_id) {
  // A column, not a comment line before the header: readers that take the
  // first line as the column names (csv.DictReader, pandas) read it as before.
  const std::string last = run_id.empty() ? std::string() : "," + run_id;
  write_atomically(path, [&](std::ofstream& out) {
    out << header << (run_id.empty() ? "" : std::string(",") + results::field_run_id) << '\n';
    for (const auto& r : rows) out << r << last << '\n';
  });
}

EnergyLog::EnergyLog(const Simulation& sim) : run_id_(sim.scene().run_id) {
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
  row << ',' << sim.whole_particle_count();  // the whole plate's, on any number of processes
  rows_.push_back(row.str());
}

void EnergyLog::write(const std::string& output_dir) const {
  write_run_table((std::filesystem::path(output_dir) / results::energy_file).string(), header_, rows_, run_id_);
}

void write_arrival(const std::string& output_dir, const Simulation& sim) {
  WholePlate w;
  whole_plate(sim, true, w);
  if (!sim.communicator().is_root()) return;
  const std::size_t n = w.count;
  std::vector<PointArray> arrays;
  // Arrays that exist already are borrowed, not copied (this file is written for the largest runs too).
  arrays.push_back({results::volume, 1, {}, w.volume});
  arrays.push_back({results::cell_size, 1, {}, w.cell_size});
  arrays.push_back({results::damage, 1, {}, w.damage});
  arrays.push_back({results::strain_energy_density, 1, {}, w.energy_density});
  // The one array made for the file: Float32, as in the snapshots, one piece
  // of the file at a time (docs/performance.md).
  PointArray displacement{results::displacement, 3};
  displacement.float_fill = float_fill_of(w.ux, w.uy);
  arrays.push_back(std::move(displacement));
  const auto& thresholds = sim.scene().output.damage_thresholds;
  for (std::size_t t = 0; t < thresholds.size(); ++t)
    arrays.push_back({results::arrival_array_name(thresholds[t]), 1, {}, w.arrival + t * n});
  auto fields = material_fields(sim);
  fields.push_back({results::field_spacing, {sim.state().reference.spacing}});
  fields.push_back({results::field_time, {sim.time()}});
  fields.push_back({results::field_step, {static_cast<double>(sim.step_index())}});
  write_vtp((std::filesystem::path(output_dir) / results::arrival_file).string(), *w.x, *w.y, arrays, fields);
}

}  // namespace pd::solver
