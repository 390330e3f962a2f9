#include "run.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "atomic_file.hpp"
#include "checkpoint.hpp"
#include "error.hpp"
#include "loads.hpp"
#include "outputs.hpp"
#include "particle_file.hpp"
#include "peak_memory.hpp"
#include "pd/version.hpp"
#include "progress.hpp"
#include "quasi_static_run.hpp"
#include "results_format.hpp"
#include "simulation.hpp"
#include "static_then_dynamic.hpp"

namespace pd::solver {
namespace {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (c == '\n') out += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) out += ' ';
    else out += c;
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream out;
  out << std::setprecision(12) << v;
  return out.str();
}

std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

long step_count(double end_time, double dt) {
  // The last step reaches or passes end_time; the 1e-9 guards against 2e-4/2e-8 = 10000.000000001.
  return std::max(1L, static_cast<long>(std::ceil(end_time / dt - 1e-9)));
}

// Largest damage among the stop region's particles.
double region_damage(const Simulation& sim, const std::vector<std::uint32_t>& region) {
  if (!sim.has_damage()) return 0;
  const auto& d = sim.damage();
  double largest = 0;
  for (auto i : region) largest = std::max(largest, d[i]);
  return largest;
}

void print_plan(std::ostream& log, const Scene& scene, const ParticleSet& particles, const Simulation& sim,
                long first_step, long last_step, const std::string& output_dir) {
  const auto& m = scene.material;
  const auto& pmb = sim.pmb();
  log << "pd-solve " << version_string << "\n"
      << "  scene:     " << scene.path << "\n"
      << "  particles: " << scene.particle_file << " (" << particles.size() << " particles, " << sim.bond_count()
      << " directed bonds, spacing " << particles.spacing << " m, horizon " << pmb.horizon << " m)\n"
      << "  model:     PMB bond-based, plane " << (m.plane == PlaneKind::stress ? "stress" : "strain")
      << " (model Poisson ratio " << pmb.model_poisson_ratio << "), c*h = " << pmb.micromodulus_area
      << " N/m^5, s0 = " << pmb.critical_stretch << ", bond weights "
      << (scene.bond_weights == BondWeights::distance_moment ? "distance_moment" : "partial_volume") << "\n"
      << "  kernel:    lattice sweep for " << sim.lattice_particle_count() << " particles, neighbour lists for "
      << particles.size() - sim.lattice_particle_count() << "\n"
      << "  effects:   damage " << (scene.effects.damage ? "on" : "off") << ", surface correction "
      << (scene.effects.surface_correction
              ? std::string("on (") + (sim.surface_correction_from_cache() ? "from cache" : std::to_string(sim.surface_correction_iterations()) + " iterations") + ")"
              : std::string("off"))
      << ", pre-cracks " << scene.precracks.size() << " (" << sim.precrack_bonds_cut() << " directed bonds cut)\n"
      << "  loads:     ";
  if (sim.loads().empty()) log << "none";
  for (const auto& load : sim.loads())
    log << "\n    " << load.spec.name << ": " << to_string(load.spec.kind) << " on " << load.spec.region.describe()
        << " (" << load.particles.size() << " particles)"
        << (load.spec.kind == LoadKind::traction ? ", edge length " + format_number(load.edge_length) + " m" : "");
  log << "\n  time step: " << sim.time_step() << " s (stable limit " << sim.stable_time_step() << " s"
      << (scene.time.automatic ? ", safety " + format_number(scene.time.safety) : std::string(", fixed"))
      << (sim.time_step() > sim.stable_time_step() ? ", ABOVE THE LIMIT (forced)" : "") << ")\n"
      << "  steps:     " << first_step << " -> " << last_step << " (end time " << scene.time.end << " s)\n"
      << "  threads:   " << omp_get_max_threads() << "\n"
      << "  output:    " << output_dir << ": energy every " << scene.output.energy_interval << " steps, snapshots "
      << (scene.output.snapshot_interval ? "every " + std::to_string(scene.output.snapshot_interval) + " steps" : std::string("off"))
      << ", checkpoints "
      << (scene.output.checkpoint_interval ? "every " + std::to_string(scene.output.checkpoint_interval) + " steps" : std::string("off"))
      << "\n";
  if (scene.stop.enabled)
    log << "  stop:      when damage >= " << scene.stop.damage << " in " << scene.stop.region.describe() << "\n";
  log << std::flush;
}

