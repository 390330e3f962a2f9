#pragma once
// The post tool's input: a solver output directory (names in
// common/results_format.hpp). arrival.vtp is required; the snapshot
// collection is optional and only used for maps at given times.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "error.hpp"

namespace pd::post {

// One damage threshold and its per-particle arrival times [s] (-1 = never).
struct ArrivalField {
  double threshold = 0;
  std::string array;  // its name in arrival.vtp
  std::vector<double> time;
};

struct ArrivalData {
  std::string path;  // the arrival.vtp that was read
  std::vector<double> x, y;             // reference positions [m]
  std::vector<double> cell_size;        // [m]
  std::vector<double> damage;           // final, in [0, 1] (vtp_input.hpp: checked_damage)
  std::vector<double> strain_energy_density;  // final [J/m^3] (empty if absent)
  std::vector<double> ux, uy;           // final displacement [m] (empty if absent)
  std::vector<ArrivalField> arrivals;   // every threshold in the file, ascending
  std::vector<double> arrival;          // the chosen threshold's arrival times [s]
  double threshold = 0;                 // the chosen threshold

  double youngs_modulus = 0;          // [Pa]
  double density = 0;                 // [kg/m^3]
  std::optional<double> model_poisson_ratio;     // field poisson_ratio: the model's (PMB: 1/3 or 1/4)
  std::optional<double> material_poisson_ratio;  // field material_poisson_ratio, when the scene gave it
  std::optional<bool> plane_strain;              // field plane_strain, when the solver wrote it
  double time_step = 0;               // [s]
  double end_time = 0;                // [s]
  long end_step = -1;                 // field step (-1 if absent)
  double horizon = 0;                 // [m]
  double spacing = 0;                 // [m]
  std::string run_id;                 // field run_id (empty: a run before 6 December 2026)
  std::vector<std::string> notes;     // fallbacks taken while reading

