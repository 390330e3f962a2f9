#include "horizon_mode.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"
#include "units.hpp"

namespace pd::solver {

const char* to_string(HorizonMode mode) {
  switch (mode) {
    case HorizonMode::uniform: return "uniform";
    case HorizonMode::dual_horizon: return "dual_horizon";
    case HorizonMode::ordinary_variable: return "ordinary_variable";
  }
  return "?";
}

double largest_horizon(const ParticleSet& p) {
  double largest = 0;
  for (double h : p.horizon) largest = std::max(largest, h);
  return largest;
}

namespace {

// Why a scene cannot run on horizons that differ (or with dual horizons) with
// model.dual_horizon = `dual`: where the key comes from ("FILE" or "FILE,
// --set") and the reason, or an empty reason when it can. `what` says what
// asks for it ("horizons that differ", "model.dual_horizon = true").
struct Obstacle {
  std::string source, reason;
};
Obstacle variable_horizon_obstacle(const Scene& scene, bool dual, const std::string& what) {
  const std::string model = "model.type = \"" + std::string(to_string(scene.model)) + "\"";
  // The state-based model has a dual-horizon form (theory.md Sec. 6.8), not
  // ordinary PD's per-particle constants.
  if (scene.model != ModelType::pmb && !dual)
    return {scene.source_of("model.dual_horizon"), model + " with " + what +
           " needs model.dual_horizon = true (got false): ordinary PD with a variable horizon is available for "
           "model.type = \"pmb\" only"};
  if (scene.effects.surface_correction)
    return {scene.source_of("effects.surface_correction"), "effects.surface_correction = true is not available with " + what +
           " (the correction's factors assume one horizon); set it to false"};
  if (scene.quasi_static.enabled && scene.model != ModelType::pmb)
    return {scene.source_of("model.type"), "[quasi_static] with " + model + " and " + what +
           " is not available: dual-horizon " + to_string(scene.model) +
           " runs are dynamic only for now; remove [quasi_static] or use model.type = \"pmb\""};
  if (scene.quasi_static.enabled) {
    // Dual-horizon forces are the gradient of one energy (theory.md Sec. 6.6),
    // which the minimiser needs; ordinary PD's with a variable horizon are not.
    if (!dual)
      return {scene.source_of("model.dual_horizon"), "[quasi_static] is not available for ordinary PD with " +
             what + " (its forces are not the gradient of an energy to minimise); set model.dual_horizon = true"};
    if (scene.effects.damage)
      return {scene.source_of("effects.damage"), "[quasi_static] with " + what +
             " needs effects.damage = false for now (a bond and its dual bond break at different stretches, which "
             "the energy table cannot hold yet); run a fracture scene dynamically"};
    if (scene.quasi_static.lattice_kernels)
      return {scene.source_of("quasi_static.kernels"), "quasi_static.kernels = \"lattice\" is not available with " +
             what + " (the lattice's constants assume one horizon); use \"lists\""};
  }
  return {};
}

}  // namespace

HorizonMode horizon_mode(const Scene& scene, const ParticleSet& p) {
  if (p.size() == 0) throw Error(scene.particle_file + ": the particle set is empty");
  const auto [low, high] = std::minmax_element(p.horizon.begin(), p.horizon.end());
  const bool varies = *high - *low > 1e-9 * *high;
  const bool dual = scene.dual_horizon.value_or(false);
  if (!varies && !dual) return HorizonMode::uniform;
  const std::string what = dual ? "model.dual_horizon = true" + scene.from_set("model.dual_horizon")
                                : std::string("horizons that differ");
  if (varies && !scene.dual_horizon) {
    // Offer only the settings this scene can run with, so that the advice
    // does not lead to the next refusal.
    const Obstacle with_dual = variable_horizon_obstacle(scene, true, what);
    const Obstacle with_ordinary = variable_horizon_obstacle(scene, false, what);
    std::string advice;
    if (with_dual.reason.empty() && with_ordinary.reason.empty())
      advice = "set model.dual_horizon = true in " + scene.path +
               " (dual-horizon PD, theory.md Sec. 6), or false for ordinary PD with a variable horizon, which has "
               "ghost forces where the horizon changes";
    else if (with_dual.reason.empty())
      advice = "set model.dual_horizon = true in " + scene.path + " (dual-horizon PD, theory.md Sec. 6)";
    else if (with_ordinary.reason.empty())
      advice = "set model.dual_horizon = false in " + scene.path +
               " (ordinary PD with a variable horizon, which has ghost forces where the horizon changes)";
    else if (with_dual.reason == with_ordinary.reason)
      // One obstacle for both forms (the surface correction): say it once.
      advice = with_dual.source + ": " + with_dual.reason + " (with either value of model.dual_horizon)";
    else
      advice = scene.path + " runs on neither form: with model.dual_horizon = true, " + with_dual.reason +
               "; with false, " + with_ordinary.reason +
               "; or mesh the plate with one horizon (pd-mesh without --refine-region, --box-spacing or "
               "--graded-spacing)";
    throw Error(scene.particle_file + ": particles have different horizons (" + format_mm(*low) + " to " +
                format_mm(*high) + "); " + advice);
  }
  if (const Obstacle why = variable_horizon_obstacle(scene, dual, what); !why.reason.empty())
    throw Error(why.source + ": " + why.reason);
  return dual ? HorizonMode::dual_horizon : HorizonMode::ordinary_variable;
}

}  // namespace pd::solver
