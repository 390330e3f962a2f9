#include "particle_state.hpp"

namespace pd::solver {

void release_set_up_geometry(ParticleSet& particles) {
  std::vector<std::uint64_t>().swap(particles.cell_offsets);
  std::vector<double>().swap(particles.cell_vx);
  std::vector<double>().swap(particles.cell_vy);
  std::vector<std::uint64_t>().swap(particles.family_offsets);
  std::vector<std::uint32_t>().swap(particles.neighbors);
  std::vector<double>().swap(particles.partial_volume);
}

ParticleSet copy_without_set_up_geometry(const ParticleSet& p) {
  // Every member of ParticleSet but the six arrays release_set_up_geometry frees.
  ParticleSet c;
  c.grid = p.grid;
  c.quadrature = p.quadrature;
  c.spacing = p.spacing;
  c.horizon_nominal = p.horizon_nominal;
  c.xmin = p.xmin, c.ymin = p.ymin, c.xmax = p.xmax, c.ymax = p.ymax;
  c.x = p.x;
  c.y = p.y;
  c.volume = p.volume;
  c.cell_size = p.cell_size;
  c.horizon = p.horizon;
  c.region = p.region;
  c.material = p.material;
  c.sets = p.sets;
  c.provenance = p.provenance;
  return c;
}

ParticleState state_at_rest(ParticleSet particles, std::size_t threshold_count) {
  ParticleState s;
  const std::size_t n = particles.size();
  release_set_up_geometry(particles);
  // The horizons served the set-up (bonds, the lattice, the model's
  // constants, all built by now); the run reports the model's.
  std::vector<double>().swap(particles.horizon);
  s.reference = std::move(particles);
  s.motion.ux.assign(n, 0.0);
  s.motion.uy.assign(n, 0.0);
  s.motion.vx.assign(n, 0.0);
  s.motion.vy.assign(n, 0.0);
  s.motion.fx.assign(n, 0.0);
  s.motion.fy.assign(n, 0.0);
  s.damage.assign(n, 0.0);
  s.arrival.assign(threshold_count * n, -1.0);
  return s;
}

}  // namespace pd::solver