void write_summary(const std::string& output_dir, const Scene& scene, const ParticleSet& particles,
                   const std::string& particle_hash, const Simulation& sim, const RunReport& report, int threads,
                   long steps_this_run) {
  const auto e = sim.energies();
  const auto d = sim.damage();
  std::size_t damaged = 0;
  for (double v : d) damaged += v > 0 ? 1 : 0;
  std::ostringstream j;
  j << "{\n"
    << "  \"tool\": " << json_string(std::string("pd-solve ") + version_string) << ",\n"
    << "  \"scene\": " << json_string(scene.path) << ",\n"
    << "  \"scene_text\": " << json_string(scene.canonical_text) << ",\n"
    << "  \"particle_file\": " << json_string(scene.particle_file) << ",\n"
    << "  \"particle_file_hash\": " << json_string(particle_hash) << ",\n"
    << "  \"model\": \"pmb\",\n"
    << "  \"bond_weights\": "
    << json_string(scene.bond_weights == BondWeights::distance_moment ? "distance_moment" : "partial_volume") << ",\n"
    << "  \"plane\": " << json_string(scene.material.plane == PlaneKind::stress ? "stress" : "strain") << ",\n"
    << "  \"material\": {\"youngs_modulus_Pa\": " << json_number(scene.material.youngs_modulus)
    << ", \"density_kg_m3\": " << json_number(scene.material.density)
    << ", \"fracture_energy_J_m2\": " << json_number(scene.material.fracture_energy)
    << ", \"thickness_m\": " << json_number(scene.material.thickness)
    << ", \"material_poisson_ratio\": " << json_number(scene.material.poisson_ratio)
    << ", \"model_poisson_ratio\": " << json_number(sim.pmb().model_poisson_ratio) << "},\n"
    << "  \"constants\": {\"micromodulus_times_thickness\": " << json_number(sim.pmb().micromodulus_area)
    << ", \"critical_stretch\": " << json_number(sim.pmb().critical_stretch)
    << ", \"horizon_m\": " << json_number(sim.pmb().horizon) << ", \"spacing_m\": " << json_number(particles.spacing)
    << "},\n"
    << "  \"effects\": {\"damage\": " << (scene.effects.damage ? "true" : "false")
    << ", \"surface_correction\": " << (scene.effects.surface_correction ? "true" : "false") << "},\n"
    << "  \"counts\": {\"particles\": " << particles.size() << ", \"directed_bonds\": " << sim.bond_count()
    << ", \"precrack_bonds_cut\": " << sim.precrack_bonds_cut() << ", \"loads\": " << sim.loads().size() << "},\n"
    << "  \"time_step_s\": " << json_number(sim.time_step()) << ",\n"
    << "  \"stable_time_step_s\": " << json_number(sim.stable_time_step()) << ",\n"
    << "  \"requested_end_time_s\": " << json_number(scene.time.end) << ",\n"
    << "  \"steps\": " << report.steps << ",\n"
    << "  \"steps_this_run\": " << steps_this_run << ",\n"
    << "  \"end_time_s\": " << json_number(report.time) << ",\n"
    << "  \"stop_reason\": " << json_string(report.stop_reason) << ",\n"
    << "  \"threads\": " << threads << ",\n"
    << "  \"wall_time_s\": " << json_number(report.wall_seconds) << ",\n"
    << "  \"directed_bond_evaluations_per_second\": " << json_number(report.bond_evaluations_per_second) << ",\n"
    << "  \"directed_bond_evaluations_per_second_per_thread\": "
    << json_number(report.bond_evaluations_per_second / std::max(1, threads)) << ",\n"
    << "  \"peak_memory_bytes\": " << peak_memory_bytes() << ",\n"
    << "  \"peak_memory_bytes_per_directed_bond\": "
    << json_number(sim.bond_count() > 0 ? static_cast<double>(peak_memory_bytes()) / sim.bond_count() : 0.0) << ",\n"
    << "  \"final\": {\"kinetic_energy_J\": " << json_number(e.kinetic) << ", \"strain_energy_J\": "
    << json_number(e.strain) << ", \"external_work_J\": " << json_number(e.external_work)
    << ", \"broken_bonds\": " << sim.broken_bond_count() << ", \"damaged_particles\": " << damaged
    << ", \"max_damage\": " << json_number(d.empty() ? 0.0 : *std::max_element(d.begin(), d.end())) << "}\n"
    << "}\n";
  write_atomically((std::filesystem::path(output_dir) / results::summary_file).string(),
                   [&](std::ofstream& out) { out << j.str(); });
}

}  // namespace

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  if (scene.quasi_static.enabled)
    return scene.quasi_static.then_dynamic ? run_static_then_dynamic(scene, options)
                                           : run_quasi_static_scene(scene, options);
  std::ostream& log = options.log ? *options.log : std::cout;
  if (options.output_dir.empty()) throw Error("no output directory given");
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const int threads = omp_get_max_threads();
  const std::string& out = options.output_dir;
  std::filesystem::create_directories(out);
  const auto path_in_out = [&](const std::string& name) { return (std::filesystem::path(out) / name).string(); };

  // The families stream by and stay compact (compact_families.hpp): the
  // particle file's 12 bytes per bond are never held at once.
  auto read = read_compact_particle_file(scene.particle_file);
  ParticleSet& particles = read.particles;
  const std::string particle_hash = file_hash_hex(scene.particle_file);
  SimulationOptions sim_options;
  sim_options.surface_correction_cache = path_in_out(surface_correction_cache_file);
  sim_options.particle_file_hash = particle_hash;
  Simulation sim(scene, particles, std::move(read.families), sim_options);
  // The cell polygons served the bond weights only.
  std::vector<std::uint64_t>().swap(particles.cell_offsets);
  std::vector<double>().swap(particles.cell_vx);
  std::vector<double>().swap(particles.cell_vy);
  std::vector<std::uint64_t>().swap(particles.family_offsets);

  const std::string checkpoint_key = scene.restart_key_text + "\nparticles " + particle_hash;
  EnergyLog energy(sim);
  if (options.restart) {
    Checkpoint c = read_checkpoint(path_in_out(checkpoint_file), checkpoint_key);
    sim.restore_state(c.state);
    energy.set_rows(std::move(c.energy_rows));
  } else {
    if (options.initial_state) options.initial_state(sim);
    energy.record(sim);
    if (scene.output.snapshot_interval > 0) write_snapshot(out, sim);
    // A start state that took work to reach (a quasi-static equilibrium) is
    // saved at once, so that a restart never has to reach it again.
    if (options.initial_state && scene.output.checkpoint_interval > 0)
      write_checkpoint(path_in_out(checkpoint_file), checkpoint_key, {sim.save_state(), energy.rows()});
  }
  const long first_step = sim.step_index();
  const long last_step = step_count(scene.time.end, sim.time_step());
  print_plan(log, scene, particles, sim, first_step, last_step, out);

  std::vector<std::uint32_t> stop_region;
  if (scene.stop.enabled) stop_region = resolve_region(scene.stop.region, particles, scene.path, "stop");

  const auto& o = scene.output;
  const auto write_progress_files = [&] {
    energy.write(out);
    write_snapshot_collection(out, o.snapshot_interval, sim.step_index(), sim.time_step());
    write_arrival(out, sim, particles);
  };

  RunReport report;
  report.stop_reason = "end time";
  // Set-up of the loop (not timed): the initial energy and the first safe state.
  const auto e0 = sim.energies();
  const double initial_energy = e0.kinetic + e0.strain;
  Simulation::State last_good = sim.save_state();
  Progress progress(first_step, last_step, sim.bond_count(), options.show_progress);

  while (sim.step_index() < last_step) {
    sim.step();
    const long step = sim.step_index();
    const NonFinite& bad = sim.non_finite();
    bool blow_up = false;
    std::string blow_up_text;
    if (!bad.found && step % o.energy_interval == 0) {
      const auto e = sim.energies();
      energy.record(sim, e);
      // Energy blow-up: the plate holds far more energy than it was ever given.
      const double supplied = std::fabs(e.external_work) + initial_energy;
      if (e.kinetic + e.strain > 100.0 * supplied + 1e-15) {
        blow_up = true;
        std::ostringstream m;
        m << "kinetic + strain energy " << e.kinetic + e.strain << " J exceeds 100 x the energy supplied ("
          << supplied << " J)";
        blow_up_text = m.str();
      } else {
        sim.save_state(last_good);
      }
    }
    if (bad.found || blow_up) {
      std::ostringstream m;
      m << "the run became unstable at step " << step << " (t = " << sim.time() << " s): ";
      if (bad.found)
        m << "non-finite " << bad.quantity << " of particle " << bad.particle << " at (" << particles.x[bad.particle]
          << ", " << particles.y[bad.particle] << ") m";
      else
        m << blow_up_text;
      m << "; time step " << sim.time_step() << " s, stable limit " << sim.stable_time_step() << " s";
      sim.restore_state(last_good);
      if (o.snapshot_interval > 0) write_snapshot(out, sim);
      energy.write(out);
      write_arrival(out, sim, particles);
      m << "; the last good state (step " << sim.step_index() << ") is in " << out;
      progress.finish(step, sim.time());
      throw Error(m.str());
    }
    if (o.snapshot_interval > 0 && step % o.snapshot_interval == 0) {
      write_snapshot(out, sim);
      write_snapshot_collection(out, o.snapshot_interval, step, sim.time_step());
      energy.write(out);
    }
    if (o.checkpoint_interval > 0 && step % o.checkpoint_interval == 0) {
      write_checkpoint(path_in_out(checkpoint_file), checkpoint_key, {sim.save_state(), energy.rows()});
      write_progress_files();
    }
    if (scene.stop.enabled && region_damage(sim, stop_region) >= scene.stop.damage) {
      std::ostringstream m;
      m << "stop condition: damage >= " << scene.stop.damage << " in " << scene.stop.region.describe();
      report.stop_reason = m.str();
      break;
    }
    progress.update(step, sim.time());
  }
  progress.finish(sim.step_index(), sim.time());
  if (energy.rows().empty() || sim.step_index() % o.energy_interval != 0) energy.record(sim);
  write_progress_files();
  report.steps = sim.step_index();
  report.time = sim.time();
  report.wall_seconds = progress.elapsed_seconds();
  const long steps_this_run = sim.step_index() - first_step;
  report.bond_evaluations_per_second =
      report.wall_seconds > 0 ? steps_this_run * static_cast<double>(sim.bond_count()) / report.wall_seconds : 0;
  write_summary(out, scene, particles, particle_hash, sim, report, threads, steps_this_run);
  log << "done: " << report.steps << " steps, t = " << report.time << " s (" << report.stop_reason << "), "
      << report.wall_seconds << " s wall, " << report.bond_evaluations_per_second
      << " directed bond evaluations/s (" << report.bond_evaluations_per_second / threads << " per thread), peak memory "
      << peak_memory_bytes() / (1024 * 1024) << " MB ("
      << static_cast<double>(peak_memory_bytes()) / std::max<std::uint64_t>(1, sim.bond_count()) << " bytes per directed bond)\n";
  return report;
}

}  // namespace pd::solver
