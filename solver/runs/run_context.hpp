#pragma once
// What every run does before it builds its problem, in one place: the
// output folder, the threads, the particle file (read once, its families
// collected compact while it streams by; on several processes, where the
// scene allows, only this process's slab's band of it), its hash, the stop
// region and the checkpoint key. The problem (Simulation,
// QuasiStaticProblem) then takes the particles and families over.
#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bond_setup.hpp"
#include "compact_families.hpp"
#include "output_folder_lock.hpp"
#include "particle_file.hpp"
#include "run.hpp"
#include "scene.hpp"
#include "slab_band.hpp"

namespace pd::solver {

struct RunContext {
  Scene scene;
  RunOptions options;
  std::chrono::steady_clock::time_point start;
  int threads = 1;                // OpenMP threads per process
  bool threads_by_size = false;   // fewer than OpenMP's default for a small plate (threads_for_size)
  int processes = 1;              // MPI processes (docs/solver.md, "Running on several processes")
  std::string particle_hash;      // of the particle file (cache and checkpoint keys)
  std::string checkpoint_key;     // scene (without what a restart may extend) + particle hash
  ParticleSet particles;          // without families; moved into the problem
  Families families;              // moved into the problem
  std::size_t particle_count = 0;  // of the whole plate
  std::size_t particles_read = 0;  // kept by this process's read (its band's, or the whole plate's)
  double spacing = 0;             // lattice spacing of the particle file [m]
  std::vector<std::uint32_t> stop_region;  // particles of [stop] (empty without; global ids)
  // Several processes (docs/solver.md, "Set-up"): the set-up made on this
  // process's slab's band (`particles` and `families` are the band's), or on
  // the whole plate, and why.
  bool band_setup = false;
  std::string whole_plate_reason;   // empty with a band set-up or on one process
  std::optional<Partition> band_partition;  // band set-up: this process's slab
  WholePlateFacts whole_plate;              // band set-up: what the run needs of the whole plate

  // The surface-correction factors the set-up kept back from the folder's
  // cache (shared by the copies of this context).
  std::shared_ptr<DeferredCacheWrite> deferred_cache = std::make_shared<DeferredCacheWrite>();

  std::ostream& log() const;
  const std::string& output_dir() const { return options.output_dir; }
  std::string path(const std::string& name) const;  // a file inside the output folder
  SetupOptions setup_options() const;               // the surface-correction cache in the output folder
  double elapsed_seconds() const;
  // A fresh run (not --restart), once its set-up has passed every check and
  // before it writes its first file: removes the results an earlier run left
  // in its folder (remove_earlier_results) on the root process, and says so.
  // A run refused at set-up leaves the earlier results whole.
  void clear_earlier_results() const;
  // Every check of the run has passed: writes the factors its set-up kept
  // back from the folder's surface-correction cache (a refused run leaves an
  // earlier run's cache, which its --restart reads, as it was, and none where
  // there was none).
  void write_deferred_cache() const;
};

// pd::Error naming the file or option on any problem.
RunContext prepare_run(const Scene& scene, const RunOptions& options);

// What prepare_run refuses before it makes the output folder: a missing
// particle file, an output folder that is a file. pd::Error naming them.
void check_run_paths(const Scene& scene, const RunOptions& options);

// Something other than a file where the run in `output_dir` writes a
// result (a folder named energy.csv), or a file where it makes snapshots/,
// refused naming it and what to do: at the start, and by the root before it
// writes a result during the run (a place taken since). `with_cache`: also
// the surface-correction cache, which one process writes at the start.
// Its refusal ends in `taken_place_advice` (what to do at the start; a run
// stopped by a place taken during it says instead how to go on).
inline constexpr const char* taken_place_advice = "move it, or give -o a new or empty folder";
void check_result_paths(const Scene& scene, const std::string& output_dir, bool with_cache);

// The output folder, made where missing, locked for this run
// (OutputFolderLock): pd::Error when another run holds it. A restart into a
// folder that does not exist gets no lock and no folder (its run refuses it).
OutputFolderLock lock_output_folder(const RunOptions& options);

// Removes what an earlier run wrote into OUTDIR (summary.json, energy.csv,
// arrival.vtp, load_steps.csv, final_state.vtp, snapshots.pvd, the
// snapshots' step_NNNNNNNN.vtp and checkpoint.bin) and pd-post's outputs
// (remove_post_outputs), keeping the caches, other subfolders and anything
// else; returns how many files it removed.
std::size_t remove_earlier_results(const std::string& output_dir);
// pd::Error where a fresh run with `options` would refuse to clear its
// folders (a file of a result's name that pd-solve did not write in OUTDIR,
// or in an earlier switching run's OUTDIR/quasi_static unless the run's own
// quasi-static part writes there); removes nothing.
void check_earlier_results_removable(const RunOptions& options);
// Whether OUTDIR, or its switching run's OUTDIR/quasi_static, holds a file
// a run writes as its result (those remove_earlier_results would remove; the
// caches and the lock are none).
bool holds_results(const std::string& output_dir);
// Where OUTDIR/post holds pd-post's summary.json: the files of pd-post's names
// there (results::is_post_output), which show earlier results; a user's other
// files stay. Returns how many it removed.
std::size_t remove_post_outputs(const std::string& output_dir);

}  // namespace pd::solver
