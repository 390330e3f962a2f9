#pragma once
// The per-particle arrays of a run, with one owner (docs/solver.md, "State").
// The solution methods (dynamics/, statics/) and the kernels work on it; the
// reference configuration is the particle file's data, kept without its
// families and cells once the bonds are set up.
#include <cstddef>
#include <vector>

#include "particle_file.hpp"

namespace pd::solver {

// Displacements [m] (the current position is reference + displacement;
// keeping the displacement itself loses no digits to the positions'
// magnitude), velocities [m/s] and force densities [N/m^3], structure of arrays.
struct Kinematics {
  std::vector<double> ux, uy;  // displacement
  std::vector<double> vx, vy;  // velocity
  std::vector<double> fx, fy;  // force density: internal (the model's bond forces), plus body forces
};

struct ParticleState {
  // The reference configuration: positions x, y [m], cell areas `volume`
  // [m^2], cell sizes, boundary sets, grid description. Families and cell
  // polygons are dropped after set-up (the bonds are the force field's), and
  // so are the per-particle horizons (the model holds the run's).
  ParticleSet reference;
  Kinematics motion;
  std::vector<double> damage;   // D_i = 1 - sum intact phi A / sum phi A [Peng et al. 2023, Eq. (10)]; all 0 without damage
  std::vector<double> arrival;  // arrival[t * n + i]: first time D_i >= threshold t [s], -1 if never

  std::size_t size() const { return reference.x.size(); }
  const std::vector<double>& x0() const { return reference.x; }  // reference positions [m]
  const std::vector<double>& y0() const { return reference.y; }
  const std::vector<double>& area() const { return reference.volume; }  // cell areas [m^2]
};

// Frees the cell polygons and the listed families of `particles`, which only
// the bond set-up reads (bond weights, families): a run's set-up lets them go
// as soon as it is done, before the force field is built (for a dx square
// the polygon alone is 72 bytes).
void release_set_up_geometry(ParticleSet& particles);
// A copy of `particles` without them: what a run keeps of a set whose owner
// keeps the set whole (adaptive refinement), for half the copying or less.
ParticleSet copy_without_set_up_geometry(const ParticleSet& particles);

// `particles` as the reference configuration of a state at rest (zero
// displacements, velocities, forces, damage; arrival times -1 for
// `threshold_count` thresholds). Families and cell polygons are not kept
// (release_set_up_geometry).
ParticleState state_at_rest(ParticleSet particles, std::size_t threshold_count);

}  // namespace pd::solver
