#pragma once
// The run driver: reads the particle file, builds the simulation, steps it to
// the end time (or the stop condition) and writes the output directory
// (docs/solver.md), with checkpoints and --restart.
#include <functional>
#include <iosfwd>
#include <string>

#include "scene.hpp"

namespace pd::solver {

class Simulation;

struct RunOptions {
  std::string output_dir;     // required
  bool restart = false;       // continue from OUTDIR/checkpoint.bin
  int threads = 0;            // 0 = OpenMP default
  bool show_progress = true;  // progress lines on stderr
  std::ostream* log = nullptr;  // plan and final report; nullptr = std::cout
  // Dynamic runs, not restarted: sets the state at t = 0 before the first
  // output (a quasi-static equilibrium, static_then_dynamic.hpp); with
  // checkpoints on, that state is checkpointed at once. Empty = at rest.
  std::function<void(Simulation&)> initial_state;
};

struct RunReport {
  long steps = 0;              // last step index reached
  double time = 0;             // [s]
  std::string stop_reason;     // "end time", or the stop condition
  double wall_seconds = 0;
  double bond_evaluations_per_second = 0;
};

RunReport run_scene(const Scene& scene, const RunOptions& options);

// Name of the checkpoint file inside OUTDIR.
inline constexpr const char* checkpoint_file = "checkpoint.bin";
// Name of the surface-correction cache inside OUTDIR.
inline constexpr const char* surface_correction_cache_file = "surface_correction.cache";

}  // namespace pd::solver
