#pragma once
// Small-strain static equilibrium of a dual-horizon PMB plate (theory.md
// Sec. 6.5), for comparisons on grids whose horizons vary (NB-NUG boxes
// meshed finer than the squares, pd-mesh --box-spacing). The solver's own
// quasi-static path assumes one horizon; this one takes the dynamic solver's
// dual-horizon bond table as it is, linearises it and solves K u = f by
// Jacobi-preconditioned conjugate gradients, with x-displacements prescribed
// on named particle sets. No surface correction and no damage (the table's
// dual-horizon form refuses both).
#include <cstdint>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::validation {

struct PrescribedX {
  std::string set;  // a boundary set of the particle file
  double ux = 0;    // [m]
};

struct LinearStaticResult {
  std::vector<double> ux, uy;        // per particle [m]
  std::vector<double> reaction_x;    // per prescribed set: sum of the constraint forces, per metre of thickness [N/m]
  long iterations = 0;
  double relative_residual = 0;      // |r| / |f| over the free unknowns
  bool converged = false;
  double setup_seconds = 0, solve_seconds = 0;
};

// `scene` gives the material, the bond weights and model.dual_horizon (it
// must be true, with PMB, surface correction off and quasi_static off).
LinearStaticResult solve_dual_horizon_static(const solver::Scene& scene, const ParticleSet& particles,
                                             const std::vector<PrescribedX>& prescribed, double tolerance,
                                             long max_iterations);

}  // namespace pd::validation
