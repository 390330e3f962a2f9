#pragma once
// pd-post from options to files: read the solver output, find branches and
// tips, compute speeds and pore trapping, write tables, summary and pictures.
#include <string>
#include <vector>

#include "arrival_data.hpp"
#include "crack_branches.hpp"
#include "crack_speed.hpp"
#include "pores.hpp"
#include "tip_tracking.hpp"

namespace pd::post {

struct PostOptions {
  std::string outdir;             // solver output directory
  std::string postdir;            // default: OUTDIR/post
  double threshold = 0.35;        // damage threshold of the crack
  int window_steps = 30;          // speed window in solver steps ...
  double window_time = 0;         // ... or in seconds when > 0
  std::string boxes_file;         // manual branch boxes (CSV); empty = automatic
  std::string pores_file;         // pore circles (CSV); empty = detect from the layout
  std::vector<double> map_times;  // [s] extra damage / strain-energy maps
};

struct PostResult {
  ArrivalData data;
  std::vector<Pore> pores;
  std::string pore_source;
  CrackNetwork network;
  std::vector<TipPath> tips;
  std::vector<SpeedSample> speeds;
  std::vector<PoreVisit> pore_visits;
  double rayleigh_speed = 0;      // [m/s]
  int window_steps = 0;
  double window_seconds = 0;
  std::string postdir;
  std::string main_picture;       // damage map with the tip paths
  std::string speed_table;        // crack_speed.csv
  std::vector<std::string> pictures;
  std::vector<std::string> notes; // what was assumed or left out
};

// Analysis only (no files written).
PostResult analyse(const PostOptions& options);

// Analysis plus every output file in the post directory.
PostResult run_post(const PostOptions& options);

}  // namespace pd::post
