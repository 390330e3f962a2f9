#include "run_context.hpp"

#include <omp.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <filesystem>
#include <iostream>
#include <vector>

#include "atomic_file.hpp"
#include "checkpoint.hpp"
#include "error.hpp"
#include "loads.hpp"
#include "material_scales.hpp"
#include "outputs.hpp"
#include "processes.hpp"
#include "results_format.hpp"

namespace pd::solver {

std::ostream& RunContext::log() const { return options.log ? *options.log : std::cout; }

std::string RunContext::path(const std::string& name) const {
  return (std::filesystem::path(options.output_dir) / name).string();
}

SetupOptions RunContext::setup_options() const {
  SetupOptions setup;
  // Several processes each make the same set-up; none of them writes the cache.
  if (processes == 1) {
    setup.surface_correction_cache = path(surface_correction_cache_file);
    setup.shared_surface_correction_cache = options.shared_surface_correction_cache;
    setup.shared_surface_correction_kept_back = options.shared_surface_correction_kept_back.get();
  }
  setup.particle_file_hash = particle_hash;
  setup.deferred_cache = deferred_cache.get();
  return setup;
}

double RunContext::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {

// Removes the files that exist of `files`; pd::Error naming one that cannot go.
std::size_t remove_files(const std::vector<std::filesystem::path>& files, const std::string& what) {
  std::size_t removed = 0;
  for (const auto& file : files) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) continue;
    if (!std::filesystem::remove(file, error) || error)
      throw Error(file.string() + ": cannot remove this " + what + (error ? ": " + error.message() : std::string()));
    ++removed;
  }
  return removed;
}

// Whether `file` begins as the file of its name that pd-solve writes (a
// summary.json by pd-solve, energy.csv's and load_steps.csv's headers, a
// checkpoint's magic, VTK's XML for .vtp and .pvd): a fresh run removes only
// such files, and refuses a folder where a file of a result's name is
// something else (a user's own energy.csv or summary.json under -o .).
bool begins_as_solver_result(const std::filesystem::path& file) {
  const std::string text = results::file_head(file);
  const std::string name = file.filename().string();
  const auto begins = [&](const char* prefix) { return text.rfind(prefix, 0) == 0; };
  if (name == results::summary_file) return results::summary_by_solver(file);
  if (name == results::energy_file) return begins("time_s,step,");
  if (name == results::load_steps_file) return begins("step,load_factor");
  if (name == checkpoint_file) return begins("PDCHK") || begins("PDQSC");
  return begins("<?xml") || begins("<VTKFile");  // arrival.vtp, final_state.vtp, snapshots.pvd, step_N.vtp
}

}  // namespace

