#pragma once
// The part of a particle file one process of a distributed run keeps
// (docs/formats.md, "Reading under MPI"; docs/solver.md, "Set-up"): the
// particles whose position along one axis lies in a band, their compact
// families restricted to the band and numbered among the kept particles,
// their global ids (indices in the file) kept. The families stream by and
// only the kept ones are held; the stencils and lattices are the whole
// file's (the same reference squares, the same stencil particles, the same
// partial volumes to the last bit as read_compact_particle_file gives). The
// per-particle arrays of the whole file are held while it is read.
//
// A kept particle whose family reaches out of the band loses those bonds
// (its family becomes a list of the rest): it is marked incomplete. A
// particle farther than longest_possible_bond (families.hpp) from the band's
// edges keeps its whole family, bond for bond in the file's order.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "compact_families.hpp"
#include "particle_file.hpp"

namespace pd {

struct ParticleBand {
  // The kept particles: the file's grid description, per-particle arrays and
  // cells, no family arrays; sets restricted to the kept particles, in local
  // numbering; the file's provenance.
  ParticleSet particles;
  Families families;                          // local numbering; the whole file's lattices and stencils
  std::vector<std::uint32_t> global_id;       // per kept particle, ascending
  std::vector<std::uint8_t> family_complete;  // per kept particle: no bond left out
  std::size_t whole_count = 0;                // particles in the file
  std::uint64_t whole_bond_count = 0;         // directed bonds in the file
};

// Keeps the particles with `lo` <= position <= `hi` along `axis` (0: x,
// 1: y). Every check of the streaming reader is made on the whole file.
// pd::Error naming the file on any defect, or when `lo` > `hi`.
ParticleBand read_particle_band(const std::string& path, int axis, double lo, double hi);

// The band chosen from the whole file's per-particle arrays, cells and
// family offsets (no family yet: `choose` is called before the first one),
// e.g. from slab cuts that need the family lengths. `whole`, if given, sees
// the whole file's per-particle arrays, cells, family offsets and sets once
// the file is read, before they are cut to the band (to resolve regions in
// the file's numbering). An exception from either ends the read.
struct BandChoice {
  int axis = 0;
  double lo = 0, hi = 0;
};
using BandChooser = std::function<BandChoice(const ParticleSet& whole_without_families)>;
using WholeArraysVisitor = std::function<void(const ParticleSet& whole_without_families)>;
ParticleBand read_particle_band(const std::string& path, const BandChooser& choose,
                                const WholeArraysVisitor& whole = {});

}  // namespace pd
