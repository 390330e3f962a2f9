#pragma once
// Synthetic solver outputs for the pd-post tests: a square lattice of
// particles (optionally with circular holes) and an arrival-time field whose
// crack speed, branching and pore trapping are known in closed form; and
// quasi-static outputs with a displacement field of known jump.
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vtk_output.hpp"

namespace pd::post::test {

struct Hole {
  double x, y, r;  // [m]
};

struct Lattice {
  double width = 20e-3, height = 10e-3, spacing = 0.1e-3;  // [m]
  std::vector<double> x, y;
  std::vector<double> cell_size;  // [m] per particle; empty: `spacing` for all
};

// Cell centres (i + 1/2, j + 1/2) * spacing, leaving out those inside a hole.
Lattice make_lattice(double width, double height, double spacing, const std::vector<Hole>& holes = {});

// The lattice with every square whose centre has x > x_from split into its
// four quarters (as a refinement event splits them).
Lattice split_right_of(const Lattice& lattice, double x_from);

// PMMA-like constants of the synthetic runs.
inline constexpr double test_time_step = 2e-8;   // [s]
inline constexpr double test_youngs = 3.24e9;    // [Pa]
inline constexpr double test_density = 1190;     // [kg/m^3]
inline constexpr double test_nu = 0.35;          // the material's (field material_poisson_ratio)

// What else a synthetic dynamic run writes, beyond the arrival field.
struct SyntheticRun {
  SyntheticRun() {}  // not an aggregate: {0.5} stays a list of thresholds
  double time_step = test_time_step;  // [s] field time_step; arrival times are rounded up to it
  std::vector<double> thresholds = {0.35};
  // summary.json as pd-solve writes it at the end of a run (false: an
  // unfinished run), with this "plane" (empty: the key left out).
  bool summary = true;
  std::string plane = "stress";
  // Field poisson_ratio of arrival.vtp (the model's; nullopt: left out).
  std::optional<double> model_poisson_ratio = 1.0 / 3.0;
  double cracked_damage = 1.0;  // damage of the cracked particles (others 0)
  std::optional<bool> plane_strain_field;  // field plane_strain of arrival.vtp (nullopt: left out)
  // Field end_time of arrival.vtp when it is not the run's end (an edited
  // file whose arrival times pass it); nullopt: the end time given.
  std::optional<double> end_time_field;
  // Field time_step of arrival.vtp when it is not the run's (an edited file); nullopt: time_step.
  std::optional<double> time_step_field;
  // Fields youngs_modulus and density of arrival.vtp (an edited file); nullopt: the test constants.
  std::optional<double> youngs_field, density_field;
  // Field material_poisson_ratio of arrival.vtp (an edited file); nullopt: test_nu.
  std::optional<double> material_poisson_field;
  // Arrival times written as they are, not rounded to a step nor -1 for a
  // negative one (an edited file): particle index and time [s].
  std::vector<std::pair<std::size_t, double>> edited_times;
  // Fields of arrival.vtp as an edited file has them: each replaces the
  // field of its name, or is added (a text where a number belongs, too).
  std::vector<pd::FieldValue> edited_fields;
};

// First solver step time at or after t (damage is recorded once per step).
double on_step(double t, double time_step = test_time_step);

// Writes DIR/arrival.vtp (and DIR/summary.json). `arrival(x, y)` gives the
// exact arrival time [s] or -1; it is stored under every threshold's array
// name after rounding up to a step.
void write_arrival_output(const std::string& dir, const Lattice& lattice,
                          const std::function<double(double, double)>& arrival, double end_time,
                          const SyntheticRun& run);
void write_arrival_output(const std::string& dir, const Lattice& lattice,
                          const std::function<double(double, double)>& arrival,
                          double end_time, const std::vector<double>& thresholds = {0.35});

// Writes DIR/summary.json: the keys pd-post reads, as pd-solve writes them
// ("plane" left out when empty; "mode": "quasi_static" when quasi_static).
void write_solver_summary(const std::string& dir, const std::string& plane, bool quasi_static = false);

// A quasi-static output directory: load_steps.csv (the load factors, two
// loads "left" and "right" with the given reactions), final_state.vtp with
// the displacement and damage fields (if `final_state`), one snapshot per
// entry of `snapshot_factors` (the fields scaled by the snapshot's load
// factor over the last one), and summary.json (if `summary`).
struct QuasiStaticRun {
  std::vector<double> load_factors;
  std::vector<double> right_reaction_x;  // [N] per load step; left_reaction_x = minus it
  std::vector<double> max_damage;        // load_steps.csv's column per load step (empty: the damage field's largest)
  std::function<double(double, double)> ux, uy, damage;  // final state
  bool final_state = true;
  bool summary = true;
  std::vector<double> snapshot_factors;
  // Fields of final_state.vtp as an edited file has them (as SyntheticRun's edited_fields).
  std::vector<pd::FieldValue> edited_state_fields;
};
void write_quasi_static_output(const std::string& dir, const Lattice& lattice, const QuasiStaticRun& run);

// A fresh empty directory under the test build folder.
std::string fresh_dir(const std::string& name);

}  // namespace pd::post::test