namespace {

// The paths in OUTDIR where a run writes its results (existing or not): the
// files of their names and the snapshots' step_NNNNNNNN.vtp.
std::vector<std::filesystem::path> result_paths(const std::string& output_dir) {
  namespace fs = std::filesystem;
  const fs::path out(output_dir);
  std::vector<fs::path> files;
  // The checkpoint too: a later --restart would take it for the new run's
  // and continue the earlier run over the new run's snapshots.
  for (const char* name : {results::summary_file, results::energy_file, results::arrival_file,
                           results::snapshot_collection, results::load_steps_file, results::final_state_file,
                           checkpoint_file})
    files.push_back(out / name);
  std::error_code error;
  const fs::path snapshots = out / results::snapshot_folder;
  if (fs::is_directory(snapshots, error))
    for (const auto& entry : fs::directory_iterator(snapshots)) {
      // The solver's own names only, "step_NNNNNNNN.vtp": nothing else a user put there.
      if (snapshot_step_of(entry.path().filename().string()) >= 0) files.push_back(entry.path());
    }
  return files;
}

// The files of an earlier run in FOLDER that a fresh run into RUN_FOLDER
// removes; pd::Error (before any is removed) where a file of a result's name
// is not one.
std::vector<std::filesystem::path> earlier_result_files(const std::string& folder, const std::string& run_folder) {
  namespace fs = std::filesystem;
  const std::vector<fs::path> files = result_paths(folder);
  std::error_code error;
  // All or nothing: a file that is not an earlier run's stops the run before any goes.
  for (const auto& file : files)
    if (fs::is_regular_file(file, error) && !begins_as_solver_result(file))
      throw Error(file.string() + ": a file of a result's name that pd-solve did not write (it does not begin as its " +
                  file.filename().string() + " does); a fresh run into " + run_folder + " would replace it" +
                  (folder == run_folder ? std::string()
                                        : " (it removes an earlier switching run's quasi-static part in " + folder +
                                              ")") +
                  ": give -o a new or empty folder, or move the file");
  return files;
}

// The folders a fresh run clears: OUTDIR, and OUTDIR/quasi_static where an
// earlier switching run left its quasi-static part there (pd-post reads that
// folder as a run of its own) unless it is this run's own.
std::vector<std::string> folders_a_fresh_run_clears(const RunOptions& options) {
  std::vector<std::string> folders{options.output_dir};
  const auto part = std::filesystem::path(options.output_dir) / results::quasi_static_part_folder;
  std::error_code error;
  if (!options.quasi_static_part_is_own && std::filesystem::is_directory(part, error))
    folders.push_back(part.string());
  return folders;
}

}  // namespace

void check_earlier_results_removable(const RunOptions& options) {
  // Every folder before any removal: a refusal leaves all earlier results
  // (before 7 December 2026 OUTDIR was cleared before OUTDIR/quasi_static was refused).
  for (const auto& folder : folders_a_fresh_run_clears(options)) earlier_result_files(folder, options.output_dir);
}

bool holds_results(const std::string& output_dir) {
  namespace fs = std::filesystem;
  std::error_code error;
  const auto any_in = [&](const fs::path& folder) {
    for (const auto& file : result_paths(folder.string()))
      if (fs::is_regular_file(file, error)) return true;
    return false;
  };
  return any_in(output_dir) || any_in(fs::path(output_dir) / results::quasi_static_part_folder);
}

std::size_t remove_earlier_results(const std::string& output_dir) {
  return remove_files(earlier_result_files(output_dir, output_dir), "result of an earlier run") +
         remove_post_outputs(output_dir);
}

std::size_t remove_post_outputs(const std::string& output_dir) {
  // pd-post's pictures and tables of the earlier results in OUTDIR/post,
  // which would otherwise sit beside the new ones looking like them.
  // (Only beside pd-post's own summary.json: a folder "post" of the user's keeps its files.)
  return remove_files(results::post_outputs_in(std::filesystem::path(output_dir) / results::post_folder),
                      "pd-post output of earlier results");
}

namespace {

// The output folder, made if missing, and a file written and removed in it:
// a folder the run cannot write in is refused at the start, not at its
// first snapshot after the whole set-up.
void make_writable_folder(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::create_directories(folder, error);
  // The folder or one of its parents a link that leads nowhere (before 7
  // December 2026 "cannot make the output folder: File exists").
  std::error_code ignored;
  for (fs::path f = folder; error && !f.empty(); f = f.parent_path()) {
    if (fs::is_symlink(f, ignored) && !fs::exists(f, ignored))
      throw Error("-o " + clipped(folder) + ": " + clipped(f.string()) + " is a link to " +
                  clipped(fs::read_symlink(f, ignored).string()) + ", which does not exist: cannot make the output "
                  "folder there; make the folder it leads to, or give -o another folder");
    if (f == f.parent_path()) break;  // (the root)
  }
  if (error || !fs::is_directory(folder, error))
    throw Error("-o " + clipped(folder) + ": cannot make the output folder" +
                (error ? ": " + error.message() : std::string(" (a file has that name)")));
  const std::string why = why_cannot_write_in(folder);
  if (!why.empty()) throw Error("-o " + clipped(folder) + ": cannot write in the output folder: " + why);
}

// Why a restart finds no checkpoint, and what to do. With checkpoints on,
// the run in the folder was killed before its first one, or it finished
// without one (a run of this scene checkpoints its last step): it had other
// settings. Without, the scene needs them.
std::string missing_checkpoint_advice(const Scene& scene, const std::string& output_dir) {
  const long interval = scene.output.checkpoint_interval;
  if (interval <= 0) return "(run without --restart first, with output.checkpoint_interval > 0)";
  std::error_code error;
  if (std::filesystem::exists(std::filesystem::path(output_dir) / results::summary_file, error))
    return "(the run in this folder ended without one: it did not run with this scene's "
           "output.checkpoint_interval = " + std::to_string(interval) + "); run without --restart to start over";
  return "(with output.checkpoint_interval = " + std::to_string(interval) +
         ", the run in this folder stopped before its first checkpoint, or none ran here); run without --restart "
         "to start over";
}

}  // namespace

