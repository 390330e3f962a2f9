#pragma once
// What one process of a distributed run reads of the particle file when its
// set-up is made on its slab's band (docs/solver.md, "Running on several
// processes (MPI)", "Set-up"): the particles within three bond reaches of
// its slab with their families (read_particle_band), its partition, and the
// few facts of the whole plate the run needs besides: the file's particle
// and bond counts, where each owned particle's family starts among the
// file's bonds (the checkpoint's bond-state rows), and the loads and the
// stop region resolved on the whole file's per-particle arrays and sets
// (global ids; no family of the whole plate is ever held).
//
// The set-up on the band equals the whole plate's for the owned particles
// and their ghosts: with one horizon (PMB or OSB, with or without the
// surface correction) the factors whose fixed point couples the whole plate
// are iterated on the slabs afterwards; with variable or dual horizons the
// rows of the owned particles are built from the band's families, whose
// ghosts (with dual horizons, also every particle owning a bond towards the
// slab) keep their whole families. Refinement and quasi-static runs need
// the whole plate's set-up (distributed_setup_refusal).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bond_setup.hpp"
#include "compact_families.hpp"
#include "error.hpp"
#include "loads.hpp"
#include "particle_file.hpp"
#include "partition.hpp"
#include "scene.hpp"

namespace pd::solver {

// The whole plate as a process of a band set-up knows it (Simulation's constructor).
struct WholePlateFacts {
  std::size_t particle_count = 0;  // in the file
  std::uint64_t bond_count = 0;    // directed bonds in the file
  // Per owned particle (in the partition's order): the first of its family's
  // bonds among the file's (the file's family offset) and the family's length.
  std::vector<std::uint64_t> owned_family_start;
  std::vector<std::uint32_t> owned_family_length;
  std::vector<ResolvedLoad> loads;  // on the whole plate, global ids
  // Per local particle (owned, then ghosts): its index in the band.
  std::vector<std::uint32_t> band_index;
  // The file's horizon mode and horizon, which the band's particles alone may not show.
  PlateHorizons horizons;
  // With variable horizons, per particle of the band: the first of its
  // family's bonds among the file's (its rows' entries name their bonds by
  // the file's numbers, which checkpoints use); empty with one horizon.
  std::vector<std::uint64_t> band_family_start;
};

struct SlabBand {
  ParticleSet particles;  // the band's (read_particle_band): per-particle arrays, cells, sets; no family arrays
  Families families;      // the band's, in its numbering
  Partition partition;    // global ids
  WholePlateFacts whole;
  std::vector<std::uint32_t> stop_region;  // [stop]'s particles, global ids (empty without)
  std::size_t band_width_reaches = 3;      // the band: the slab widened by this many bond reaches
};

// An error read_slab_band finds in the scene or the process count while the
// file streams by (a load's set or point, the stop region, the horizons the
// scene's model refuses, more slabs than the plate's positions allow): the
// file itself is sound, and the message names what is at fault.
struct BandSceneError : Error {
  using Error::Error;
};

// Why `scene` on several processes needs the whole plate's set-up, or an
// empty string when a band is enough (the particle file may still say
// otherwise: read_slab_band).
std::string distributed_setup_refusal(const Scene& scene);

// Reads process `rank`'s band of `scene.particle_file` among `size` slabs.
// pd::Error naming the file, the scene and the key on any defect (as
// read_particle_file, resolve_loads and resolve_region).
SlabBand read_slab_band(const Scene& scene, int rank, int size);

}  // namespace pd::solver
