#pragma once
// The scene: everything a run needs besides the particle file, read from a
// TOML file (keys, units and defaults: docs/scenes.md). All values are SI.
#include <array>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "bond_weights.hpp"
#include "geometry.hpp"
#include "material.hpp"
#include "model_registry.hpp"

namespace pd::solver {

struct EffectsSpec {
  bool damage = true;
  bool surface_correction = false;
};

struct TimeSpec {
  bool automatic = true;  // step = safety * stable limit
  double step = 0;        // [s] when not automatic
  double safety = 0.8;    // fraction of the stable limit when automatic
  double end = 0;         // [s]
  bool force = false;     // accept a fixed step above the stable limit
};

// Where a load or a stop condition acts: a named boundary set of the particle
// file, "all", an axis-aligned box [xmin, ymin, xmax, ymax] in metres, or the
// one particle nearest to a point (a pin).
struct RegionSpec {
  std::string set;                // empty when a box or a point is used
  bool has_box = false;
  std::array<double, 4> box{};    // xmin, ymin, xmax, ymax [m]
  bool has_nearest = false;
  Vec2 nearest;                   // [m]: the region is the particle whose centre is nearest
  std::string where;              // "scene.toml:LINE" or "scene.toml, --set": for messages
  std::string describe() const;
};

// Multiplier f(t) of a load's value.
struct TimeFunction {
  enum class Kind { constant, ramp, table } kind = Kind::constant;
  double ramp_time = 0;                        // [s]: f = min(t / ramp_time, 1)
  std::vector<std::pair<double, double>> table;  // (t [s], f), piecewise linear, held at the ends
  double operator()(double time) const;
};

enum class LoadKind { velocity, displacement, fixed, traction, initial_velocity };
const char* to_string(LoadKind kind);

// Which part of a scene that switches from quasi-static to dynamic
// (quasi_static.then = "dynamic") a load belongs to; `any` in every other scene.
enum class LoadPhase { any, quasi_static, dynamic };

// How a load component varies with the reference position p: its value is
// x + dot(gradient, p - origin) (LoadSpec::x_at); a zero gradient is a
// uniform value (docs/scenes.md, "Values that vary linearly").
struct LinearVariation {
  Vec2 gradient;  // [value unit / m]
  Vec2 origin;    // [m]: where the component has its given value
  // The points the scene wrote (`at`, or `from` and `to`) with their keys,
  // checked against the plate once it is read (a point in mm far off it).
  std::vector<std::pair<std::string, Vec2>> written_points;
  bool is_uniform() const { return gradient.x == 0 && gradient.y == 0; }
};

struct LoadSpec {
  std::string name;     // for energy.csv columns
  // Its position in the scene file's [[loads]] (for messages: a switching
  // scene's parts hold some of them); -1 for a scene built in code.
  long file_index = -1;
  LoadPhase phase = LoadPhase::any;
  LoadKind kind = LoadKind::fixed;
  RegionSpec region;
  bool has_x = false, has_y = false;  // which components are given (constrained)
  double x = 0, y = 0;  // m/s (velocity), m (displacement), Pa (traction); at `origin` if they vary
  LinearVariation x_variation, y_variation;
  TimeFunction time_function;
  double edge_length = 0;  // traction only: loaded edge length [m]; 0 = automatic
  // The components at reference position p [value unit], at f(t) = 1.
  double x_at(Vec2 p) const { return x + dot(x_variation.gradient, p - x_variation.origin); }
  double y_at(Vec2 p) const { return y + dot(y_variation.gradient, p - y_variation.origin); }
};

struct PrecrackSpec {
  Vec2 from, to;  // [m]
  std::string where_from{}, where_to{};  // "scene.toml:LINE" or "scene.toml, --set" of each end: for messages
};

// Stop before the end time when any particle of the region reaches a damage.
struct StopSpec {
  bool enabled = false;
  RegionSpec region;
  double damage = 0.35;
};

// Quasi-static mode ([quasi_static], docs/scenes.md): instead of time steps, a
// list of load steps; at each one the energy is minimised (solver/ncg.hpp).
// Displacement loads and tractions are multiplied by the step's load factor.
struct QuasiStaticSpec {
  bool enabled = false;
  std::vector<double> load_factors;  // cumulative load factor of every step, in order
  std::string load_steps_key = "load_factors";  // the key that gave them: load_factors or increments
  double tolerance = 1e-6;           // relative residual force at which a minimisation has converged
  long max_iterations = 20000;       // NCG iterations per minimisation
  bool warn_on_nonconvergence = false;  // on_nonconvergence = "warn": go on with the achieved residual
  long max_breaking_rounds = 1000;   // re-equilibrations after bond breaking within one load step
  // Stop when the reaction force falls below this fraction of its largest value
  // so far (the sample has separated); 0 = never.
  double stop_reaction_fraction = 0;
  // then = "dynamic": after the last load step the run goes on as a dynamic one
  // from that equilibrium ([time], the loads of phase "dynamic"; static_then_dynamic.hpp).
  bool then_dynamic = false;
  // kernels = "lattice": the residual from the dynamic solver's kernels (float
  // lattice sweep, then double near convergence; docs/solver.md, "Fast
  // kernels"); "lists" (default): the double-precision energy table.
  bool lattice_kernels = false;
  // With the lattice kernels: the coarse-space correction of the
  // preconditioner (theory.md Sec. 4.13); false keeps the 2 x 2 blocks alone.
  bool coarse_correction = true;
  // With the lattice kernels: damped Newton rounds after a dropped tangent and
  // K0 round (theory.md Sec. 4.14); false goes to the central-difference NCG
  // there at once (the path before them, for comparison).
  bool damped_rounds = true;
  double progress_interval = 10;  // [s] between progress lines of a running minimisation
  // The plan's warnings for keys given that the scene's other choices leave
  // without effect ("FILE:LINE: key 'quasi_static.coarse_correction' = false
  // has no effect with quasi_static.kernels = \"lists\": ...").
  std::vector<std::string> inert_keys;
};

// The strain a particle's refinement criterion measures (theory.md Sec.
// 8.1): the largest stretch of its intact bonds, or the accumulated normal
// strains along x and y of its family (Zeng and Zhang 2024).
enum class RefinementStrain { bond, normal };
// The scene's default alpha of each criterion: the largest bond stretch
// splits at 0.4, the accumulated normal strain (a family average, Zeng and
// Zhang's) at their 0.5 (docs/refinement.md, "Criteria and spread").
constexpr double default_strain_fraction(RefinementStrain strain) {
  return strain == RefinementStrain::bond ? 0.4 : 0.5;
}
// Which particles split with a chosen one: its family (at most as fine),
// those of them within a distance (RefinementSpec::spread_horizons), or none.
enum class RefinementSpread { family, within, none };

// Adaptive particle refinement during a dynamic run ([refinement],
// docs/scenes.md; theory.md Sec. 8): square particles split into four
// children where the crack is about to run.
struct RefinementSpec {
  bool enabled = false;
  double damage_threshold = 0.4;  // phi_c: split a particle whose damage exceeds it
  // alpha: ... or whose strain (`strain`) exceeds alpha s_c(delta_i)
  double strain_fraction = default_strain_fraction(RefinementStrain::bond);
  // The fine zone's lead: once a particle meets the criteria (an event), every
  // particle whose strain exceeds lead_fraction s_c splits as well, so that the
  // next event comes later (docs/refinement.md, "Fewer events"). Equal to
  // strain_fraction (the scene's default) or 0: no lead.
  double lead_fraction = 0;
  // The strain fraction an event splits at: the lead's, or alpha without one.
  double event_split_fraction() const {
    return lead_fraction > 0 && lead_fraction < strain_fraction ? lead_fraction : strain_fraction;
  }
  RefinementStrain strain = RefinementStrain::bond;
  RefinementSpread spread = RefinementSpread::family;
  double spread_horizons = 0;     // spread `within`: the distance, in horizons of the chosen particle
  long levels = 1;                // halvings a particle of the particle file may undergo (dx -> dx / 2^levels)
  bool has_region = false;        // splits only inside `region` (else anywhere)
  std::array<double, 4> region{};  // xmin, ymin, xmax, ymax [m]
  long particle_budget = 0;       // largest particle count refinement may reach; 0 = no limit
  long check_interval = 10;       // steps between checks of the criteria
  bool check_interval_defaulted = false;  // the scene and --set left it out (for messages)
  // The --set keys that made [refinement] where the scene has none ("refinement.levels"):
  // --set adds keys and their tables, and this one turns refinement on (the plan says so).
  std::string made_by_set;
};

struct OutputSpec {
  long snapshot_interval = 0;    // steps; 0 = no snapshots
  long energy_interval = 100;    // steps
  long checkpoint_interval = 0;  // steps; 0 = none
  std::vector<double> damage_thresholds{0.2, 0.35, 0.5};
};

struct Scene {
  std::string path;           // the scene file (for messages)
  std::string particle_file;  // resolved against the scene file's folder
  std::string particles_as_written;  // the key 'particles' as the scene or --set gave it (for messages)
  MaterialSpec material;
  ModelType model = ModelType::pmb;
  // What a broken OSB bond leaves (model.osb_failure; theory.md Sec. 5.8).
  OsbFailure osb_failure = OsbFailure::force_and_dilatation;
  BondWeights bond_weights = BondWeights::distance_moment;  // model.bond_weights
  // model.dual_horizon: true = dual-horizon PD (theory.md Sec. 6), false =
  // ordinary PD even with variable horizons; unset = not given (particles
  // whose horizons differ then need it, setup/horizon_mode.hpp).
  std::optional<bool> dual_horizon;
  EffectsSpec effects;
  TimeSpec time;                 // dynamic mode, and the dynamic part of a switching scene
  QuasiStaticSpec quasi_static;  // quasi_static.enabled selects the quasi-static mode
  StopSpec stop;
  // The dynamic part of a switching scene (static_then_dynamic.hpp): it
  // starts from the quasi-static part's equilibrium, not from rest.
  bool starts_from_equilibrium = false;
  RefinementSpec refinement;
  std::vector<LoadSpec> loads;
  std::vector<PrecrackSpec> precracks;
  OutputSpec output;
  std::string canonical_text;  // the parsed scene after overrides, printed back
  // The same without time.end: the checkpoint key (a restart may extend the end time).
  std::string restart_key_text;
  // The keys written with their default value ("time.safety" for safety =
  // 0.8), which the restart key leaves out: a scene that writes a default is
  // the scene that leaves it out.
  std::vector<std::string> written_defaults;
  // The run's identifier, written into its result files (run_identifier;
  // set by prepare_run once the particle file's hash is known; empty for a
  // scene that is not run, whose files then carry none).
  std::string run_id;
  std::set<std::string> set_keys;  // the keys --set gave, as written ("time.step")

