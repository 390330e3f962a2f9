#include "quasi_static_run.hpp"

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "atomic_file.hpp"
#include "checkpoint.hpp"
#include "error.hpp"
#include "interrupt.hpp"
#include "pd/version.hpp"
#include "peak_memory.hpp"
#include "load_steps.hpp"
#include "outputs.hpp"
#include "plan_limits.hpp"
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

// The load factor as written, in the shortest text that reads back to it (12
// digits printed two factors 1e-13 apart the same; the progress lines and
// messages had 6: 0.1234567 as 0.123457, before 7 December 2026).
std::string load_steps_row(const LoadStepRecord& r, const std::vector<ResolvedLoad>& loads) {
  std::string row = std::to_string(r.step) + "," + shortest_text(r.load_factor) + "," +
                    std::to_string(r.minimisations) + "," + std::to_string(r.iterations) + "," + number(r.relative_residual) + "," +
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
  std::vector<FieldValue> fields{{results::field_spacing, {p.state().reference.spacing}},
                                 {results::field_horizon, {p.model().horizon}},
                                 {results::field_plane_strain, {p.scene().material.plane == PlaneKind::strain ? 1.0 : 0.0}}};
  add_run_id_field(fields, p.scene());
  return fields;
}

// One residual at the start state, timed: the cost of a bond sweep on this
// machine, for the plan's estimate (only an estimate; as a dynamic run's
// force evaluation at set-up).
double bond_sweep_seconds(QuasiStaticProblem& problem) {
  std::vector<double> u(2 * problem.particle_count(), 0.0), r;
  const auto start = std::chrono::steady_clock::now();
  problem.residual(u, r);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The snapshots the load steps after `done` write (one every
// output.snapshot_interval load steps, numbered from 1), with the
// checkpoint: u, the predictor's increment and the damage load factors (5
// doubles per particle), the bond states and the rows of load_steps.csv
// (each about as long as its header).
SnapshotVolume load_step_snapshots(const RunContext& run, const QuasiStaticProblem& p, std::size_t done) {
  const OutputSpec& o = run.scene.output;
  const long interval = o.snapshot_interval;
  const std::size_t steps = run.scene.quasi_static.load_factors.size();
  SnapshotVolume volume;
  volume.snapshots = std::floor(static_cast<double>(steps) / interval) - std::floor(static_cast<double>(done) / interval);
  volume.particles = static_cast<double>(p.particle_count());
  if (o.checkpoint_interval > 0)
    volume.checkpoint_bytes = 5 * 8 * volume.particles + static_cast<double>(p.bond_states().size()) +
                              static_cast<double>(steps) * static_cast<double>(load_steps_header(p.loads()).size());
  volume.span = "from load step " + std::to_string(done + 1) + " to " + std::to_string(steps);
  volume.advice = "give fewer load steps";
  return volume;
}

// `least_seconds`: the load steps' cost at the least (load_step_length).
void print_plan(const RunContext& run, const QuasiStaticProblem& p, const std::vector<std::string>& run_warnings,
                double least_seconds, std::size_t done) {
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
  print_plan_header(log, run, {p.model(), p.setup_facts(), p.loads(), 0, run_warnings}, "quasi-static", extra.str());
  log << "  steps:     " << q.load_factors.size() << (q.load_factors.size() == 1 ? " load step" : " load steps")
      << ", load factor " << shortest_text(q.load_factors.front()) << " -> "
      << shortest_text(q.load_factors.back()) << ", at least about " << duration_text(least_seconds)
      << (done > 0 ? " for the " + std::to_string(q.load_factors.size() - done) + " left" : std::string())
      << " at the set-up's bond sweep (" << least_sweeps_per_load_step
      << " per load step, 2 more per NCG iteration); NCG tolerance " << q.tolerance << ", at most "
      << q.max_iterations << " iterations per minimisation\n";
  print_plan_footer(log, run, "");
}

}  // namespace

RunLength load_step_length(const Scene& scene, double bond_count, std::size_t done, double sweep_seconds) {
  const std::size_t steps = scene.quasi_static.load_factors.size();
  RunLength length;
  length.steps = static_cast<double>(steps - done);
  length.seconds = length.steps * least_sweeps_per_load_step * sweep_seconds;
  length.bond_evaluations = length.steps * least_sweeps_per_load_step * bond_count;
  std::ostringstream m;
  m << "quasi_static.load_factors / increments: " << steps << " load steps";
  if (done > 0) m << ", " << steps - done << " of them after the checkpoint's " << done;
  m << "; at the " << sweep_seconds << " s per bond sweep measured at set-up and at least "
    << least_sweeps_per_load_step << " sweeps per load step (2 more per NCG iteration) that is at least about "
    << length.seconds / 86400.0 << " days";
  length.description = m.str();
  length.advice = "give fewer load steps: quasi_static.load_factors or increments";
  return length;
}

RunReport run_quasi_static(RunContext run, Equilibrium* end_state) {
  const Scene& scene = run.scene;
  std::ostream& log = run.log();
  const auto path_in_out = [&](const std::string& name) { return run.path(name); };
  QuasiStaticProblem problem(scene, std::move(run.particles), std::move(run.families), run.setup_options());
  const std::vector<std::uint32_t>& stop_region = run.stop_region;
  std::vector<std::string> rows;
  std::vector<std::pair<double, std::string>> snapshots;
  // Checkpoints after load steps; --restart continues after the last one (the
  // scene may only add load steps: the key leaves out the load factors). Its
  // checks come before the plan's, and both before the folder changes.
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
  }
  // A stop condition that the pre-cracks already meet would end the run after
  // its first load step, as if the crack had reached the region (before 7
  // December 2026, exit 0); refused as a dynamic run refuses it.
  if (!run.options.restart && scene.stop.enabled) {
    const RegionPeak start =
        most_damaged(stop_region, problem.damage(), problem.reference_x(), problem.reference_y());
    if (start.damage >= scene.stop.damage)
      throw Error(stop_holds_at_start(scene, start.damage, "load step", "the pre-cracks"));
  }
  // What the plan asks of the machine (plan_limits.hpp), as a dynamic run's.
  const std::size_t done_before = resume.load_factors_done.size();
  const RunLength length =
      load_step_length(scene, static_cast<double>(problem.dynamic_bond_count()), done_before, bond_sweep_seconds(problem));
  std::vector<std::string> plan_warnings;
  for (const std::string& w :
       {check_run_length(length, scene.path),
        scene.output.snapshot_interval > 0 ? check_snapshot_volume(run, load_step_snapshots(run, problem, done_before))
                                           : std::string()})
    if (!w.empty()) plan_warnings.push_back(w);
  run.clear_earlier_results();
  run.write_deferred_cache();
  print_plan(run, problem, plan_warnings, length.seconds, done_before);
  require_plan_written(run.log());
  if (run.options.restart) {
    log << "restart after load step " << done_before << "\n" << std::flush;
    // Until this run ends, the folder holds an unfinished run (no summary.json).
    std::error_code ignored;
    std::filesystem::remove(path_in_out(results::summary_file), ignored);
    remove_post_outputs(run.output_dir());  // pd-post's pictures of the steps so far
  }

  const std::string header = load_steps_header(problem.loads());
  const long interval = scene.output.snapshot_interval;
  // load_steps.csv is rewritten whole, atomically and synced to the disk:
  // after every load step that cost more than the step on a small plate
  // (8,000 steps of 50 particles: 66 s, 10 s of it CPU), and the rows grow.
  // So between snapshots it is rewritten once a second at most, and always
  // at a snapshot, a checkpoint, the end and an interruption.
  using Clock = std::chrono::steady_clock;
  std::size_t rows_written = 0;
  Clock::time_point rows_written_at{};
  const auto write_rows = [&] {
    write_run_table(path_in_out(results::load_steps_file), header, rows, scene.run_id);
    rows_written = rows.size();
    rows_written_at = Clock::now();
  };
  const auto observer = [&](const QuasiStaticProblem& p, const std::vector<double>& u, const LoadStepRecord& r) {
    rows.push_back(load_steps_row(r, p.loads()));
    const bool snapshot_step = interval > 0 && r.step % interval == 0;
    if (snapshot_step || Clock::now() - rows_written_at >= std::chrono::seconds(1)) write_rows();
    log << "step " << r.step << ": load factor " << shortest_text(r.load_factor) << ", " << r.iterations
        << " iterations in " << r.minimisations << " minimisation(s), relative residual " << r.relative_residual
        << ", energy " << r.strain_energy << " J, reaction " << axial_reaction(r, p.loads()) << " N, pairs broken "
        << r.pairs_broken
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
      write_pvd(path_in_out(results::snapshot_collection), snapshots, scene.run_id);
    }
  };
  // Also after the last step: a finished run can then be extended, or handed
  // over to a dynamic part, without repeating a step.
  long checkpointed = -1;  // the load steps done at the checkpoint written last (-1: none yet)
  const auto save_checkpoint = [&](const LoadStepState& state, const std::vector<std::uint8_t>& bond_states) {
    write_checkpoint(path_in_out(checkpoint_file), checkpoint_key,
                     QuasiStaticCheckpoint{state, bond_states, rows, snapshots});
    if (rows_written != rows.size()) write_rows();
    checkpointed = static_cast<long>(state.load_factors_done.size());
  };
  // A switching scene's last load step, kept for a Ctrl-C during the part's
  // end files (the dynamic part is still to come).
  std::optional<InterruptedLoadSteps> last_step;
  const auto checkpoint = [&](const LoadStepState& state) {
    const long interval = scene.output.checkpoint_interval;
    const std::size_t done = state.load_factors_done.size();
    const bool last = !state.stop_reason.empty() || done == scene.quasi_static.load_factors.size();
    if (interval > 0 && (static_cast<long>(done) % interval == 0 || last)) save_checkpoint(state, problem.bond_states());
    if (end_state && last) last_step = InterruptedLoadSteps{static_cast<long>(done), false, state, problem.bond_states()};
  };
  // Interrupted: the last completed step's checkpoint (also with
  // checkpoint_interval = 0) and load_steps.csv let --restart go on as if
  // never stopped; no summary.json (not a finished run) but in a switching
  // scene's part that had done its steps.
  const std::size_t steps = scene.quasi_static.load_factors.size();
  const auto stop_interrupted = [&](const InterruptedLoadSteps& stop) {
    const std::size_t done = stop.state.load_factors_done.size();
    if (checkpointed != static_cast<long>(done)) save_checkpoint(stop.state, stop.bond_states);
    if (rows_written != rows.size()) write_rows();
    std::ostringstream m;
    m << "interrupted by " << interrupt_name(interrupt_signal()) << (stop.abandoned ? " in" : " after")
      << " load step " << stop.step << " of " << steps << " (load factor "
      << shortest_text(scene.quasi_static.load_factors[stop.step - 1]) << ")"
      << (stop.abandoned ? ", which was abandoned (a restart does it again)" : "") << ": "
      << path_in_out(checkpoint_file) << " holds "
      << (done == 0 ? std::string("the start (no load step done)")
                    : stop.abandoned ? "load step " + std::to_string(done) : std::string("that step"))
      << ", " << results::load_steps_file << " the rows of the steps done; the same command with --restart continues "
      << "the run";
    throw Error(m.str());
  };
  // Ctrl-C or SIGTERM stops the load steps at the next safe point: after the
  // step, or within it (its minimisation abandoned); a second one ends the
  // process. To the end of the run: one during its end files lets it finish.
  const CatchInterrupts interrupts;
  // A run that fails on the way keeps the rows of its steps for diagnosis.
  const QuasiStaticResult result = [&] {
    try {
      return solve_quasi_static(problem, scene, stop_region, log, observer, run.options.restart ? &resume : nullptr,
                                checkpoint, run.options.show_progress ? &std::cerr : nullptr, warning_echo(run),
                                [] { return interrupt_signal() != 0; });
    } catch (...) {
      // (Its header at least: a first load step that fails leaves a
      // quasi-static folder that pd-post recognises, not an empty one.)
      if (rows_written != rows.size() || rows.empty()) write_rows();
      throw;
    }
  }();
  // With steps left (a switching scene: its dynamic part).
  if (result.interrupted && (result.interrupted->abandoned || end_state || result.stop_reason == "interrupted"))
    stop_interrupted(*result.interrupted);
  if (rows_written != rows.size()) write_rows();
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

  std::vector<std::string> warnings = plan_warnings;
  warnings.insert(warnings.end(), result.warnings.begin(), result.warnings.end());
  JsonObject j = summary_fields(run, {problem.model(), problem.setup_facts(), problem.loads(), 0, warnings},
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
  // A switching scene interrupted during these end files stops before its dynamic part.
  if (end_state && interrupt_signal() != 0 && last_step) stop_interrupted(*last_step);
  return report;
}

}  // namespace pd::solver
