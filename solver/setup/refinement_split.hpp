#pragma once
// The split of adaptive particle refinement (theory.md Sec. 8, after Zeng
// and Zhang 2024): a square particle becomes four children at the centres of
// its quarters, with a quarter of its area and half its side and horizon; a
// free cell (a triangle or quadrilateral, one edge perhaps curved) four
// children on the pieces its edges' midpoints cut (theory.md Sec. 8.2).
// After a split every family is rebuilt with the discretisation library's
// FamilyBuilder, exact partial volumes for each particle's own horizon,
// keeping only bonds whose ends' origins were bonded before (no bond appears
// through a hole, a notch or an opened crack that the old set had closed off).
//
// The run's driver (runs/adaptive_refinement.hpp) decides which particles
// split and carries the motion over with the functions below.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "cell_disk_memo.hpp"
#include "geometry.hpp"
#include "particle_file.hpp"

namespace pd::solver {

// One refinement event of a run: at which step and time, and which particles
// (indices in the set before the event, sorted) split. A run's list of
// events rebuilds its refined set from the particle file (a restart).
struct SplitEvent {
  long step = 0;
  double time = 0;  // [s]
  std::vector<std::uint32_t> parents;
};

// A particle set after a split and where each particle came from.
struct SplitResult {
  ParticleSet particles;              // with cells and families
  std::vector<std::uint32_t> origin;  // per particle: its index before the split (a child: its parent's)
  std::vector<std::uint8_t> is_child; // per particle: 1 if it was born in this split
  std::size_t families_built = 0;     // families the FamilyBuilder built (the others kept theirs)
  // Per particle: 1 if the FamilyBuilder built its family, 0 if it is its
  // origin's family with the new indices (to neighbours that did not split).
  std::vector<std::uint8_t> rebuilt;
};

// Whether particle i's cell is an axis-aligned square (four vertices, equal
// sides along x and y): the lattice's cells, quartered at their quarter
// centres (and the only cells a lattice sweep can hold).
bool is_square_cell(const ParticleSet& particles, std::size_t i);

// Whether particle i's cell can split: a square, or a free cell (the gmsh
// cells of NB-NUG boxes) with three or four corners, its edges straight or,
// along a curved boundary, polylines (theory.md Sec. 8.2). Other polygons
// stay as they are.
bool can_split_cell(const ParticleSet& particles, std::size_t i);

// Side of a square cell [m].
double square_side(const ParticleSet& particles, std::size_t i);

// Offsets of the four children from their parent's centre for a square of
// side D [m]: (-D/4, -D/4), (D/4, -D/4), (-D/4, D/4), (D/4, D/4), in this order.
std::array<Vec2, 4> child_offsets(double side);

// Which families a split builds again with the FamilyBuilder: `local`, the
// children's and those of the particles bonded to a parent (the others keep
// theirs, with the new indices: theory.md Sec. 8.3), or `whole`, every one. Both give the same
// families; `whole` is the reference the local rebuild is tested against.
enum class FamilyRebuild { local, whole };

// Splits `parents` (sorted, unique, cells that can split; pd::Error otherwise) of
// `particles` (with cells and families). The other particles keep their
// order, then the children follow, four per parent in parent order.
// Boundary sets hold a parent's children in its place. Families rebuilt.
// `partial_areas` (optional): the partial areas of four-vertex cells kept
// from earlier splits of the run, to look up and to keep new ones in.
SplitResult split_particles(const ParticleSet& particles, const std::vector<std::uint32_t>& parents,
                            FamilyRebuild mode = FamilyRebuild::local, CellDiskMemo* partial_areas = nullptr);

// Per-particle values carried to the split set: every particle takes its
// origin's value (a child its parent's: velocity, damage arrival times).
// `values` holds `blocks` arrays of the old particle count one after another
// (the arrival times: one block per damage threshold).
std::vector<double> values_by_origin(const std::vector<double>& values, const std::vector<std::uint32_t>& origin,
                                     std::size_t blocks = 1);

// Each particle's partners in a list of broken pairs (i < j), sorted per
// particle: who a particle is no longer bonded to.
class BrokenPartners {
 public:
  BrokenPartners(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs, std::size_t particle_count);
  const std::uint32_t* begin(std::uint32_t i) const { return partner_.data() + first_[i]; }
  const std::uint32_t* end(std::uint32_t i) const { return partner_.data() + first_[i + 1]; }

 private:
  std::vector<std::uint64_t> first_;
  std::vector<std::uint32_t> partner_;
};

// Displacements [m] of the split set: a particle that did not split keeps its
// own; a child takes its parent's plus the parent's displacement gradient
// (the least-squares gradient of its family, displacement_gradient.hpp)
// applied to its offset, u_c = u_p + G_p (X_c - X_p), so that under a
// homogeneous deformation every bond keeps its stretch and none breaks by the
// split itself. `before` is the set the displacements `ux`, `uy` belong to.
// A parent with `by_intact_bonds[parent]` set takes the gradient over its
// intact bonds only, its `broken` partners left out (unless the rest spans no
// area): a crack's opening in its family then does not stretch its
// children's bonds (theory.md Sec. 8.2).
std::pair<std::vector<double>, std::vector<double>> displacements_after_split(
    const ParticleSet& before, const std::vector<double>& ux, const std::vector<double>& uy, const SplitResult& split,
    const BrokenPartners* broken = nullptr, const std::vector<std::uint8_t>* by_intact_bonds = nullptr);

// Pairs (i < j, sorted) of the split set whose bonds are born broken: those
// whose origins' pair was broken before (`broken_before`: pairs of the old
// set, i < j, sorted), so that the crack the old set held stays open. Siblings
// are never a broken pair.
std::vector<std::pair<std::uint32_t, std::uint32_t>> inherited_broken_pairs(
    const SplitResult& split, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& broken_before);

}  // namespace pd::solver
