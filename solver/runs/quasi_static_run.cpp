#include "quasi_static_run.hpp"

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "atomic_file.hpp"
#include "checkpoint.hpp"
#include "error.hpp"
#include "pd/version.hpp"
#include "peak_memory.hpp"
#include "load_steps.hpp"
#include "results_format.hpp"
#include "vtk_output.hpp"

namespace pd::solver {
namespace {

std::string number(double v) {
  std::ostringstream out;
  out << std::setprecision(12) << v;
  return out.str();
}

std::string load_steps_header(const std::vector<ResolvedLoad>& loads) {
  std::string h =
      "step,load_factor,minimisations,iterations,relative_residual,converged,strain_energy_J,potential_energy_J,"
      "pairs_broken,broken_bonds,max_damage";
  for (const auto& load : loads) h += "," + load.spec.name + "_reaction_x_N," + load.spec.name + "_reaction_y_N";
  return h;
}

std::string load_steps_row(const LoadStepRecord& r) {
  std::string row = std::to_string(r.step) + "," + number(r.load_factor) + "," + std::to_string(r.minimisations) +
                    "," + std::to_string(r.iterations) + "," + number(r.relative_residual) + "," +
                    (r.converged ? "1" : "0") + "," + number(r.strain_energy) + "," + number(r.potential_energy) +
                    "," + std::to_string(r.pairs_broken) + "," + std::to_string(r.broken_bonds) + "," +
                    number(r.max_damage);
  for (const auto& reaction : r.reactions) row += "," + number(reaction.reaction_x) + "," + number(reaction.reaction_y);
  return row;
}

std::vector<double> displacement_xyz(const std::vector<double>& u) {
  const std::size_t n = u.size() / 2;
  std::vector<double> out(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    out[3 * i] = u[i];
    out[3 * i + 1] = u[n + i];
  }
  return out;
}

std::string snapshot_name(long step) {
  char name[64];
  std::snprintf(name, sizeof name, "%s/step_%08ld.vtp", results::snapshot_folder, step);
  return name;
}

void print_plan(std::ostream& log, const Scene& scene, const ParticleSet& particles, const QuasiStaticProblem& p,
                const std::string& out) {
  const auto& q = scene.quasi_static;
  log << "pd-solve " << version_string << " (quasi-static)\n"
      << "  scene:     " << scene.path << "\n"
      << "  particles: " << scene.particle_file << " (" << particles.size() << " particles, " << p.dynamic_bond_count()
      << " directed bonds; energy table " << p.energy_bonds().size() << " directed bonds, largest stiffness asymmetry "
      << p.stiffness_asymmetry() << ")\n"
      << "  model:     PMB bond-based, c*h = " << p.pmb().micromodulus_area << " N/m^5, s0 = " << p.pmb().critical_stretch
      << ", horizon " << p.pmb().horizon << " m, bond weights "
      << (scene.bond_weights == BondWeights::distance_moment ? "distance_moment" : "partial_volume") << "\n"
      << "  effects:   damage " << (scene.effects.damage ? "on" : "off") << ", surface correction "
      << (scene.effects.surface_correction ? "on" : "off") << ", pre-cracks " << scene.precracks.size() << " ("
      << p.precrack_bonds_cut() << " directed bonds cut)\n"
      << "  loads:    ";
  for (const auto& load : p.loads())
    log << " " << load.spec.name << " (" << to_string(load.spec.kind) << ", " << load.particles.size() << " particles)";
  log << "\n  steps:     " << q.load_factors.size() << " load steps, load factor " << q.load_factors.front() << " -> "
      << q.load_factors.back() << "; NCG tolerance " << q.tolerance << ", at most " << q.max_iterations
      << " iterations per minimisation\n"
      << "  threads:   " << omp_get_max_threads() << "\n"
      << "  output:    " << out << "\n"
      << std::flush;
}

}  // namespace

RunReport run_quasi_static_scene(const Scene& scene, const RunOptions& options, Equilibrium* end_state) {
  std::ostream& log = options.log ? *options.log : std::cout;
  if (options.output_dir.empty()) throw Error("no output directory given");
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto start = std::chrono::steady_clock::now();
  const std::string& out = options.output_dir;
  std::filesystem::create_directories(out);
  const auto path_in_out = [&](const std::string& name) { return (std::filesystem::path(out) / name).string(); };

  const ParticleSet particles = read_particle_file(scene.particle_file);
  const std::string particle_hash = file_hash_hex(scene.particle_file);
  SimulationOptions setup;
  setup.surface_correction_cache = path_in_out(surface_correction_cache_file);
  setup.particle_file_hash = particle_hash;
  QuasiStaticProblem problem(scene, particles, setup);
  print_plan(log, scene, particles, problem, out);

  std::vector<std::uint32_t> stop_region;
  if (scene.stop.enabled) stop_region = resolve_region(scene.stop.region, particles, scene.path, "stop");

  const std::string header = load_steps_header(problem.loads());
  std::vector<std::string> rows;
  std::vector<std::pair<double, std::string>> snapshots;
  const long interval = scene.output.snapshot_interval;
  const auto write_rows = [&] {
    write_atomically(path_in_out(results::load_steps_file), [&](std::ofstream& f) {
      f << header << "\n";
      for (const auto& r : rows) f << r << "\n";
    });
  };
  const auto observer = [&](const QuasiStaticProblem& p, const std::vector<double>& u, const LoadStepRecord& r) {
    rows.push_back(load_steps_row(r));
    write_rows();
    log << "step " << r.step << ": load factor " << r.load_factor << ", " << r.iterations << " iterations in "
        << r.minimisations << " minimisation(s), relative residual " << r.relative_residual << ", energy "
        << r.strain_energy << " J, reaction " << axial_reaction(r, p.loads()) << " N, pairs broken " << r.pairs_broken
        << (r.converged ? "" : " (NOT CONVERGED)") << "\n"
        << std::flush;
    if (interval > 0 && r.step % interval == 0) {
      std::filesystem::create_directories(path_in_out(results::snapshot_folder));
      const std::string name = snapshot_name(r.step);
      const std::size_t n = p.particle_count();
      std::vector<PointArray> arrays(2);
      arrays[0] = {results::displacement, 3};
      arrays[0].float_values = float_vectors(n, [&](std::size_t i) { return std::pair{u[i], u[n + i]}; });
      arrays[1] = {results::damage, 1};
      arrays[1].float_values = float_values_of(p.damage().data(), n);
      write_vtp(path_in_out(name), p.reference_x(), p.reference_y(), arrays,
                {{results::field_load_factor, {r.load_factor}}, {results::field_step, {double(r.step)}}});
      snapshots.emplace_back(r.load_factor, name);
      write_pvd(path_in_out(results::snapshot_collection), snapshots);
    }
  };
  // Checkpoints after load steps; --restart continues after the last one (the
  // scene may only add load steps: the key leaves out the load factors).
  const std::string checkpoint_key = scene.restart_key_text + "\nparticles " + particle_hash;
  LoadStepState resume;
  if (options.restart) {
    QuasiStaticCheckpoint c = read_quasi_static_checkpoint(path_in_out(checkpoint_file), checkpoint_key);
    problem.set_bond_states(c.bond_states);
    rows = std::move(c.load_step_rows);
    snapshots = std::move(c.snapshots);
    resume = std::move(c.state);
    log << "restart after load step " << resume.load_factors_done.size() << "\n" << std::flush;
  }
  // Also after the last step: a finished run can then be extended, or handed
  // over to a dynamic part, without repeating a step.
  const auto checkpoint = [&](const LoadStepState& state) {
    const long interval = scene.output.checkpoint_interval;
    const std::size_t done = state.load_factors_done.size();
    const bool last = !state.stop_reason.empty() || done == scene.quasi_static.load_factors.size();
    if (interval > 0 && (static_cast<long>(done) % interval == 0 || last))
      write_checkpoint(path_in_out(checkpoint_file), checkpoint_key,
                       QuasiStaticCheckpoint{state, problem.bond_states(), rows, snapshots});
  };
  const QuasiStaticResult result = solve_quasi_static(problem, scene, stop_region, log, observer,
                                                      options.restart ? &resume : nullptr, checkpoint,
                                                      options.show_progress ? &std::cerr : nullptr);
  const double final_factor = !result.steps.empty()                ? result.steps.back().load_factor
                              : !resume.load_factors_done.empty() ? resume.load_factors_done.back()
                                                                  : 0.0;

  write_vtp(path_in_out(results::final_state_file), problem.reference_x(), problem.reference_y(),
            {{results::displacement, 3, displacement_xyz(result.u)},
             {results::damage, 1, result.damage},
             {results::damage_load_factor, 1, result.damage_load_factor},
             {results::volume, 1, particles.volume}},
            {{results::field_load_factor, {final_factor}},
             {results::field_spacing, {particles.spacing}},
             {results::field_horizon, {problem.pmb().horizon}}});

  if (end_state) {
    end_state->u = result.u;
    end_state->broken_pairs = problem.broken_pairs();
    end_state->load_factor = final_factor;
  }

  RunReport report;
  report.steps = static_cast<long>(rows.size());  // load steps done, before a restart included
  report.time = final_factor;
  report.stop_reason = result.stop_reason;
  report.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  long iterations = 0;
  for (const auto& r : result.steps) iterations += r.iterations;

  std::ostringstream j;
  j << "{\n  \"tool\": \"pd-solve " << version_string << "\",\n  \"mode\": \"quasi_static\",\n"
    << "  \"particle_file_hash\": \"" << particle_hash << "\",\n"
    << "  \"particles\": " << particles.size() << ",\n  \"directed_bonds\": " << problem.dynamic_bond_count() << ",\n"
    << "  \"energy_table_directed_bonds\": " << problem.energy_bonds().size() << ",\n"
    << "  \"stiffness_asymmetry\": " << number(problem.stiffness_asymmetry()) << ",\n"
    << "  \"load_steps\": " << report.steps << ",\n  \"load_steps_this_run\": " << result.steps.size() << ",\n"
    << "  \"final_load_factor\": " << number(report.time) << ",\n"
    << "  \"ncg_iterations_this_run\": " << iterations << ",\n"
    << "  \"broken_bonds\": " << problem.broken_bond_count() << ",\n"
    << "  \"stop_reason\": \"" << result.stop_reason << "\",\n"
    << "  \"threads\": " << omp_get_max_threads() << ",\n  \"wall_time_s\": " << number(report.wall_seconds) << ",\n"
    << "  \"peak_memory_bytes\": " << peak_memory_bytes() << "\n}\n";
  write_atomically(path_in_out(results::summary_file), [&](std::ofstream& f) { f << j.str(); });
  log << "done: " << report.steps << " load steps (" << result.stop_reason << "), " << iterations
      << " NCG iterations, " << report.wall_seconds << " s wall, peak memory " << peak_memory_bytes() / (1024 * 1024)
      << " MB\n";
  return report;
}

}  // namespace pd::solver
