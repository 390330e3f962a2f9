#pragma once
// What every model reports about itself: the plan, summary.json and the
// output files' field data take it from here, whatever the model.
#include <string>
#include <utility>
#include <vector>

namespace pd::solver {

struct ModelSummary {
  std::string name;                // model.type in the scene
  std::string description;         // for the plan, e.g. "PMB bond-based"
  double horizon = 0;              // delta [m]
  double critical_stretch = 0;     // s0 [-]
  double model_poisson_ratio = 0;  // the Poisson ratio the model represents
  // Named constants for summary.json, SI units in the names.
  std::vector<std::pair<std::string, double>> constants;
  // The same, one line for the plan.
  std::string constants_text;
  // How the force field runs this model when that differs from the default
  // kernel choice (for the plan); empty otherwise.
  std::string kernel_note;
};

}  // namespace pd::solver
