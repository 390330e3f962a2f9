#pragma once
// The families of a particle set, compact (docs/performance.md, "Memory").
//
// An NB-NUG grid is 97-99 % squares of one size, and the family of a square
// away from holes and edges is the same set of squares at the same cell
// steps with the same partial volumes for every such square: "the stencil".
// A particle whose family is its stencil stores nothing per bond; its
// neighbours are found through the lattice cells. The other particles keep
// their family as a list. A grid with several resolutions (squares of
// several sizes) has one lattice and one stencil per size: a "level".
//
// Code that works per bond (weights, surface correction, time step, bond
// constants) goes through `for_each_bond`, so that the particle file's
// families (12 bytes per bond) never need to be held in memory at once.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "uninitialised_vector.hpp"

namespace pd {

struct EarlierBondWeights;  // bond_weights.hpp

// One directed bond i -> neighbor as `for_each_bond` hands it over. `index`
// numbers it among its level's stencil bonds (on_stencil) or the listed ones.
struct BondRef {
  std::uint32_t neighbor;
  double partial_volume;  // phi_ij
  std::size_t index;
  bool on_stencil;
  std::uint8_t level;  // the stencil's level (on_stencil only)
};

// A value per directed bond: one per stencil bond of each level (shared by
// all stencil particles of the level) and one per listed bond. `listed` is
// sized unwritten (resize does not zero it): its makers write every listed
// bond's value (bond_energy_weights).
template <class T>
struct PerBond {
  std::vector<std::vector<T>> stencil;  // [level][stencil bond]
  UninitialisedVector<T> listed;
  T operator()(const BondRef& b) const { return b.on_stencil ? stencil[b.level][b.index] : listed[b.index]; }
};

// One resolution level: a lattice of square cells of one size from
// (Families::xmin, Families::ymin), and the family its interior squares share.
struct StencilLevel {
  double spacing = 0;                  // cell side [m]
  double horizon = 0;                  // of the squares on the stencil [m]
  long nx = 0, ny = 0;                 // lattice cells, row-major: cell = row * nx + col
  std::vector<std::uint32_t> at_cell;  // per cell: the square in it, or Families::none
  // The stencil, in the order of the bonds in the file: cell steps to the
  // neighbour and partial volumes. Empty when no square has a whole family.
  std::vector<long> di, dj;
  std::vector<double> phi;
  std::size_t size() const { return di.size(); }
};

struct Families {
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  static constexpr std::uint8_t no_level = std::numeric_limits<std::uint8_t>::max();

  std::size_t particle_count = 0;
  double xmin = 0, ymin = 0;  // origin of every level's lattice [m]
  // levels[0] has the particle file's spacing; further levels other square sizes.
  std::vector<StencilLevel> levels;
  std::vector<std::uint8_t> level;     // per particle: the level of its square, or no_level
  std::vector<std::int64_t> cell;      // per particle: its cell in that level's lattice, -1 if none
  std::vector<std::uint8_t> on_stencil;  // per particle: its family is its level's stencil

  // Listed families (CSR; empty rows for stencil particles).
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint32_t> neighbors;
  std::vector<double> partial_volume;

  std::size_t family_size(std::uint32_t i) const {
    return on_stencil[i] ? levels[level[i]].size() : static_cast<std::size_t>(offsets[i + 1] - offsets[i]);
  }
  std::uint64_t bond_count() const;  // directed bonds of all families
  std::size_t stencil_particle_count() const;                  // all levels
  std::size_t stencil_particle_count(std::uint8_t level) const;  // one level
  double longest_stencil_bond() const;                         // [m], 0 without stencils

  // Calls f(const BondRef&) for every bond of particle i, in the file's order.
  template <class F>
  void for_each_bond(std::uint32_t i, F&& f) const {
    if (on_stencil[i]) {
      const StencilLevel& s = levels[level[i]];
      const std::int64_t c = cell[i];
      for (std::size_t o = 0; o < s.di.size(); ++o)
        f(BondRef{s.at_cell[static_cast<std::size_t>(c + s.dj[o] * s.nx + s.di[o])], s.phi[o], o, true, level[i]});
    } else {
      for (auto b = offsets[i]; b < offsets[i + 1]; ++b)
        f(BondRef{neighbors[b], partial_volume[b], static_cast<std::size_t>(b), false, no_level});
    }
  }

