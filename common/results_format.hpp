#pragma once
// Names shared by the solver (writer) and the post tool (reader) for the
// files of a solver output directory. docs/formats.md describes them.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "units.hpp"

namespace pd::results {

inline constexpr const char* summary_file = "summary.json";
inline constexpr const char* energy_file = "energy.csv";
inline constexpr const char* snapshot_collection = "snapshots.pvd";
inline constexpr const char* snapshot_folder = "snapshots";
// Per-particle damage arrival times plus the final state and the material.
inline constexpr const char* arrival_file = "arrival.vtp";
// The last column of energy.csv: the particle count at the row (it changes
// with adaptive refinement; runs of earlier versions have no such column).
inline constexpr const char* energy_particles_column = "particles";

// The first 256 bytes of a regular file (fewer if it is shorter; none if it
// is no regular file: a FIFO would block the read).
inline std::string file_head(const std::filesystem::path& file) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) return {};
  std::ifstream in(file, std::ios::binary);
  char head[256] = {};
  in.read(head, sizeof head);
  return std::string(head, static_cast<std::size_t>(in.gcount()));
}

// Whether `file` is a summary.json that pd-solve wrote: pd-solve names
// itself in every one ("tool": "pd-solve 0.1.0", near its start), which
// pd-post's own summary.json and a user's file do not.
inline bool summary_by_solver(const std::filesystem::path& file) {
  const std::string text = file_head(file);
  return text.rfind("{", 0) == 0 && text.find("\"tool\": \"pd-solve") != std::string::npos;
}

// Point arrays of arrival.vtp (reference configuration).
inline constexpr const char* volume = "volume";
inline constexpr const char* cell_size = "cell_size";
inline constexpr const char* damage = "damage";
inline constexpr const char* strain_energy_density = "strain_energy_density";  // J/m^3
inline constexpr const char* displacement = "displacement";                      // m, 3 components
inline constexpr const char* velocity = "velocity";                              // m/s, 3 components
// Arrival time [s] of damage >= threshold, or -1 if never reached; one array
// per threshold, named by arrival_array_name.
inline constexpr const char* arrival_prefix = "arrival_time_";
// "arrival_time_0.35": the threshold with two decimals where they give it
// back exactly, else with as many digits as do ("arrival_time_0.354",
// "arrival_time_1e-300"), so that every threshold has a name of its own
// which reads back as that threshold. (Two decimals alone named 0.001 and
// 1e-300 "arrival_time_0.00", and 0.354 "arrival_time_0.35", which pd-post
// then took for the crack at 0.35.)
inline std::string arrival_array_name(double threshold) {
  char two_decimals[48];
  std::snprintf(two_decimals, sizeof two_decimals, "%.2f", threshold);
  const bool exact = std::strtod(two_decimals, nullptr) == threshold;
  return arrival_prefix + (exact ? std::string(two_decimals) : shortest_text(threshold));
}

// Field data (one value each unless noted) of arrival.vtp and snapshots.
inline constexpr const char* field_time = "time";                    // s
inline constexpr const char* field_step = "step";
inline constexpr const char* field_youngs_modulus = "youngs_modulus";  // Pa
inline constexpr const char* field_density = "density";                // kg/m^3
inline constexpr const char* field_poisson_ratio = "poisson_ratio";    // of the model (1/3 or 1/4 for PMB)
inline constexpr const char* field_material_poisson_ratio = "material_poisson_ratio";  // as given (for c_R)
inline constexpr const char* field_time_step = "time_step";            // s
inline constexpr const char* field_thresholds = "damage_thresholds";   // several values
inline constexpr const char* field_end_time = "end_time";              // s, time of the last step
inline constexpr const char* field_horizon = "horizon";                // m
inline constexpr const char* field_spacing = "spacing";                // m
inline constexpr const char* field_plane_strain = "plane_strain";      // 1 plane strain, 0 plane stress
// The run's identifier (16 hex digits, a string array of one value; also
// summary.json's "run_id", since 7 December 2026 the last column of
// energy.csv and load_steps.csv, the same on every row, and the attribute
// run_id of snapshots.pvd's Collection element): every file of one run
// carries the same, so that pd-post tells a file copied in from another run
// (docs/formats.md, "Run identifier"). Files of earlier runs have none.
inline constexpr const char* field_run_id = "run_id";

// Quasi-static runs (docs/solver.md, "Quasi-static mode").
inline constexpr const char* load_steps_file = "load_steps.csv";    // one row per load step
inline constexpr const char* final_state_file = "final_state.vtp";  // reference positions, final state
// Load factor at which a particle first had damage, -1 if never (final_state.vtp).
inline constexpr const char* damage_load_factor = "damage_load_factor";
inline constexpr const char* field_load_factor = "load_factor";
// pd-post's default folder inside the output directory (docs/post.md).
inline constexpr const char* post_folder = "post";
// Whether a file name is one pd-post writes there: its summary.json, tables
// and pictures (damage_*, strain_energy_*, displacement_x_*, displacement_y_*
// maps at any time or load factor). A fresh or continued pd-solve run
// removes these, which show the earlier results; other files stay.
inline bool is_post_output(const std::string& name) {
  for (const char* fixed : {"summary.json", "crack_speed.csv", "crack_tips.csv", "branches.csv", "branching_events.csv",
                            "pore_trapping.csv", "line_profile.csv", "line_profile.png", "reactions.csv",
                            "reactions.png", "speed_vs_time.png", "speed_vs_x.png", "cell_size_final.png"})
    if (name == fixed) return true;
  const bool png = name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0;
  for (const char* map : {"damage_", "strain_energy_", "displacement_x_", "displacement_y_"})
    if (png && name.rfind(map, 0) == 0) return true;
  return false;
}
// The files of pd-post's names (is_post_output) in `folder`, where its
// summary.json is pd-post's (names the tool in its first bytes); none
// otherwise, so that a folder of the user's keeps its files whatever their
// names. Removed by a fresh or continued pd-solve run (OUTDIR/post) and by
// pd-post itself before it writes a folder again (a picture of an earlier
// --times would otherwise stay beside the new ones).
inline std::vector<std::filesystem::path> post_outputs_in(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  std::error_code error;
  if (!std::filesystem::is_regular_file(folder / summary_file, error)) return files;
  std::ifstream summary(folder / summary_file, std::ios::binary);
  char head[256] = {};
  summary.read(head, sizeof head);
  if (std::string(head, static_cast<std::size_t>(summary.gcount())).find("\"tool\": \"pd-post") == std::string::npos)
    return files;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error))
    if (is_post_output(entry.path().filename().string())) files.push_back(entry.path());
  return files;
}
// Folder inside the output directory of a scene that switches from
// quasi-static to dynamic, with the files of the quasi-static part.
inline constexpr const char* quasi_static_part_folder = "quasi_static";
}  // namespace pd::results
