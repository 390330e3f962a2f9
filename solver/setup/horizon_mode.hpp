#pragma once
// How a run treats the particles' horizons (theory.md Sec. 6), decided once
// from the particle file and the scene:
//   uniform       - one horizon: the constant-horizon set-up of Secs. 1-5,
//                   lattice sweep and all;
//   dual_horizon  - model.dual_horizon = true: each directed bond i -> j with
//                   i's own constants, its reaction on j (Ren et al. 2017);
//                   PMB and, in dynamic runs, OSB (theory.md Sec. 6.8);
//   ordinary_variable - model.dual_horizon = false with horizons that differ:
//                   ordinary PD (PMB only), each particle with its own constants and no
//                   reaction, which has ghost forces where the horizon changes
//                   (kept to show them, theory.md Sec. 6.3).
// Ordinary PD and dual-horizon OSB run on neighbour lists
// (variable_horizon_bonds.hpp); dual-horizon PMB sends the constant-horizon
// squares through the lattice sweep (theory.md Sec. 6.7).
#include <string>

#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::solver {

enum class HorizonMode { uniform, dual_horizon, ordinary_variable };

const char* to_string(HorizonMode mode);

// The largest horizon of the set [m] (the constants the plan prints are its).
double largest_horizon(const ParticleSet& particles);

// The mode of `scene` on `particles`; pd::Error naming the scene file and key
// when the combination is not available: horizons that differ without
// model.dual_horizon, ordinary PD with variable horizons for a model other
// than PMB, variable horizons with the surface correction; in a quasi-static
// scene anything but PMB with dual horizons without damage on the neighbour
// lists.
HorizonMode horizon_mode(const Scene& scene, const ParticleSet& particles);

}  // namespace pd::solver
