#pragma once
// The part of a set-up one process of a distributed run works on
// (docs/solver.md, "Running on several processes (MPI)"): its local
// particles (owned ones first, then ghosts) with the bonds of the owned ones.
//
// The set-up itself (weights, pre-cracks, surface correction) is made on the
// whole plate, exactly as a one-process run makes it, or on the slab's band
// of the particle file (state/slab_band.hpp: the same numbers for every
// local particle), and then cut out here: a ghost's family is incomplete
// locally, so its directional shape must come from the whole family, which
// the set-up of the whole plate or the band sees. The local families keep
// the whole plate's lattices (cell numbers and stencils), so that an owned
// square keeps its stencil family and the lattice sweep finds every local
// particle in its cell; the lattice cells of particles that are not local
// hold none.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bond_setup.hpp"
#include "bond_table.hpp"
#include "particle_file.hpp"

namespace pd::solver {

struct LocalBonds {
  ParticleSet particles;  // the local particles' per-particle arrays and grid description (no cells, sets, families)
  BondSetup setup;        // families: the owned particles' whole families, renumbered; ghosts have none
};

// `local_ids`: the local particles' indices in `whole` (the plate or a
// band) in local order, the first `owned_count` of them owned; every
// neighbour of an owned particle must be among them.
LocalBonds local_bonds(const ParticleSet& whole, const BondSetup& whole_setup,
                       const std::vector<std::uint32_t>& local_ids, std::size_t owned_count);

// The rows of a variable-horizon run (variable_horizon_bonds.hpp) one
// process works on: the whole plate's rows of its owned particles, their
// entries in the same order with the neighbours renumbered to local ones,
// and an empty row for every ghost. With dual horizons an owned particle's
// row also holds the reactions of the bonds other particles own towards it;
// those owners are within the largest horizon, not the particle's own, and
// the partition makes them ghosts (state/partition.hpp). Cut from the whole
// table, the rows are the one-process rows bit for bit (the same xi in
// float, the same constants), so a bond's own entry and its dual entry on two
// processes see the same extension and break at the same step.
struct LocalRows {
  BondTable table;
  std::vector<std::uint8_t> intact;      // per entry (empty without damage)
  std::vector<std::uint64_t> entry_bond;  // per entry: the whole plate's directed bond whose state it carries
};

// `whole_intact` and `whole_entry_bond` (as variable_horizon_rows gives
// it) may be empty (no damage). Taken by value and freed array by array
// as each is cut (moved in, the whole table and its cut-out are not held
// together). pd::Error when an entry of an owned row names a particle that
// is not local. The rows of the particles that are not owned may hold
// anything (with dual horizons, e.g., only the entries of bonds with an
// owned end): they are not read.
// With `first_row`, only the rows of the owned particles [first_row,
// owned_count) are cut (the others empty): a piece of a process's rows,
// made from the bonds of those rows alone (joined_rows).
LocalRows local_rows(BondTable whole, std::vector<std::uint8_t> whole_intact,
                     std::vector<std::uint64_t> whole_entry_bond, const std::vector<std::uint32_t>& local_ids,
                     std::size_t owned_count, std::size_t first_row = 0);

// The pieces' rows (local_rows with first_row[k] for piece k, each cut for
// the same local particles: piece k holds the owned rows from first_row[k]
// to the next piece's first) as one process's rows, the pieces freed array
// by array as they are copied.
LocalRows joined_rows(std::vector<LocalRows> pieces, const std::vector<std::size_t>& first_row,
                      std::size_t owned_count);

// Where each particle's family starts among the bonds of `families`, taken
// family by family in particle order (as variable_horizon_rows numbers them
// in `entry_bond`), with the bond count last: particle_count + 1 values.
std::vector<std::uint64_t> family_starts(const Families& families);

}  // namespace pd::solver
