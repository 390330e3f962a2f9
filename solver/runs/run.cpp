#include "run.hpp"

#include <filesystem>
#include <iostream>

#include "atomic_file.hpp"
#include "dynamic_run.hpp"
#include "quasi_static_run.hpp"
#include "results_format.hpp"
#include "static_then_dynamic.hpp"

namespace pd::solver {

std::size_t remove_stale_outputs(const std::string& output_dir, std::ostream& log) {
  namespace fs = std::filesystem;
  // Every folder a run writes into: a killed run may have left a temporary
  // file in any of them, and nothing else would ever remove it.
  const fs::path out(output_dir);
  const fs::path part = out / results::quasi_static_part_folder;
  std::size_t removed = 0;
  for (const fs::path& folder : {out, out / results::snapshot_folder, part, part / results::snapshot_folder})
    removed += remove_stale_temporaries(folder.string()).size();
  if (removed > 0)
    log << "removed " << removed << " temporary file" << (removed == 1 ? "" : "s") << " left by a killed run in "
        << output_dir << "\n";
  return removed;
}

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  if (!options.output_dir.empty()) remove_stale_outputs(options.output_dir, options.log ? *options.log : std::cout);
  if (!scene.quasi_static.enabled) return run_dynamic(prepare_run(scene, options));
  if (!scene.quasi_static.then_dynamic) return run_quasi_static(prepare_run(scene, options));
  return run_static_then_dynamic(scene, options);
}

}  // namespace pd::solver
