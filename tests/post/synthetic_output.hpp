#pragma once
// Synthetic solver outputs for the pd-post tests: a square lattice of
// particles (optionally with circular holes) and an arrival-time field whose
// crack speed, branching and pore trapping are known in closed form.
#include <functional>
#include <string>
#include <vector>

namespace pd::post::test {

struct Hole {
  double x, y, r;  // [m]
};

struct Lattice {
  double width = 20e-3, height = 10e-3, spacing = 0.1e-3;  // [m]
  std::vector<double> x, y;
};

// Cell centres (i + 1/2, j + 1/2) * spacing, leaving out those inside a hole.
Lattice make_lattice(double width, double height, double spacing, const std::vector<Hole>& holes = {});

// PMMA-like constants of the synthetic runs.
inline constexpr double test_time_step = 2e-8;   // [s]
inline constexpr double test_youngs = 3.24e9;    // [Pa]
inline constexpr double test_density = 1190;     // [kg/m^3]
inline constexpr double test_nu = 0.35;

// First solver step time at or after t (damage is recorded once per step).
double on_step(double t);

// Writes DIR/arrival.vtp. `arrival(x, y)` gives the exact arrival time [s]
// or -1; it is stored under the threshold's array name after rounding up to
// a step. Damage = 1 where cracked. `thresholds` lists the arrays written
// (all with the same times).
void write_arrival_output(const std::string& dir, const Lattice& lattice,
                          const std::function<double(double, double)>& arrival,
                          double end_time, const std::vector<double>& thresholds = {0.35});

// A fresh empty directory under the test build folder.
std::string fresh_dir(const std::string& name);

}  // namespace pd::post::test
