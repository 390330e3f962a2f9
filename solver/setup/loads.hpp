#pragma once
// Loads resolved against a particle set: which particles each load acts on,
// and for tractions the equivalent body-force density (docs/scenes.md).
#include <cstdint>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::solver {

// Particles of a region: a named set of the particle file, "all", or the
// particles whose centres lie in the closed box. pd::Error names `key` and the
// scene file for an unknown set or an empty region.
std::vector<std::uint32_t> resolve_region(const RegionSpec& region, const ParticleSet& particles,
                                          const std::string& scene_path, const std::string& key);

struct ResolvedLoad {
  LoadSpec spec;
  std::vector<std::uint32_t> particles;
  // Traction only. The traction t [Pa] acts on an edge of length L [m]; it is
  // spread as a uniform body-force density b = t L / sum_{i in set} A_i [N/m^3]
  // over the set's particles, so the resultant b sum A_i h = t L h [N] is exact.
  double edge_length = 0;      // L [m]
  double body_force_x = 0;     // b_x at f(t) = 1 [N/m^3]
  double body_force_y = 0;
  bool constrains_motion() const {
    return spec.kind == LoadKind::velocity || spec.kind == LoadKind::displacement || spec.kind == LoadKind::fixed;
  }
};

// Per constrained or traction load: resultant of the internal forces on its
// particles.
struct LoadResultant {
  double reaction_x = 0, reaction_y = 0;  // [N]: minus the internal force resultant on the set
                                           // (= the applied resultant for a traction)
};

std::vector<ResolvedLoad> resolve_loads(const Scene& scene, const ParticleSet& particles);

// Default loaded edge length of a traction set: the longer side of the
// bounding box of the set's cells (centre +- cell_size / 2).
double set_edge_length(const ParticleSet& particles, const std::vector<std::uint32_t>& set);

}  // namespace pd::solver
