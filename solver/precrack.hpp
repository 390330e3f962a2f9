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

#include "bonds.hpp"
#include "geometry.hpp"
#include "scene.hpp"

namespace pd::solver {

bool bond_crosses_crack(Vec2 particle_i, Vec2 particle_j, const PrecrackSpec& crack);

// Sets intact[b] = 0 for every bond crossing any crack; returns the number of directed bonds cut.
std::size_t apply_precracks(const ParticleSet& particles, const BondTable& bonds,
                            const std::vector<PrecrackSpec>& cracks, std::vector<std::uint8_t>& intact);

}  // namespace pd::solver
