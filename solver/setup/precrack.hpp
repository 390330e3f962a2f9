#pragma once
// Pre-cracks: line segments; every bond that crosses one is broken at t = 0.
//
// The rule (docs/scenes.md, "precracks"; theory.md Sec. 1.5): a bond is cut
// when its particles lie on different sides of the crack's line and the bond
// meets that line on the open segment (from, to): between the end points,
// not at either end. So the bonds cut by a crack of length a along a lattice
// are those crossing in (0, a), whether its ends fall on a particle, a cell
// edge or between: an end on a round number does not cut the extra row of
// bonds that pass exactly through it, and a crack cuts the same bonds drawn
// either way. Where several cracks end at one point (a crack drawn as two
// halves from its centre, or two cracks end to end) the first of them in the
// scene includes that point, so that the point is cut once, as inside one
// crack.
// Touching cases: a particle lying on the crack's line counts as lying on its
// left-hand side (for a crack running in +x: above it); a bond meeting the
// line within the tolerance of an end point meets it at that end point.
// Distances are compared to 1e-6 of the bond length (far below any spacing,
// far above the round-off of coordinates). Both directions of a pair get the
// same answer (the arithmetic does not depend on the bond's direction).
#include <cstdint>
#include <string>
#include <vector>

#include "compact_families.hpp"
#include "geometry.hpp"
#include "scene.hpp"

namespace pd::solver {

// Which end points belong to a crack: a bond meeting its line exactly there is cut.
struct CrackEnds {
  bool from = false, to = false;
};

// The ends each crack of a scene includes (see above): none, except at a
// point where several cracks end, which the first of them includes.
std::vector<CrackEnds> included_ends(const std::vector<PrecrackSpec>& cracks);

bool bond_crosses_crack(Vec2 particle_i, Vec2 particle_j, const PrecrackSpec& crack, CrackEnds ends = {});

// A bound of the length of every bond of `families` [m]: the longest of
// the stencils' bonds and of the listed bonds. The pre-cracks look for cut
// bonds within it of a crack; any larger bound finds the same bonds.
double longest_bond(const ParticleSet& particles, const Families& families);
// The longest listed bond of the particles with only[i] != 0 (all when null) [m].
double longest_listed_bond(const ParticleSet& particles, const Families& families,
                           const std::vector<std::uint8_t>* only);

// The particles with a bond that crosses a crack (sorted, unique). Their
// families must be lists (Families::make_listed) before apply_precracks.
// pd::Error naming `scene_path` when a crack crosses no bond at all (it lies
// outside the plate or in a hole, or its coordinates are not in metres),
// unless `bonds_cut` is given: it then receives each crack's count of
// directed bonds cut, for a part of the plate (a slab's band) whose caller
// checks the whole plate's (require_precrack_cuts). `longest`: a bound of
// the bonds' lengths (longest_bond) if the caller has one, else 0.
std::vector<std::uint32_t> particles_cut_by(const ParticleSet& particles, const Families& families,
                                            const std::vector<PrecrackSpec>& cracks, const std::string& scene_path,
                                            std::vector<std::uint64_t>* bonds_cut = nullptr, double longest = 0);

// The error above when a crack's count in `bonds_cut` is 0 (`particles`: for
// the plate's bounds in the message).
void require_precrack_cuts(const std::vector<std::uint64_t>& bonds_cut, const ParticleSet& particles,
                           const std::vector<PrecrackSpec>& cracks, const std::string& scene_path);

// Sets listed_intact[b] = 0 for every (listed) bond crossing any crack;
// returns the number of directed bonds cut. `longest`: as above.
std::size_t apply_precracks(const ParticleSet& particles, const Families& families,
                            const std::vector<PrecrackSpec>& cracks, std::vector<std::uint8_t>& listed_intact,
                            double longest = 0);

}  // namespace pd::solver