  std::size_t size() const { return x.size(); }
};

// Where the plate lies [m]: its particles' centres widened by the largest
// cell size (a centre lies up to half a cell inside an edge, where a notch's
// circle may be centred), for telling input in another unit from input on the plate.
struct PlateExtent {
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  bool contains(double x, double y) const { return x >= x_min && x <= x_max && y >= y_min && y <= y_max; }
  std::string text() const;  // "x 0 to 0.02 m, y 0 to 0.01 m"
};
PlateExtent plate_extent(const ArrivalData& data);

// Lengths given on the command line (a --line's ends, --line-offset,
// --band) farther than this many plate sizes beyond the plate are refused:
// in the wrong unit by far, or hostile (1e300 m).
inline constexpr double max_plate_sizes_away = 100;

// pd::Error unless `outdir` is a folder: "not found", or for a file, what
// pd-post reads instead.
void require_output_directory(const std::string& outdir);

// The most time steps a run may have for pd-post, which follows each crack
// tip at every step: a run of more is an edited or damaged file.
inline constexpr double max_tracked_steps = 1e9;

// The shear wave speeds sqrt(E / (2 (1 + nu) rho)) of solids lie between
// about 1 m/s (the softest gels, a shear modulus of 1 kPa) and 1.3e4 m/s
// (diamond): an arrival.vtp whose youngs_modulus, density and Poisson ratio
// give one outside these bounds is an edited or damaged file.
inline constexpr double min_shear_wave_speed = 1;    // [m/s]
inline constexpr double max_shear_wave_speed = 1e5;  // [m/s]

// Reads OUTDIR/arrival.vtp for `threshold`. Throws pd::Error naming the
// directory, the file or the missing array.
ArrivalData read_arrival_data(const std::string& outdir, double threshold);

// Damage at time t rebuilt from the arrival arrays alone: the largest
// threshold whose arrival time is <= t (0 if none). A staircase version of
// the true damage history, as fine as the solver's list of thresholds.
std::vector<double> damage_at_time(const ArrivalData& data, double time);

struct SnapshotEntry {
  double time = 0;         // [s] (a quasi-static run's: its load factor)
  std::string file;        // absolute or relative to the working directory
  std::string collection;  // the snapshots.pvd that lists it
};

// A snapshot in a message on what it is: "a snapshot COLLECTION lists; give
// the collection pd-solve wrote" (pd-solve lists its snapshots/ files only).
std::string snapshot_role(const SnapshotEntry& entry);

// Whether two values one run recorded in two of its files differ beyond the
// round-off of the shorter one's digits (summary.json's 12 significant
// digits; a .vtp's or a .pvd's 17); a NaN (absent) differs from nothing.
bool recorded_values_differ(double a, double b);

// pd::Error naming `path` with `what` differs from another file of the run:
// the two files are from different runs (a folder mixed by copying or moving
// files), and what to do about it.
Error mixed_runs_error(const std::string& path, const std::string& what);

// mixed_runs_error naming `path` and `other_path` with both run identifiers
// (docs/formats.md, "Run identifier") when the two files carry one each and
// they differ: a file copied in from another run of the same step, time and
// particle count. A file without one (written before 6 December 2026) is not
// compared. `key` names where `path` holds it ("\"run_id\"" in summary.json).
void check_same_run_id(const std::string& path, const std::string& run_id, const std::string& key,
                       const std::string& other_path, const std::string& other_run_id);

// The tables and the collection of OUTDIR that carry the run's identifier
// (since 7 December 2026): energy.csv's and load_steps.csv's column run_id on
// every row, snapshots.pvd's attribute run_id of its Collection element,
// whichever are there, each against `run_id`, the identifier of `run_path`
// (the run's arrival.vtp or state), by check_same_run_id: a table or
// collection copied in from another run is refused, naming its line; so is
// a row of such a table whose length is not its header's, or whose run_id is
// empty (a file cut or edited). A file without one (an earlier version's) is
// not compared; nor are any when `run_id` is empty.
void check_run_tables(const std::string& outdir, const std::string& run_path, const std::string& run_id);

// The cells of one line of a CSV table pd-solve wrote (a line ending in ','
// has an empty last cell).
std::vector<std::string> split_csv_line(const std::string& line);

// "line N: found K values, expected M, one for each column of the header":
// a row of a table pd-solve wrote (energy.csv, load_steps.csv) whose length
// is not its header's.
std::string row_length_text(int line_no, std::size_t found, std::size_t expected);

enum class RunKind { dynamic, quasi_static };

// The entries of OUTDIR/snapshots.pvd, sorted by time; empty if it is absent.
// A dynamic run's times are from 0 on, so a negative one is refused, naming
// the entry; a quasi-static run's entries are load factors, which may be.
std::vector<SnapshotEntry> list_snapshots(const std::string& outdir, RunKind kind);

// The entry whose time is nearest to `time`, the first of equals (the list
// must not be empty and must be sorted by time, as list_snapshots gives it).
const SnapshotEntry& nearest_snapshot(const std::vector<SnapshotEntry>& entries, double time);

struct SnapshotFields {
  double time = 0;                            // [s] (a quasi-static snapshot: its load factor)
  std::vector<double> damage;                 // in [0, 1]
  std::vector<double> strain_energy_density;  // [J/m^3]; empty if the snapshot has none
  std::vector<double> ux, uy;                 // displacement [m]; empty if absent
  // A snapshot of another particle set than the final one (adaptive
  // refinement: the set grows during the run) brings its own particles:
  // reference positions and cell sizes [m]; empty otherwise.
  std::vector<double> x, y, cell_size;
  std::string run_id;  // field run_id (empty if absent)
};

// mixed_runs_error naming the snapshot of `entry` when the time (or, with
// `by_load_factor`, the load factor) it records differs from the one its
// collection lists it at: a file of another run.
void check_snapshot_time(const SnapshotEntry& entry, double recorded, bool by_load_factor);

// The particles of the run's state a snapshot is drawn on (arrival.vtp's or
// final_state.vtp's): reference positions and cell sizes [m].
struct RunParticles {
  const std::string& path;
  const std::vector<double>& x;
  const std::vector<double>& y;
  const std::vector<double>& cell_size;
};

// Reads one snapshot; its particles must be those of `run` (as many, each
// within a thousandth of its cell of the run's position: a snapshot of the
// particles in another order would put each value at another particle's
// place), unless `own_particles` allows a snapshot
// with its own `cell_size` array (a refined run's), whose particles then come
// with it (x, y, cell_size; never more than `expected_points`: a refined
// run's set only grows). Field `time`, else `load_factor`, else the
// collection's time; a recorded one that differs from the collection's is
// another run's snapshot, refused naming both. Its run identifier is the
// caller's to compare (check_same_run_id), with the run's state it draws on.
SnapshotFields read_snapshot(const SnapshotEntry& entry, const RunParticles& run, bool own_particles = false);

}  // namespace pd::post
