#pragma once
// Case C2 (docs/validation.md; [Peng, Chen, Bobaru 2023, Sec. 4.2]): the C1
// plate pulled apart quasi-statically with damage: equal and opposite u_x on
// the left and right strips, first in large steps, then in small ones, until
// the sample separates; the cracks that start at the hole are counted
// (hole_cracks.hpp) and their initiation displacements recorded.
#include <iosfwd>
#include <string>
#include <vector>

#include "c1_comparison.hpp"
#include "hole_cracks.hpp"
#include "load_steps.hpp"

namespace pd::validation {

struct C2Options {
  int first_steps = 8;              // large steps ...
  double first_increment = 1e-5;    // ... of 0.01 mm per edge [m]
  double small_increment = 1e-7;    // then steps of 1e-4 mm per edge [m]
  int max_small_steps = 2000;
  double stop_reaction_fraction = 0.05;  // separated when the reaction falls below 5 % of its peak
  double tolerance = 1e-6;
  long max_iterations = 50000;
  bool surface_correction = true;
  // The paper's bonds are phi_ij V_j [Peng, Chen, Bobaru 2023, Eq. (11)]; the
  // default is the solver's (docs/solver.md, "Bond weights").
  BondWeights bond_weights = BondWeights::distance_moment;
};

struct C2Result {
  std::vector<solver::LoadStepRecord> steps;  // load factor = displacement of each edge [m]
  std::vector<double> damage, damage_load_factor;
  std::vector<HoleCrack> cracks;
  std::string stop_reason;
  double peak_reaction = 0;  // [N per metre of thickness]
  double seconds = 0;
  double first_damage_displacement = -1;  // [m], first load step with any broken bond
};

// The ring in which C2's cracks are counted (docs/validation.md, "C2"):
// from delta/2 to 2 delta beyond the hole's edge, damage >= 0.3, a gap of
// more than delta/2 along the ring between two cracks.
HoleRing c2_ring(double hole_cx, double hole_cy, double hole_radius, double horizon);

// Runs C2 on the particle set (sets "left", "right") and counts the cracks in a
// ring from delta/2 to 2 delta beyond the hole's edge.
C2Result run_c2(const ParticleSet& particles, double hole_cx, double hole_cy, double hole_radius,
                const C1Material& material, const C2Options& options, std::ostream& log);

}  // namespace pd::validation
