#pragma once
// pd-solve on a scene: dynamic, quasi-static, or quasi-static then dynamic
// (docs/solver.md). run_scene only dispatches to the run of the scene's
// kind; each run reads the particle file, builds its problem, steps it and
// writes the output directory, with checkpoints and --restart.
#include <cstddef>
#include <iosfwd>
#include <memory>
#include <string>

#include "scene.hpp"

namespace pd::solver {

struct DeferredCacheWrite;

// Directed bonds per thread below which pd-solve, left to choose, runs on
// fewer threads (RunOptions::threads_by_size; docs/performance.md).
constexpr double threads_by_size_bonds = 4e5;

struct RunOptions {
  std::string output_dir;       // required
  bool restart = false;         // continue from OUTDIR/checkpoint.bin
  int threads = 0;              // 0 = OpenMP default
  // With threads = 0: a plate of few bonds runs on fewer threads than
  // OpenMP's default (one per threads_by_size_bonds directed bonds; pd-solve
  // without --threads or OMP_NUM_THREADS).
  bool threads_by_size = false;
  bool show_progress = true;    // progress lines on stderr
  bool refinement_details = false;  // --verbose: each refinement event's set-up counts and part times
  // The dynamic part of a switching run: OUTDIR/quasi_static holds its own
  // first part. Any other fresh run removes an earlier run's results there.
  bool quasi_static_part_is_own = false;
  // The quasi-static part of a switching run: the dynamic part's
  // surface-correction cache (OUTDIR's), whose factors fit this part's bonds;
  // copied into this part's folder once its checks have passed.
  std::string shared_surface_correction_cache;
  // Its factors as the dynamic part's check computed them, when they would
  // replace other factors there: kept back (read from here instead) and
  // written with this part's own, once this part has passed its checks too.
  std::shared_ptr<DeferredCacheWrite> shared_surface_correction_kept_back;
  // The quasi-static part of a fresh switching run: OUTDIR, whose earlier
  // results (the dynamic part's, and its checkpoint) go with this part's own
  // once this part has passed its checks.
  std::string switching_run_folder;
  std::ostream* log = nullptr;  // plan and final report; nullptr = std::cout
};

struct RunReport {
  long steps = 0;              // last step index reached (load steps for a quasi-static run)
  double time = 0;             // [s] (the last load factor for a quasi-static run)
  std::string stop_reason;     // "end time", "last load step", or the stop condition
  double wall_seconds = 0;
  double bond_evaluations_per_second = 0;  // dynamic runs
};

RunReport run_scene(const Scene& scene, const RunOptions& options);

// Removes the temporary files a killed run left in OUTDIR, its snapshot
// folder, the quasi-static part's folder and snapshot folder, and pd-post's
// folder OUTDIR/post (remove_stale_temporaries); says how many on `log` when there were any.
// run_scene calls it first, for fresh and resumed runs alike.
std::size_t remove_stale_outputs(const std::string& output_dir, std::ostream& log);

// Name of the checkpoint file inside OUTDIR.
inline constexpr const char* checkpoint_file = "checkpoint.bin";
// Name of the surface-correction cache inside OUTDIR.
inline constexpr const char* surface_correction_cache_file = "surface_correction.cache";

}  // namespace pd::solver