// Where the run in OUTDIR writes a result, something other than a file (a
// folder named energy.csv), or a file where it makes its snapshots/ folder:
// refused at the start, by every process, not when the root first writes
// there, after the set-up (and summary.json after the whole run; on several
// processes the root alone failed there, and MPI_Abort ended the others).
void check_result_paths(const Scene& scene, const std::string& output_dir, bool with_cache) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(output_dir, error)) return;  // (the run makes it: nothing in it yet)
  std::vector<fs::path> files = result_paths(output_dir);
  // The set-up's cache, which one process writes with the surface correction
  // on (before 7 December 2026 a folder of its name stopped the run after it
  // had written arrival.vtp, with "name a file").
  if (with_cache && scene.effects.surface_correction && process_count() == 1)
    files.push_back(fs::path(output_dir) / surface_correction_cache_file);
  for (const auto& file : files)
    check_replaceable_file(file.string(), "",
                           "the run writes its " + file.filename().string() +
                               " there; " + taken_place_advice);
  const fs::path snapshots = fs::path(output_dir) / results::snapshot_folder;
  const long interval = scene.output.snapshot_interval;
  // (A link that leads nowhere too: the folder cannot be made in its place.)
  if (interval > 0 && fs::symlink_status(snapshots, error).type() != fs::file_type::not_found &&
      !fs::is_directory(snapshots, error))
    throw Error(clipped(snapshots.string()) + ": not a folder, where the run writes its snapshots (" +
                scene.source_of("output.snapshot_interval") + ": key 'output.snapshot_interval' = " +
                std::to_string(interval) + "); " + taken_place_advice);
}

