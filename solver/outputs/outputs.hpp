#pragma once
// Files of a solver output directory (names: common/results_format.hpp,
// description: docs/solver.md). Every file is written atomically.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "simulation.hpp"
#include "vtk_output.hpp"

namespace pd::solver {

// The run's identifier as a .vtp's field `run_id` (docs/formats.md, "Run
// identifier"), where the scene has one (a run's: prepare_run).
void add_run_id_field(std::vector<FieldValue>& fields, const Scene& scene);

// A step's snapshot file relative to the output directory: snapshots/step_NNNNNNNN.vtp.
std::string snapshot_name(long step);
// The step of a file name the solver gives its snapshots ("step_NNNNNNNN.vtp",
// without the folder); -1 for any other name (a user's file).
long snapshot_step_of(const std::string& file_name);

// OUTDIR/snapshots/step_NNNNNNNN.vtp; returns its name relative to OUTDIR.
// `with_cell_size`: also the particles' cell sizes, for a run whose particle
// set changes (adaptive refinement), whose snapshots pd-post then draws with
// their own particles rather than the final set's.
std::string write_snapshot(const std::string& output_dir, const Simulation& sim, bool with_cell_size = false);

// OUTDIR/snapshots.pvd listing the snapshots of steps interval, 2 interval, ... <= last_step
// (the list follows from the interval, so a restarted run rebuilds it), with
// the run's identifier `run_id` (write_pvd).
void write_snapshot_collection(const std::string& output_dir, const std::string& run_id, long interval, long last_step,
                               double time_step);
// The same with the time of each step given [s] (a run whose time step
// changed: adaptive refinement); with `with_last_step`, last_step is listed
// also when it is off the interval (the end of a run, which always has a snapshot).
void write_snapshot_collection(const std::string& output_dir, const std::string& run_id, long interval, long last_step,
                               const std::function<double(long)>& time_of_step, bool with_last_step = false);

// A CSV table of the run (energy.csv, load_steps.csv), written whole at
// `path`: the header and the rows, each with the run's identifier `run_id`
// as its last column (docs/formats.md, "Run identifier"; none when it is
// empty). The rows are kept, and checkpointed, without it, so that a
// restarted run, whose rows come from its checkpoint, has it once on each.
void write_run_table(const std::string& path, const std::string& header, const std::vector<std::string>& rows,
                     const std::string& run_id);

// The rows of energy.csv, kept in memory (and in checkpoints) and written whole.
class EnergyLog {
public:
  explicit EnergyLog(const Simulation& sim);
  // `energies`: sim.energies(), when the caller has them already.
  void record(const Simulation& sim, const EnergyTotals& energies);
  void record(const Simulation& sim) { record(sim, sim.energies()); }
  void write(const std::string& output_dir) const;
  const std::vector<std::string>& rows() const { return rows_; }
  void set_rows(std::vector<std::string> rows) { rows_ = std::move(rows); }
  std::string header() const { return header_; }

private:
  std::string header_;
  std::string run_id_;  // the scene's: its last column (write_run_table)
  std::vector<std::string> rows_;
};

// OUTDIR/arrival.vtp: reference positions, final state, arrival times, material.
void write_arrival(const std::string& output_dir, const Simulation& sim);

}  // namespace pd::solver
