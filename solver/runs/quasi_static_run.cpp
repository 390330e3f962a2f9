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
#include "outputs.hpp"
#include "quasi_static_problem.hpp"
#include "run_report.hpp"
#include "results_format.hpp"
#include "units.hpp"
#include "vtk_output.hpp"

namespace pd::solver {
namespace {

std::string number(double v) {
  std::ostringstream out;
  out << std::setprecision(12) << v;
  return out.str();
}

// The loads whose prescribed displacement goes into load_steps.csv.
bool prescribes_displacement(const ResolvedLoad& load) {
  return load.spec.kind == LoadKind::displacement || load.spec.kind == LoadKind::fixed;
}

std::string load_steps_header(const std::vector<ResolvedLoad>& loads) {
  std::string h =
      "step,load_factor,minimisations,iterations,relative_residual,converged,strain_energy_J,potential_energy_J,"
      "pairs_broken,broken_bonds,max_damage";
  for (const auto& load : loads) h += "," + load.spec.name + "_reaction_x_N," + load.spec.name + "_reaction_y_N";
  for (const auto& load : loads)
    if (prescribes_displacement(load))
      h += "," + load.spec.name + "_displacement_x_m," + load.spec.name + "_displacement_y_m";
  return h;
}

std::string load_steps_row(const LoadStepRecord& r, const std::vector<ResolvedLoad>& loads) {
  std::string row = std::to_string(r.step) + "," + number(r.load_factor) + "," + std::to_string(r.minimisations) +
                    "," + std::to_string(r.iterations) + "," + number(r.relative_residual) + "," +
                    (r.converged ? "1" : "0") + "," + number(r.strain_energy) + "," + number(r.potential_energy) +
                    "," + std::to_string(r.pairs_broken) + "," + std::to_string(r.broken_bonds) + "," +
                    number(r.max_damage);
  for (const auto& reaction : r.reactions) row += "," + number(reaction.reaction_x) + "," + number(reaction.reaction_y);
  // The displacement the load prescribes at this load factor (a component it
  // leaves free: empty); one that varies over the set, its mean over the set's particles.
  const auto prescribed = [](bool uniform, double value, const std::vector<double>& values) {
    if (uniform || values.empty()) return value;
    double sum = 0;
    for (double v : values) sum += v;
    return sum / static_cast<double>(values.size());
  };
  for (const auto& load : loads) {
    if (!prescribes_displacement(load)) continue;
    const double scale = load.spec.kind == LoadKind::fixed ? 0.0 : r.load_factor;
    const double x = prescribed(load.spec.x_variation.is_uniform(), load.spec.x, load.value_x);
    const double y = prescribed(load.spec.y_variation.is_uniform(), load.spec.y, load.value_y);
    row += "," + (load.spec.has_x ? number(x * scale) : std::string()) + "," +
           (load.spec.has_y ? number(y * scale) : std::string());
  }
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

// The field data every quasi-static file carries: the grid and the model.
std::vector<FieldValue> grid_fields(const QuasiStaticProblem& p) {
  return {{results::field_spacing, {p.state().reference.spacing}},
          {results::field_horizon, {p.model().horizon}},
          {results::field_plane_strain, {p.scene().material.plane == PlaneKind::strain ? 1.0 : 0.0}}};
}

void print_plan(const RunContext& run, const QuasiStaticProblem& p) {
  const auto& q = run.scene.quasi_static;
  std::ostream& log = run.log();
  std::ostringstream extra;
  if (p.lattice_kernels() && p.lattice_kernel()->empty())
    extra << "; the dynamic solver's lattice kernel, no lattice squares: its general particles' lists (double)";
  else if (p.lattice_kernels())
    extra << "; the dynamic solver's lattice kernel (float, then double near convergence)";
  else
    extra << "; energy table " << p.energy_bonds().size() << " directed bonds, largest stiffness asymmetry "
          << p.stiffness_asymmetry();
  print_plan_header(log, run, {p.model(), p.setup_facts(), p.loads()}, "quasi-static", extra.str());
  log << "  steps:     " << q.load_factors.size() << " load steps, load factor " << q.load_factors.front() << " -> "
      << q.load_factors.back() << "; NCG tolerance " << q.tolerance << ", at most " << q.max_iterations
      << " iterations per minimisation\n";
  print_plan_footer(log, run, "");
}

}  // namespace

RunReport run_quasi_static(RunContext run, Equilibrium* end_state) {
  const Scene& scene = run.scene;
  std::ostream& log = run.log();
  const auto path_in_out = [&](const std::string& name) { return run.path(name); };
  QuasiStaticProblem problem(scene, std::move(run.particles), std::move(run.families), run.setup_options());
  run.clear_earlier_results();
  print_plan(run, problem);
  require_plan_written(run.log());
  const std::vector<std::uint32_t>& stop_region = run.stop_region;

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
    rows.push_back(load_steps_row(r, p.loads()));
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
      std::vector<PointArray> arrays(4);
      arrays[0] = {results::displacement, 3};
      arrays[0].float_values = float_vectors(n, [&](std::size_t i) { return std::pair{u[i], u[n + i]}; });
      arrays[1] = {results::damage, 1};
      arrays[1].float_values = float_values_of(p.damage().data(), n);
      arrays[2] = {results::strain_energy_density, 1};
      arrays[2].float_values = float_values_of(p.strain_energy_density(u).data(), n);
      arrays[3] = {results::cell_size, 1};
      arrays[3].float_values = float_values_of(p.state().reference.cell_size.data(), n);
      auto fields = grid_fields(p);
      fields.push_back({results::field_load_factor, {r.load_factor}});
      fields.push_back({results::field_step, {double(r.step)}});
      write_vtp(path_in_out(name), p.reference_x(), p.reference_y(), arrays, fields);
      snapshots.emplace_back(r.load_factor, name);
      write_pvd(path_in_out(results::snapshot_collection), snapshots);
    }
  };
  // Checkpoints after load steps; --restart continues after the last one (the
  // scene may only add load steps: the key leaves out the load factors).
  const std::string& checkpoint_key = run.checkpoint_key;
  LoadStepState resume;
  if (run.options.restart) {
    QuasiStaticCheckpoint c = read_quasi_static_checkpoint(path_in_out(checkpoint_file), checkpoint_key);
    problem.set_bond_states(c.bond_states);
    rows = std::move(c.load_step_rows);
    snapshots = std::move(c.snapshots);
    resume = std::move(c.state);
    // A restart continues a run with more load steps (a switching scene also
    // with its dynamic part): one with none left would do nothing and rewrite
    // the results as those of a finished run.
    // (`end_state`: the quasi-static part of a switching scene, which goes on.)
    check_resumable(scene, problem.particle_count(), resume);
    const std::size_t done = resume.load_factors_done.size();
    const std::size_t steps = scene.quasi_static.load_factors.size();
    if (!end_state && !resume.stop_reason.empty())
      throw Error(path_in_out(checkpoint_file) + ": the run stopped after load step " + std::to_string(done) + " (" +
                  resume.stop_reason + "): a restart would stop again at once (run again without --restart)");
    if (!end_state && done == steps)
      throw Error(scene.path + ": the scene's " + std::to_string(steps) + " load steps are all done in " +
                  path_in_out(checkpoint_file) + " (" + std::to_string(done) +
                  " done): a restart continues a run with more load steps; add some (quasi_static.load_factors or "
                  "increments), or run without --restart to start over");
    // The folder must hold the snapshots the checkpoint's run wrote, which
    // snapshots.pvd will list (as a dynamic restart checks its own).
    for (const auto& [load_factor, name] : snapshots) {
      std::error_code error;
      if (!std::filesystem::is_regular_file(path_in_out(name), error))
        throw Error(path_in_out(name) + ": missing, though the run of " + path_in_out(checkpoint_file) +
                    " wrote it (its snapshot at load factor " + shortest_text(load_factor) +
                    "): the folder does not hold that run's snapshots, and snapshots.pvd would list an absent "
                    "file; run without --restart to start over");
    }
    log << "restart after load step " << done << "\n" << std::flush;
    // Until this run ends, the folder holds an unfinished run (no summary.json).
    std::error_code ignored;
    std::filesystem::remove(path_in_out(results::summary_file), ignored);
    remove_post_outputs(run.output_dir());  // pd-post's pictures of the steps so far
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
                                                      run.options.restart ? &resume : nullptr, checkpoint,
                                                      run.options.show_progress ? &std::cerr : nullptr,
                                                      warning_echo(run));
  const double final_factor = !result.steps.empty()                ? result.steps.back().load_factor
                              : !resume.load_factors_done.empty() ? resume.load_factors_done.back()
                                                                  : 0.0;

