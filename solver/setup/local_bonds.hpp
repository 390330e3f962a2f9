#pragma once
// The part of a set-up one process of a distributed run works on
// (docs/solver.md, "Running on several processes (MPI)"): its local
// particles (owned ones first, then ghosts) with the bonds of the owned ones.
//
// The set-up itself (weights, pre-cracks, surface correction) is made on the
// whole plate, exactly as a one-process run makes it, and then cut out here:
// a ghost's family is incomplete locally, so its surface-correction factor
// must come from the whole family, which its owner (or here: the same
// whole-plate set-up) sees. The local families keep the whole plate's
// lattices (cell numbers and stencils), so that an owned square keeps its
// stencil family and the lattice sweep finds every local particle in its
// cell; the lattice cells of particles that are not local hold none.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bond_setup.hpp"
#include "particle_file.hpp"

namespace pd::solver {

struct LocalBonds {
  ParticleSet particles;  // the local particles' per-particle arrays and grid description (no cells, sets, families)
  BondSetup setup;        // families: the owned particles' whole families, renumbered; ghosts have none
};

// `local_ids`: global ids of the local particles in local order, the first
// `owned_count` of them owned; every neighbour of an owned particle must be
// among them.
LocalBonds local_bonds(const ParticleSet& whole, const BondSetup& whole_setup,
                       const std::vector<std::uint32_t>& local_ids, std::size_t owned_count);

}  // namespace pd::solver
