#pragma once
// pd-post for a quasi-static output directory (docs/post.md, "Quasi-static
// runs"): displacement, damage and strain-energy maps of the final state (and
// at given load factors, from the snapshots), reactions against load factor
// (table and plot), values along a line, summary.json.
#include <string>
#include <vector>

#include "line_profile.hpp"
#include "post_pipeline.hpp"
#include "quasi_static_data.hpp"
#include "solver_summary.hpp"

namespace pd::post {

struct QuasiStaticPostResult {
  QuasiStaticData data;
  SolverSummary solver;
  double max_damage = 0;              // of the state drawn, in [0, 1]
  std::vector<MapAt> maps;            // at the requested load factors
  std::optional<SampleLine> line_segment;
  double line_offset = 0;             // [m]
  std::vector<LineSample> line;
  std::string postdir;
  std::string main_picture;           // displacement_y_final.png, or the reaction plot without a state
  std::string reaction_table;         // reactions.csv
  std::vector<std::string> pictures;
  std::vector<std::string> notes, warnings;
};

QuasiStaticPostResult run_quasi_static_post(const PostOptions& options);

}  // namespace pd::post
