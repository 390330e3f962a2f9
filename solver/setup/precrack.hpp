#pragma once
// Pre-cracks: line segments; every bond whose segment crosses one is broken at t = 0.
//
// Rule for bonds that touch a crack line (docs/scenes.md, "precracks"):
// a particle lying on the crack's supporting line (within 1e-9 of the bond
// length) counts as lying on the left-hand side of the crack direction
// from -> to (for a crack running in +x: above it). So a bond from a particle
// on the line to a particle strictly on the right-hand side is cut, a bond to
// a particle on the left-hand side or on the line is not. A crack end point
// lying exactly on a bond cuts that bond (the crack segment is closed).
#include <cstdint>
#include <vector>

#include "compact_families.hpp"
#include "geometry.hpp"
#include "scene.hpp"

namespace pd::solver {

bool bond_crosses_crack(Vec2 particle_i, Vec2 particle_j, const PrecrackSpec& crack);

// The particles with a bond that crosses a crack (sorted, unique). Their
// families must be lists (Families::make_listed) before apply_precracks.
std::vector<std::uint32_t> particles_cut_by(const ParticleSet& particles, const Families& families,
                                            const std::vector<PrecrackSpec>& cracks);

// Sets listed_intact[b] = 0 for every (listed) bond crossing any crack;
// returns the number of directed bonds cut.
std::size_t apply_precracks(const ParticleSet& particles, const Families& families,
                            const std::vector<PrecrackSpec>& cracks, std::vector<std::uint8_t>& listed_intact);

}  // namespace pd::solver
