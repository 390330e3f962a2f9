#include "run.hpp"

#include "dynamic_run.hpp"
#include "quasi_static_run.hpp"
#include "static_then_dynamic.hpp"

namespace pd::solver {

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  if (!scene.quasi_static.enabled) return run_dynamic(prepare_run(scene, options));
  if (!scene.quasi_static.then_dynamic) return run_quasi_static(prepare_run(scene, options));
  return run_static_then_dynamic(scene, options);
}

}  // namespace pd::solver
