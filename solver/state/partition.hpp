#pragma once
// Which particles a process owns when a run is spread over several
// (docs/solver.md, "Running on several processes (MPI)"): slabs across the
// plate's long axis, cut so that every slab holds about the same number of
// directed bonds (the work of a force evaluation is per bond, not per
// particle: the boundary layers of holes and edges have longer lists).
//
// Why slabs: the plates are long and thin, so a slab has at most two
// neighbouring slabs and one halo on each side, and the ghost exchange is two
// messages per process. Square domains on many processes would want
// recursive bisection instead (halos shrink with the square root of the
// slab's area); the exchange below takes any owner map, so only the cut
// would change.
//
// Each process keeps its own particles and, as ghosts, every particle one of
// them has a bond to (each within its owned particle's horizon of the slab);
// with dual horizons also every particle that has a bond to one of them: the
// row of an owned particle holds the reactions of those bonds (theory.md
// Sec. 6.1), whose owners lie within their own horizons, up to the largest
// one, of the slab. Local
// numbering: the owned particles first, then the ghosts, each in the particle
// file's order; their global ids (particle file indices) are kept.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "compact_families.hpp"
#include "particle_file.hpp"

namespace pd::solver {

struct Partition {
  int rank = 0, size = 1;
  int axis = 0;                       // 0: slabs follow each other along x, 1: along y
  std::vector<double> cuts;           // size - 1 positions along the axis [m]
  std::vector<std::uint32_t> owned;   // global ids, ascending
  std::vector<std::uint32_t> ghosts;  // global ids, ascending
  std::vector<int> ghost_owner;       // the rank that owns ghosts[g]
  std::uint64_t owned_bonds = 0;      // directed bonds of the owned particles
  std::size_t whole_count = 0;        // particles of the whole plate

  std::size_t local_count() const { return owned.size() + ghosts.size(); }
  // Global ids in local order (owned, then ghosts).
  std::vector<std::uint32_t> local_ids() const;
};

// Which bonds make a particle a ghost of a slab: its owned particles' own
// bonds, or (dual horizons) also the bonds other particles own towards them.
enum class GhostReach { own_bonds, bonds_both_ways };

// Where the slabs of `size` processes meet: the long axis and the size - 1
// cuts along it. Needs the particles' positions and their family lengths
// only, which the particle file holds before its bonds (offsets), so the
// cuts are known before any family is kept. pd::Error naming `where` (the
// particle file) when there are fewer distinct positions along the long axis
// than processes.
struct SlabCuts {
  int axis = 0;              // 0: slabs follow each other along x, 1: along y
  std::vector<double> cuts;  // ascending [m]
  // The slab of a particle at `position` along the axis: the cuts below it.
  int slab_of(double position) const;
};
using FamilyLength = std::function<std::uint64_t(std::uint32_t particle)>;
SlabCuts slab_cuts(const ParticleSet& particles, const FamilyLength& family_length, int size,
                   const std::string& where);
// The family lengths a particle file announces (its family offsets, which
// the streaming reader fills before the families come).
FamilyLength file_family_lengths(const ParticleSet& particles);

// The slab of `rank` among `size` for a particle set and its families.
// pd::Error naming `where` (the particle file) when there are fewer distinct
// positions along the long axis than processes.
Partition slab_partition(const ParticleSet& particles, const Families& families, int rank, int size,
                         const std::string& where, GhostReach reach = GhostReach::own_bonds);

// The slab of `rank` among `slabs.cuts.size() + 1` on a part of the plate
// (a slab's band of the particle file, particle_band.hpp): `particles` and
// `families` in the part's numbering, `global_id` the file's index of each
// (ascending), `family_complete` whether each particle's family is whole,
// `whole_count` the file's particle count. Every owned particle's family
// must be whole, and with `reach` bonds_both_ways every ghost's too (a
// part's edge families are cut short: the particles owning a bond towards
// the slab are found, and their bonds weighed, only where their families are
// whole); pd::Error naming `where` otherwise. `part_index`: per local
// particle (owned, then ghosts), its index in the part.
Partition slab_partition_of_part(const ParticleSet& particles, const Families& families,
                                 const std::vector<std::uint32_t>& global_id,
                                 const std::vector<std::uint8_t>& family_complete, std::size_t whole_count,
                                 const SlabCuts& slabs, int rank, const std::string& where,
                                 std::vector<std::uint32_t>& part_index, GhostReach reach = GhostReach::own_bonds);

}  // namespace pd::solver
