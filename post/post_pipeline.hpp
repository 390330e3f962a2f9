#pragma once
// pd-post from options to files for a dynamic run: read the solver output,
// find branches and tips, compute speeds and pore trapping, write tables,
// summary and pictures. (Quasi-static runs: quasi_static_pipeline.hpp.)
#include <optional>
#include <string>
#include <vector>

#include "arrival_data.hpp"
#include "crack_branches.hpp"
#include "crack_comparison.hpp"
#include "crack_speed.hpp"
#include "line_profile.hpp"
#include "pores.hpp"
#include "rayleigh_speed.hpp"
#include "solver_summary.hpp"
#include "speed_window.hpp"
#include "tip_tracking.hpp"

namespace pd::post {

struct PostOptions {
  std::string outdir;             // solver output directory
  std::string postdir;            // default: OUTDIR/post
  double threshold = 0.35;        // damage threshold of the crack
  bool threshold_given = false;   // --threshold was given: a quasi-static run notes it as not used
  int window_steps = 0;           // speed window in solver steps (0: the rule of speed_window.hpp) ...
  double window_time = 0;         // ... or in seconds when > 0
  double angle_length = default_angle_length;  // [m] branching angles are fitted over this length
  bool angle_length_given = false;  // --angle-length was given (as threshold_given)
  std::string boxes_file;         // manual branch boxes (CSV); empty = automatic
  std::string pores_file;         // pore circles (CSV); empty = detect from the layout
  std::vector<double> map_times;  // [s] extra damage / strain-energy maps (dynamic runs)
  std::vector<double> map_load_factors;  // extra maps of a quasi-static run
  std::optional<SampleLine> line; // values along this line (line_profile.csv)
  double line_offset = 0;         // [m] of the one-sided fits; 0 = one horizon
  std::string reference_dir;      // another run's output directory to compare damage with; empty = none
  double band = 0;                // [m] half-width around the reference's damage; 0 = two horizons (the larger)
  double damage_level = 0.2;      // damaged = final damage at or above this (comparison only)
};

// A picture drawn for a requested time (or load factor) and the one used.
struct MapAt {
  double requested = 0, used = 0;
  std::string source;  // "snapshot FILE" or "arrival times"
};

struct PostResult {
  ArrivalData data;
  SolverSummary solver;
  std::vector<Pore> pores;
  std::string pore_source;
  CrackNetwork network;
  std::vector<TipPath> tips;
  std::vector<SpeedSample> speeds;
  std::vector<PoreVisit> pore_visits;
  ElasticModel model;                       // the model that ran
  RayleighSpeed rayleigh;                   // of that model
  std::optional<RayleighSpeed> material_rayleigh;  // with the material's own Poisson ratio, for reference
  double rayleigh_speed = 0;      // [m/s] = rayleigh.speed, what speeds are divided by
  SpeedWindow window;
  int window_steps = 0;           // = window.steps
  double window_seconds = 0;      // = window.seconds
  double angle_length = 0;        // [m]
  double max_damage = 0;          // final, in [0, 1]
  std::optional<SampleLine> line_segment;  // PostOptions::line
  double line_offset = 0;         // [m] used for the one-sided fits
  std::vector<LineSample> line;   // samples along line_segment
  std::vector<MapAt> maps;
  std::optional<DamageComparison> comparison;  // with PostOptions::reference_dir
  std::string postdir;
  std::string main_picture;       // damage map with the tip paths
  std::string speed_table;        // crack_speed.csv
  std::vector<std::string> pictures;
  std::vector<std::string> notes;     // what was assumed or left out
  std::vector<std::string> warnings;  // what may make the results wrong or incomplete
};

// Analysis only (no files written).
PostResult analyse(const PostOptions& options);

// Analysis plus every output file in the post directory.
PostResult run_post(const PostOptions& options);

// Creates the folder `dir` and its parents, or throws pd::Error naming it as
// `shown` ("-o DIR", or DIR for a default) and `what` it is for: a file of
// that name, a path through a file, no permission.
void create_output_folder(const std::string& dir, const std::string& shown, const std::string& what);

// The post directory (PostOptions::postdir, default OUTDIR/post), created,
// without the temporary files of killed pd-post runs (remove_stale_temporaries;
// a note in `notes` says how many went).
std::string make_post_directory(const PostOptions& options, std::vector<std::string>& notes);

// Picture-name tags: "20us" for 2e-5 s, "lf0.8" for load factor 0.8.
std::string time_tag(double seconds);
std::string load_factor_tag(double load_factor);

}  // namespace pd::post