  auto final_fields = grid_fields(problem);
  final_fields.push_back({results::field_load_factor, {final_factor}});
  write_vtp(path_in_out(results::final_state_file), problem.reference_x(), problem.reference_y(),
            {{results::displacement, 3, displacement_xyz(result.u)},
             {results::damage, 1, result.damage},
             {results::damage_load_factor, 1, result.damage_load_factor},
             {results::strain_energy_density, 1, problem.strain_energy_density(result.u)},
             {results::volume, 1, problem.area()},
             {results::cell_size, 1, {}, problem.state().reference.cell_size.data()}},
            final_fields);

  if (end_state) {
    end_state->u = result.u;
    end_state->broken_pairs = problem.broken_pairs();
    end_state->load_factor = final_factor;
  }

  RunReport report;
  report.steps = static_cast<long>(rows.size());  // load steps done, before a restart included
  report.time = final_factor;
  report.stop_reason = result.stop_reason;
  report.wall_seconds = run.elapsed_seconds();
  long iterations = 0;
  for (const auto& r : result.steps) iterations += r.iterations;

  JsonObject j = summary_fields(run, {problem.model(), problem.setup_facts(), problem.loads(), 0, result.warnings},
                                "quasi_static", result.stop_reason, report.wall_seconds);
  j.integer("energy_table_directed_bonds", static_cast<std::int64_t>(problem.energy_bonds().size()))
      .number("stiffness_asymmetry", problem.stiffness_asymmetry())
      .integer("load_steps", report.steps)
      .integer("load_steps_this_run", static_cast<std::int64_t>(result.steps.size()))
      .number("final_load_factor", report.time)
      .integer("ncg_iterations_this_run", iterations)
      .integer("broken_bonds", static_cast<std::int64_t>(problem.broken_bond_count()));
  write_summary(run, j, problem.dynamic_bond_count());
  log << "done: " << report.steps << (report.steps == 1 ? " load step (" : " load steps (") << result.stop_reason
      << "), " << iterations
      << " NCG iterations, " << report.wall_seconds << " s wall, peak memory "
      << peak_memory_text(problem.dynamic_bond_count()) << "\n";
  return report;
}

}  // namespace pd::solver
