#pragma once
// The post tool's input for a quasi-static run (docs/solver.md,
// "Quasi-static mode"): load_steps.csv (one row per load step, with the
// reactions of every load), final_state.vtp (displacement, damage, the load
// factor at which damage first appeared) and the snapshots, whose "time" is
// their load factor. A run that was stopped has no final_state.vtp: its last
// snapshot stands in, with a warning.
#include <string>
#include <vector>

#include "arrival_data.hpp"

namespace pd::post {

// A column of load_steps.csv ending in "_reaction_x_N" or "_reaction_y_N" [N].
struct ReactionColumn {
  std::string name;
  std::vector<double> values;  // one per load step
};

struct QuasiStaticData {
  std::string outdir;
  std::string load_steps_path;
  std::vector<int> steps;             // load step numbers
  std::vector<double> load_factors;   // per load step
  std::vector<double> max_damage;     // per load step, in [0, 1]
  std::vector<ReactionColumn> reactions;

  std::string state_path;             // final_state.vtp, or the last snapshot; empty if neither
  bool final_state = false;           // the state is final_state.vtp
  double state_load_factor = 0;
  std::vector<double> x, y, cell_size;  // [m]
  std::vector<double> ux, uy;           // [m]
  std::vector<double> damage;           // in [0, 1]
  std::vector<double> strain_energy_density;  // [J/m^3], empty: pd-solve does not write it here
  double spacing = 0, horizon = 0;      // [m]
  std::string run_id;                   // the state's field run_id (empty if absent)

  std::vector<std::string> notes, warnings;
  std::size_t size() const { return x.size(); }
};

// Reads OUTDIR. Throws pd::Error naming the file for a missing or malformed
// load_steps.csv and for unreadable or inconsistent .vtp files.
QuasiStaticData read_quasi_static_data(const std::string& outdir);

}  // namespace pd::post