void check_run_paths(const Scene& scene, const RunOptions& options) {
  namespace fs = std::filesystem;
  // (error_code forms throughout: a path the system cannot use, e.g. one
  // longer than PATH_MAX, is named by its option, not by a library's text.)
  std::error_code error;
  // A name with white space at its ends that names nothing: the name
  // without it, named (before 7 December 2026 "no such file", the space unseen).
  static_cast<void>(particles_white_space_check(scene));
  // A loop of symbolic links, a name too long: the -o rule's words and what
  // to do (before 7 December 2026 the system's words alone).
  if (const std::string why = unusable_path_reason(scene.particle_file); !why.empty())
    throw Error(scene.source_of("particles") + ": key 'particles' = \"" + clipped(scene.particle_file) + "\": " + why);
  const fs::file_status particles = fs::status(scene.particle_file, error);
  // A missing file is the scene's error: say which key points there.
  if (!fs::is_regular_file(particles))
    throw Error(scene.source_of("particles") + ": key 'particles' = \"" + clipped(scene.particle_file) + "\": " +
                (fs::exists(particles) ? std::string("not a file")
                 : error && error != std::errc::no_such_file_or_directory ? error.message()
                                                                          : std::string("no such file")) +
                " (a path in the scene is relative to the scene's folder, one given with --set to the working "
                "directory; pd-mesh writes it: see the scene's first lines)");
  check_usable_path(options.output_dir, "-o");
  const fs::file_status out = fs::status(options.output_dir, error);
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error("-o " + clipped(options.output_dir) + ": a file, not a folder (the output folder of the run)");
  // The filesystem's root (-o /, or a path that resolves to it, as root):
  // no run's folder. A run writes its results and lock there and removes an
  // earlier run's files by their names (before 7 December 2026 a run wrote
  // summary.json, energy.csv, arrival.vtp and snapshots/ into /, exit 0).
  if (!fs::path(resolved_path(options.output_dir)).has_relative_path())
    throw Error("-o " + clipped(options.output_dir) + ": the filesystem's root folder" +
                (options.output_dir == "/" ? std::string() : std::string(" (where the path leads)")) +
                ", not a run's output folder: a run writes its results there and removes an earlier run's; give "
                "a folder of its own (e.g. -o out/run)");
  // A run's snapshots/ folder, or one inside it: this run's summary.json and
  // tables would sit among that run's snapshots, which the next run into
  // that folder clears by their names alone (before 7 December 2026 such a
  // run wrote there, exit 0). pd-post refuses its -o there too.
  for (fs::path folder = resolved_path(options.output_dir); folder.has_relative_path(); folder = folder.parent_path()) {
    const fs::path run = folder.parent_path();
    if (folder.filename() == results::snapshot_folder &&
        (fs::exists(run / results::snapshot_collection, error) || results::summary_by_solver(run / results::summary_file)))
      throw Error("-o " + clipped(options.output_dir) + " is inside the " + results::snapshot_folder +
                  "/ folder of the run in " + clipped(run.string()) + ": this run's results would sit among its "
                  "snapshots; give a folder of its own");
  }
  check_result_paths(scene, options.output_dir, true);
}

OutputFolderLock lock_output_folder(const RunOptions& options) {
  // A restart into a folder that does not exist has nothing to continue:
  // its run refuses it, and no folder is made.
  std::error_code error;
  if (options.restart && !std::filesystem::exists(options.output_dir, error)) return {};
  make_writable_folder(options.output_dir);
  return OutputFolderLock(options.output_dir, options.log ? *options.log : std::cout);
}

namespace {

// A plate of few bonds runs faster on fewer threads: each step's waits cost
// tens of microseconds whatever the plate's size (docs/performance.md,
// "Threads for small plates": a 4,000-particle plate's loop took 0.056 s on
// one thread and 0.079 s on two). Only where the user chose no count, on one
// process, and not for adaptive refinement (whose set grows).
void choose_threads_by_size(RunContext& c) {
  if (!c.options.threads_by_size || c.processes > 1 || c.scene.refinement.enabled) return;
  const double bonds = static_cast<double>(c.families.bond_count());
  const int wanted = std::max(1, static_cast<int>(std::lround(bonds / threads_by_size_bonds)));
  if (wanted >= c.threads) return;
  omp_set_num_threads(wanted);
  c.threads = wanted;
  c.threads_by_size = true;
}

}  // namespace

