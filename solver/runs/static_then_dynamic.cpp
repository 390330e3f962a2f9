#include "static_then_dynamic.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

#include "dynamic_run.hpp"
#include "error.hpp"
#include "peak_memory.hpp"
#include "units.hpp"

namespace pd::solver {
namespace {

Scene with_loads_of(const Scene& scene, LoadPhase phase) {
  Scene part = scene;
  part.loads.clear();
  for (const auto& load : scene.loads)
    if (load.phase == phase) part.loads.push_back(load);
  return part;
}

}  // namespace

Scene quasi_static_part(const Scene& scene) {
  Scene part = with_loads_of(scene, LoadPhase::quasi_static);
  part.quasi_static.then_dynamic = false;
  part.stop = {};
  // output.checkpoint_interval counts the dynamic part's time steps. Load
  // steps are few and each costs a whole solve: with checkpoints on, the
  // quasi-static part saves one after every load step.
  if (part.output.checkpoint_interval > 0) part.output.checkpoint_interval = 1;
  return part;
}

Scene dynamic_part(const Scene& scene) {
  Scene part = with_loads_of(scene, LoadPhase::dynamic);
  part.quasi_static = {};
  part.starts_from_equilibrium = true;
  return part;
}

void start_from_equilibrium(Simulation& sim, const Equilibrium& equilibrium) {
  const std::size_t n = sim.particle_count();
  if (equilibrium.u.size() != 2 * n) throw Error("the quasi-static state does not fit the dynamic part's particles");
  Simulation::State state = sim.save_state();
  auto& k = state.kinematics;
  for (std::size_t i = 0; i < n; ++i) {
    k.ux[i] = equilibrium.u[i];
    k.uy[i] = equilibrium.u[n + i];
  }
  sim.restore_state(state);
  // A pair broken in the quasi-static part is broken in the dynamic part.
  sim.break_pairs(equilibrium.broken_pairs);
  // restore_state keeps the saved forces; these are the forces and the damage index of the new state.
  sim.set_displacements(k.ux, k.uy);
  state = sim.save_state();
  const auto& thresholds = sim.scene().output.damage_thresholds;
  const auto& damage = sim.damage();
  for (std::size_t t = 0; t < thresholds.size(); ++t)
    for (std::size_t i = 0; i < n; ++i) state.arrival[t * n + i] = damage[i] >= thresholds[t] ? sim.time() : -1.0;
  sim.restore_state(state);
}

RunReport run_static_then_dynamic(const Scene& scene, const RunOptions& options) {
  if (options.output_dir.empty()) throw Error("no output directory given");
  namespace fs = std::filesystem;
  const fs::path out(options.output_dir);
  const fs::path dynamic_checkpoint = out / checkpoint_file;
  // --restart continues the dynamic part when it has a checkpoint (the first
  // one is written at the switch). Before that, the quasi-static part
  // continues from its own checkpoint and the switch is made again.
  if (options.restart && fs::exists(dynamic_checkpoint)) return run_dynamic(prepare_run(dynamic_part(scene), options));

  RunOptions first = options;
  first.output_dir = (out / quasi_static_part_folder).string();
  if (options.restart && !fs::exists(fs::path(first.output_dir) / checkpoint_file))
    throw Error(options.output_dir + ": nothing to restart from: neither " + dynamic_checkpoint.string() + " nor " +
                (fs::path(first.output_dir) / checkpoint_file).string() +
                " exists (output.checkpoint_interval = 0, or the run stopped before its first checkpoint); run "
                "again without --restart");
  RunOptions dynamic = options;
  dynamic.restart = false;
  dynamic.quasi_static_part_is_own = true;
  // What the dynamic part would refuse whatever the equilibrium (a time.step
  // above the stable limit, ...), before the load steps: they may take
  // hours (before, the refusal came after them).
  const auto dynamic_factors = check_dynamic_plan(prepare_run(dynamic_part(scene), dynamic));
  // A checkpoint left by an earlier run of this folder is not this run's,
  // nor are its results (the dynamic part's set-up would remove them only
  // after the quasi-static part): the quasi-static part removes them with
  // its own earlier results, once its checks have passed too. A refused run
  // leaves them (before 6 December 2026 it removed them; until 7 December
  // 2026 one the quasi-static part refused did).
  if (!options.restart) {
    // Both folders before either loses anything: a file there that no run
    // wrote refuses the run with both folders whole (before 7 December 2026
    // OUTDIR was cleared first).
    check_earlier_results_removable(first);
    check_earlier_results_removable(dynamic);
    first.switching_run_folder = options.output_dir;
  }
  reset_peak_memory();  // (that set-up is gone: the quasi-static part reports its own peak)
  // Both parts build the same bonds: the quasi-static part reads the
  // surface-correction factors that check computed, and OUTDIR's cache and
  // its folder's copy get them only once its own checks have passed (before
  // 7 December 2026 the copy came first, and a part refused by its checks
  // left it there; OUTDIR's cache was replaced before those checks).
  first.shared_surface_correction_cache = (out / surface_correction_cache_file).string();
  first.shared_surface_correction_kept_back = dynamic_factors;
  // A part refused before its first result takes back the folder it made.
  std::error_code error;
  const bool part_existed = fs::exists(first.output_dir, error) || error;
  auto equilibrium = std::make_shared<Equilibrium>();
  try {
    run_quasi_static(prepare_run(quasi_static_part(scene), first), equilibrium.get());
  } catch (...) {
    if (!part_existed && !holds_results(first.output_dir)) fs::remove_all(first.output_dir, error);
    throw;
  }
  reset_peak_memory();  // the quasi-static problem is gone: the dynamic part reports its own peak
  std::ostream& log = options.log ? *options.log : std::cout;
  log << "switching to dynamic at load factor " << shortest_text(equilibrium->load_factor) << " ("
      << equilibrium->broken_pairs.size() << " broken pairs, pre-cracks included)\n"
      << std::flush;
  return run_dynamic(prepare_run(dynamic_part(scene), dynamic),
                     [equilibrium](Simulation& sim) { start_from_equilibrium(sim, *equilibrium); });
}

}  // namespace pd::solver