  // Whether --set gave the key, itself or with its table given whole
  // ("model.dual_horizon" by --set 'model={dual_horizon=true}').
  bool given_by_set(const std::string& key) const {
    for (auto dot = key.find('.'); dot != std::string::npos; dot = key.find('.', dot + 1))
      if (set_keys.count(key.substr(0, dot))) return true;
    return set_keys.count(key) > 0;
  }
  // Where a key's value comes from, for messages: "FILE", or "FILE, --set".
  std::string source_of(const std::string& key) const { return path + (given_by_set(key) ? ", --set" : ""); }
  // " from --set" after a key's value that --set gave, for a message about
  // another key (or none): "model.dual_horizon = true from --set".
  std::string from_set(const std::string& key) const { return given_by_set(key) ? " from --set" : ""; }
};

// The particle file's name with white space at its ends (particles =
// "plate.pdp ", --set particles=' plate.pdp'), by -o's rule
// (white_space_name_check in common/atomic_file): pd::Error naming the key
// where nothing has that name, the plan's warning where something has
// (taken), "" for a name without such white space.
std::string particles_white_space_check(const Scene& scene);

// Reads a scene file and applies "section.key=value" overrides (value in TOML
// syntax; a bare word is taken as a string). Throws pd::Error naming the
// file, the key and the value on any problem.
Scene read_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// Same from text (for tests); `path` is used in messages and to resolve the particle file.
Scene parse_scene(const std::string& text, const std::string& path,
                  const std::vector<std::string>& overrides = {});

}  // namespace pd::solver