RunContext prepare_run(const Scene& scene, const RunOptions& options) {
  RunContext c;
  c.start = std::chrono::steady_clock::now();
  c.scene = scene;
  c.options = options;
  if (options.output_dir.empty()) throw Error("no output directory given");
  if (options.threads > 0) omp_set_num_threads(options.threads);
  c.threads = omp_get_max_threads();
  c.processes = process_count();
  // Every process reads the same files: an error in them (a missing or
  // malformed particle file, a stop region outside the plate) is printed
  // once (on_every_process).
  on_every_process([&] {
    check_run_paths(scene, options);
    // A restart with no checkpoint is refused before any folder is made.
    std::error_code error;
    if (options.restart && !std::filesystem::exists(std::filesystem::path(options.output_dir) / checkpoint_file, error))
      throw Error(options.output_dir + "/" + checkpoint_file + ": no checkpoint to restart from " +
                  missing_checkpoint_advice(scene, options.output_dir));
    make_writable_folder(options.output_dir);
    // A user's own file under a result's name stops a fresh run before the
    // set-up runs.
    if (!options.restart) check_earlier_results_removable(options);
    // Several processes: each reads its slab's band only, unless the
    // set-up needs the whole plate (docs/solver.md, "Set-up").
    // An error in the particle file names the scene's key that points there
    // (particles = "base.toml", a scene given for a particle file).
    const auto from_particle_file = [&](auto&& read) {
      try {
        return read();
      } catch (const BandSceneError&) {
        throw;  // (the scene's or the process count's, named as such)
      } catch (const Error& e) {
        throw Error(std::string(e.what()) + " (the particle file of " + scene.source_of("particles") +
                    ", key 'particles'; pd-mesh writes it: see the scene's first lines)");
      }
    };
    std::optional<SlabBand> band;
    if (c.processes > 1) {
      c.whole_plate_reason = distributed_setup_refusal(scene);
      if (c.whole_plate_reason.empty())
        band = from_particle_file([&] { return read_slab_band(scene, process_rank(), c.processes); });
    }
    if (band) {
      c.band_setup = true;
      c.particles = std::move(band->particles);
      c.families = std::move(band->families);
      c.band_partition = std::move(band->partition);
      c.whole_plate = std::move(band->whole);
      c.stop_region = std::move(band->stop_region);
      c.particle_count = c.whole_plate.particle_count;
    } else {
      // The families stream by and stay compact (compact_families.hpp): the
      // particle file's 12 bytes per bond are never held at once.
      auto read = from_particle_file([&] { return read_compact_particle_file(scene.particle_file); });
      c.particles = std::move(read.particles);
      c.families = std::move(read.families);
      c.particle_count = c.particles.size();
      if (scene.stop.enabled) c.stop_region = resolve_region(scene.stop.region, c.particles, scene.path, "stop");
    }
    // Before the set-up: material values the run cannot compute with at these cells and horizons.
    check_material_scales(scene, c.particles);
    c.spacing = c.particles.spacing;
    c.particles_read = c.particles.size();
    choose_threads_by_size(c);
    c.particle_hash = file_hash_hex(scene.particle_file);
    c.checkpoint_key = checkpoint_key(scene.restart_key_text, c.particle_hash, c.processes);
    c.scene.run_id = run_identifier(scene.restart_key_text, c.particle_hash);
    // Several processes save the bond states family by family (docs/formats.md;
    // the lattice sweep's pair bits converted): such a checkpoint restarts on
    // any number of processes above one, never on one (other layout).
  });
  return c;
}

void RunContext::clear_earlier_results() const {
  // A fresh run's folder holds its own results only: an earlier run's
  // summary.json beside the files of a run that fails or is killed would make
  // it look complete (pd-post), its files another kind of run.
  if (options.restart || process_rank() != 0) return;
  check_earlier_results_removable(options);  // (checked at set-up; a folder may have changed since)
  std::size_t removed = 0;
  for (const auto& folder : folders_a_fresh_run_clears(options)) removed += remove_earlier_results(folder);
  if (removed > 0)
    log() << "removed " << removed << " result file" << (removed == 1 ? "" : "s") << " of an earlier run in "
          << options.output_dir << " (caches kept)\n";
  if (options.switching_run_folder.empty()) return;
  removed = remove_earlier_results(options.switching_run_folder);  // (its checkpoint too, if it is a run's; else refused)
  if (removed > 0)
    log() << "removed " << removed << " result file" << (removed == 1 ? "" : "s") << " of an earlier run in "
          << options.switching_run_folder << " (caches kept)\n";
}

void RunContext::write_deferred_cache() const {
  if (process_rank() != 0) return;
  // A switching run's OUTDIR cache first: this part's copy is of its factors.
  if (options.shared_surface_correction_kept_back) options.shared_surface_correction_kept_back->write();
  deferred_cache->write();
}

}  // namespace pd::solver
