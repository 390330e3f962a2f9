#include "c2_fracture.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>

#include "plate_grid.hpp"

namespace pd::validation {

HoleRing c2_ring(double hole_cx, double hole_cy, double hole_radius, double horizon) {
  HoleRing ring;
  ring.cx = hole_cx;
  ring.cy = hole_cy;
  ring.radius = hole_radius;
  ring.inner = 0.5 * horizon;
  ring.outer = 2 * horizon;
  ring.max_gap = 0.5 * horizon;
  ring.damage_threshold = 0.3;
  return ring;
}

C2Result run_c2(const ParticleSet& particles, double hole_cx, double hole_cy, double hole_radius,
                const C1Material& material, const C2Options& options, std::ostream& log) {
  const auto start = std::chrono::steady_clock::now();
  solver::Scene s;
  s.path = "C2 (validation)";
  s.particle_file = "in-memory";
  s.material.youngs_modulus = material.youngs_modulus;
  s.material.fracture_energy = material.fracture_energy;
  s.effects.damage = true;
  s.effects.surface_correction = options.surface_correction;
  s.bond_weights = options.bond_weights;
  auto& q = s.quasi_static;
  q.enabled = true;
  q.tolerance = options.tolerance;
  q.max_iterations = options.max_iterations;
  q.max_breaking_rounds = 100000;
  q.stop_reaction_fraction = options.stop_reaction_fraction;
  // The load factor is the displacement of each edge in metres (load values +-1 m).
  double u = 0;
  for (int k = 0; k < options.first_steps; ++k) q.load_factors.push_back(u += options.first_increment);
  for (int k = 0; k < options.max_small_steps; ++k) q.load_factors.push_back(u += options.small_increment);
  s.loads = opposite_edge_displacements(1.0);
  solver::QuasiStaticProblem problem(s, particles);
  C2Result out;
  const auto observer = [&](const solver::QuasiStaticProblem& p, const std::vector<double>&,
                            const solver::LoadStepRecord& r) {
    const double reaction = solver::axial_reaction(r, p.loads()) / s.material.thickness;
    out.peak_reaction = std::max(out.peak_reaction, reaction);
    if (r.broken_bonds > 0 && out.first_damage_displacement < 0) out.first_damage_displacement = r.load_factor;
    if (r.pairs_broken > 0 || r.step % 10 == 0)
      log << "  step " << r.step << ": u = " << r.load_factor * 1e3 << " mm, " << r.minimisations
          << " minimisations, " << r.iterations << " iterations, " << r.pairs_broken << " bonds broken, reaction "
          << reaction << " N/m\n"
          << std::flush;
  };
  const auto result = solver::solve_quasi_static(problem, s, {}, log, observer);
  out.steps = result.steps;
  out.damage = result.damage;
  out.damage_load_factor = result.damage_load_factor;
  out.stop_reason = result.stop_reason;
  const double horizon = problem.model().horizon;
  out.cracks = cracks_at_hole(particles, out.damage, out.damage_load_factor,
                              c2_ring(hole_cx, hole_cy, hole_radius, horizon));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace pd::validation