  // Turns the stencil families of `particles` into lists (e.g. of the
  // particles a pre-crack cuts). Renumbers the listed bonds.
  void make_listed(const std::vector<std::uint32_t>& particles);

  // The lattices of `whole` for a subset of n particles: the same levels and
  // origin, each cell naming local_of[its particle] (Families::none where the
  // particle is not kept, when local_of says so). Per-particle data and lists
  // are left to the caller.
  static Families lattices_renumbered(const Families& whole, std::size_t n,
                                      const std::vector<std::uint32_t>& local_of);
};

// Collects the families of a particle set one particle at a time, in index
// order, as the particle file's streaming reader hands them over
// (read_particle_file with a FamilyVisitor). `particles` needs its
// per-particle arrays and grid description only.
class FamilyCollector {
public:
  explicit FamilyCollector(const ParticleSet& particles);
  // Keeps the families of the particles with keep[i] != 0 only (the others
  // get empty lists), while the stencils are still those of the whole set:
  // the same reference squares, the same stencil particles (particle_band.hpp).
  FamilyCollector(const ParticleSet& particles, std::vector<std::uint8_t> keep);
  // A later set of an earlier one whose families it shares (adaptive
  // refinement; `earlier` as for bond_energy_weights, with its origin): a
  // particle whose family is its earlier particle's, where its level, the
  // level's lattice and stencil and every shared particle's level are as
  // before, is on the stencil exactly when its earlier particle was (unless
  // the earlier set's pre-cracks listed it), without its bonds being
  // compared (the same families; theory.md Sec. 8.4). The particles of
  // EarlierBondWeights::listed are listed as they are collected, as
  // Families::make_listed would list them afterwards (theory.md Sec. 8.8).
  FamilyCollector(const ParticleSet& particles, const EarlierBondWeights* earlier);
  void add(std::uint32_t particle, const std::uint32_t* neighbors, const double* partial_volume, std::size_t count);
  Families finish();

private:
  bool matches_stencil(std::uint32_t i, const std::uint32_t* neighbors, const double* phi, std::size_t count) const;
  void append_listed(const std::uint32_t* neighbors, const double* phi, std::size_t count);
  void take_stencil_from(std::uint32_t i, const std::uint32_t* neighbors, const double* phi, std::size_t count);
  // With `earlier_`: whether particle i is on its stencil as its earlier
  // particle was (1, 0), listed as it was (listed_as_before), or unknown
  // (-1: its bonds are compared).
  static constexpr int listed_as_before = 2;
  int on_stencil_as_before(std::uint32_t i);
  bool listed_anyway(std::uint32_t i) const { return !listed_anyway_.empty() && listed_anyway_[i]; }

  Families f_;
  std::vector<std::uint32_t> reference_;  // per level: the square whose family defines the stencil
  std::uint32_t next_ = 0;                // the next particle expected
  std::vector<std::uint8_t> keep_;        // per particle: its family is kept (empty: every family)
  const EarlierBondWeights* earlier_ = nullptr;
  // Per level, with earlier_: -1 not yet known, 1 its stencil is decided and
  // the earlier set's level is the same lattice with the same stencil, 0 not.
  std::vector<int> level_as_before_;
  bool reserved_ = false;  // the lists were reserved at their expected size
  // Per particle: its family is listed whatever its match with the stencil
  // (EarlierBondWeights::listed; empty: none).
  std::vector<std::uint8_t> listed_anyway_;
  // Per earlier particle, with earlier_: listed after it was collected (EarlierBondWeights::listed_before).
  std::vector<std::uint8_t> listed_before_;
};

// The compact families of an in-memory particle set (with its families);
// `earlier` (optional): as for the FamilyCollector.
Families compact_families(const ParticleSet& particles, const EarlierBondWeights* earlier = nullptr);

// Reads a particle file without ever holding its families: the particle set
// (with empty family arrays) and the compact families, collected while the
// file streams by. pd::Error naming the file on any defect.
struct ParticlesAndFamilies {
  ParticleSet particles;
  Families families;
};
ParticlesAndFamilies read_compact_particle_file(const std::string& path);

}  // namespace pd
