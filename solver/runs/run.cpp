#include "run.hpp"

#include <filesystem>
#include <iostream>

#include "atomic_file.hpp"
#include "dynamic_run.hpp"
#include "error.hpp"
#include "processes.hpp"
#include "quasi_static_run.hpp"
#include "run_context.hpp"
#include "results_format.hpp"
#include "static_then_dynamic.hpp"

namespace pd::solver {

std::size_t remove_stale_outputs(const std::string& output_dir, std::ostream& log) {
  namespace fs = std::filesystem;
  // Every folder a run writes into: a killed run may have left a temporary
  // file in any of them, and nothing else would ever remove it. Also pd-post's
  // folder, whose pictures of the earlier results the run removes.
  const fs::path out(output_dir);
  const fs::path part = out / results::quasi_static_part_folder;
  std::size_t removed = 0;
  for (const fs::path& folder :
       {out, out / results::snapshot_folder, part, part / results::snapshot_folder, out / results::post_folder})
    removed += remove_stale_temporaries(folder.string()).size();
  if (removed > 0)
    log << "removed " << removed << " temporary file" << (removed == 1 ? "" : "s") << " left by a killed run in "
        << output_dir << "\n";
  return removed;
}

namespace {
// Where the processes other than the root print: nowhere (the root prints the plan and report).
std::ostream& silent_stream() {
  static std::ostream silent(nullptr);
  return silent;
}
}  // namespace

RunReport run_scene(const Scene& scene, const RunOptions& given_options) {
  RunOptions options = given_options;
  if (process_rank() != 0) options.log = &silent_stream();
  // Every process refuses the same scene: reported once (on_every_process).
  on_every_process([&] {
    if (scene.quasi_static.enabled && process_count() > 1)
      throw Error(scene.path + ": table [quasi_static]: quasi-static scenes (and those that switch to dynamics, " +
                  "quasi_static.then) run on one process for now, not " + std::to_string(process_count()) +
                  "; run pd-solve without mpirun (docs/solver.md, \"Running on several processes (MPI)\")");
    if (scene.refinement.enabled && process_count() > 1)
      throw Error(scene.path + ": table [refinement]: adaptive refinement runs on one process for now, not " +
                  std::to_string(process_count()) +
                  "; run pd-solve without mpirun (docs/solver.md, \"Running on several processes (MPI)\")");
  });
  // One run at a time in the folder: the root takes its lock before it
  // tidies or writes anything there, and holds it until the run returns
  // (fresh, --restart and every kind of run alike). The paths are checked
  // first, so that a run refused by them makes no folder.
  OutputFolderLock lock;
  if (!options.output_dir.empty()) on_every_process([&] { check_run_paths(scene, options); });
  // A run refused before it wrote a result (by its plan: a step count or
  // memory beyond the machine; by its particle file, ...) leaves no folder
  // it made: only the set-up's cache would be in it. A folder that existed
  // is left as it is.
  // (A link that leads nowhere exists: the user's; before 7 December 2026 a
  // refused run removed it.)
  const std::filesystem::path made = options.output_dir.empty() || process_rank() != 0
                                         ? std::filesystem::path()
                                         : std::filesystem::path(outermost_missing_folder(options.output_dir));
  try {
    if (!options.output_dir.empty()) on_the_root([&] { lock = lock_output_folder(options); });
    // The root alone tidies the output folder (the others would race it).
    if (!options.output_dir.empty() && process_rank() == 0)
      remove_stale_outputs(options.output_dir, options.log ? *options.log : std::cout);
    if (!scene.quasi_static.enabled) return run_dynamic(prepare_run(scene, options));
    if (!scene.quasi_static.then_dynamic) return run_quasi_static(prepare_run(scene, options));
    return run_static_then_dynamic(scene, options);
  } catch (...) {
    if (!made.empty() && !holds_results(options.output_dir)) {
      lock = OutputFolderLock();  // (its file goes first, then the lock)
      std::error_code ignored;
      std::filesystem::remove_all(made, ignored);
    }
    throw;
  }
}

}  // namespace pd::solver
