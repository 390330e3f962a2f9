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
#include <functional>
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

// One bond a pre-crack cuts: the crack (its index in the scene), the bond's
// owner and its place in the owner's family (in family order, as
// Families::for_each_bond and the particle set's lists hand it over).
struct CutBond {
  std::uint32_t crack = 0, owner = 0, place = 0;
  bool operator<(const CutBond& o) const {
    return owner != o.owner ? owner < o.owner : place != o.place ? place < o.place : crack < o.crack;
  }
  bool operator==(const CutBond& o) const { return crack == o.crack && owner == o.owner && place == o.place; }
};

// The bonds the pre-cracks cut in a particle set. A bond crossing two
// cracks is there once per crack.
struct PrecrackCuts {
  std::size_t particle_count = 0;
  std::vector<CutBond> bonds;  // sorted (CutBond::operator<: by owner, place, crack)
  // The owners and the neighbours of the cut bonds (sorted, unique): their
  // families are lists (Families::make_listed) before apply_precrack_cuts.
  std::vector<std::uint32_t> particles;
  double reach = 0;               // a bound of every bond's length of the set [m] (0 without cracks)
  std::uint64_t bonds_tested = 0;  // bonds tested against the cracks (the others taken over)
};

// A bound of the length of every bond of `families` [m]: the longest of
// the stencils' bonds and of the listed bonds. The pre-cracks look for cut
// bonds within it of a crack; any larger bound finds the same bonds.
double longest_bond(const ParticleSet& particles, const Families& families);

// The cut bonds of every family, each crack tested against the bonds of the
// particles within PrecrackCuts::reach (longest_bond) of it. pd::Error
// naming `scene_path` when a crack crosses no bond at all (it lies outside
// the plate or in a hole, or its coordinates are not in metres), unless
// `bonds_cut` is given: it then receives each crack's count of directed
// bonds cut, for a part of the plate (a slab's band) whose caller checks the
// whole plate's (require_precrack_cuts).
PrecrackCuts precrack_cuts(const ParticleSet& particles, const Families& families,
                           const std::vector<PrecrackSpec>& cracks, const std::string& scene_path,
                           std::vector<std::uint64_t>* bonds_cut = nullptr);

// The cut bonds of a particle set after an adaptive refinement event, from
// its own lists of families (ParticleSet::neighbors), before its compact
// families are collected (theory.md Sec. 8.8). `same_family[i]`: the
// particle of the earlier set whose family particle i has with the new
// indices (the split copied it), or Families::none (built again); `before`:
// the earlier set's cuts. A copied family has the same bonds in the same
// order between particles at the same places: its cut bonds are its earlier
// particle's. Only the built families are tested. The same bonds and
// particles as precrack_cuts on the new set (tested), and the same error.
PrecrackCuts precrack_cuts_after_event(const ParticleSet& particles, const std::vector<PrecrackSpec>& cracks,
                                       const std::string& scene_path, const PrecrackCuts& before,
                                       const std::vector<std::uint32_t>& same_family);

// The error above when a crack's count in `bonds_cut` is 0 (`particles`: for
// the plate's bounds in the message).
void require_precrack_cuts(const std::vector<std::uint64_t>& bonds_cut, const ParticleSet& particles,
                           const std::vector<PrecrackSpec>& cracks, const std::string& scene_path);

// Sets listed_intact[b] = 0 for every cut bond (listed: a cut bond of a
// stencil family is a pd::Error); returns the number of directed bonds cut.
std::size_t apply_precrack_cuts(const Families& families, const PrecrackCuts& cuts,
                                std::vector<std::uint8_t>& listed_intact);

// The pieces a particle set falls into when only its intact bonds hold it
// together (a listed bond with listed_intact[b] == 0 holds nothing): one
// for a plate in one piece. A pre-crack drawn across the whole plate, or a
// family emptied by cuts, makes more. `largest`: the particle counts of up to
// the three largest pieces, largest first.
struct PlatePieces {
  std::size_t count = 0;
  std::vector<std::size_t> largest;
};
PlatePieces plate_pieces(const Families& families, const std::vector<std::uint8_t>& listed_intact);

// The same on several processes, each holding its owned particles' families
// (local numbering: owned particles 0 .. owned_count - 1, then ghosts;
// `global_id` their indices in the particle file). Collective through
// `exchange` (the run's communicator). `count` on every process, `largest`
// on the root only.
struct PieceExchange {
  std::function<void(std::vector<double>&)> update_ghost_values;  // the owners' values overwrite the ghosts'
  std::function<bool(bool)> any;                                 // true on all if true on one
  std::function<std::uint64_t(std::uint64_t)> sum;
  // The owned values of all processes in the particle file's order, on the root (empty elsewhere).
  std::function<void(const double* owned, std::size_t owned_count, std::vector<double>& whole)> gather_owned;
};
PlatePieces plate_pieces_on_processes(const Families& families, const std::vector<std::uint8_t>& listed_intact,
                                      const std::vector<std::uint32_t>& global_id, std::size_t owned_count,
                                      const PieceExchange& exchange);

}  // namespace pd::solver
