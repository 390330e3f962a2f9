#pragma once
// The families of a run, compact (docs/performance.md, "Memory").
//
// An NB-NUG grid is 97-99 % dx squares, and the family of a square away from
// holes and edges is the same set of squares at the same cell steps with the
// same partial volumes for every such square: "the stencil". A particle whose
// family is the stencil stores nothing per bond; its neighbours are found
// through the lattice cells. The other particles keep their family as a list.
// The solver builds everything per bond (weights, surface correction, time
// step, bond constants) through `for_each_bond`, so that the particle file's
// families (12 bytes per bond) never need to be held in memory at once.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "particle_file.hpp"

namespace pd {

// One directed bond i -> neighbor as `for_each_bond` hands it over. `index`
// numbers it among the stencil's bonds (on_stencil) or the listed ones.
struct BondRef {
  std::uint32_t neighbor;
  double partial_volume;  // phi_ij
  std::size_t index;
  bool on_stencil;
};

// A value per directed bond: one per stencil bond (shared by all stencil
// particles) and one per listed bond.
template <class T>
struct PerBond {
  std::vector<T> stencil, listed;
  T operator()(const BondRef& b) const { return b.on_stencil ? stencil[b.index] : listed[b.index]; }
};

struct Families {
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

  std::size_t particle_count = 0;
  // The lattice: nx * ny cells of size `spacing` from (xmin, ymin); the cell
  // of a dx square particle is row * nx + col.
  double spacing = 0, xmin = 0, ymin = 0;
  long nx = 0, ny = 0;
  std::vector<std::int64_t> cell;      // per particle: its lattice cell, -1 if it is not a square
  std::vector<std::uint32_t> at_cell;  // per cell: the square in it, or `none`

  // The stencil, in the order of the bonds in the file: cell steps to the
  // neighbour and partial volumes.
  std::vector<long> stencil_di, stencil_dj;
  std::vector<double> stencil_phi;
  std::vector<std::uint8_t> on_stencil;  // per particle

  // Listed families (CSR; empty rows for stencil particles).
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint32_t> neighbors;
  std::vector<double> partial_volume;

  std::size_t stencil_size() const { return stencil_di.size(); }
  std::size_t family_size(std::uint32_t i) const {
    return on_stencil[i] ? stencil_size() : static_cast<std::size_t>(offsets[i + 1] - offsets[i]);
  }
  std::uint64_t bond_count() const;  // directed bonds of all families
  std::size_t stencil_particle_count() const;

  // Calls f(const BondRef&) for every bond of particle i, in the file's order.
  template <class F>
  void for_each_bond(std::uint32_t i, F&& f) const {
    if (on_stencil[i]) {
      const std::int64_t c = cell[i];
      for (std::size_t o = 0; o < stencil_di.size(); ++o)
        f(BondRef{at_cell[static_cast<std::size_t>(c + stencil_dj[o] * nx + stencil_di[o])], stencil_phi[o], o,
                  true});
    } else {
      for (auto b = offsets[i]; b < offsets[i + 1]; ++b)
        f(BondRef{neighbors[b], partial_volume[b], static_cast<std::size_t>(b), false});
    }
  }

  // Turns the stencil families of `particles` into lists (e.g. of the
  // particles a pre-crack cuts). Renumbers the listed bonds.
  void make_listed(const std::vector<std::uint32_t>& particles);
};

// Collects the families of a particle set one particle at a time, in index
// order, as the particle file's streaming reader hands them over
// (read_particle_file with a FamilyVisitor). `particles` needs its
// per-particle arrays and grid description only.
class FamilyCollector {
public:
  explicit FamilyCollector(const ParticleSet& particles);
  void add(std::uint32_t particle, const std::uint32_t* neighbors, const double* partial_volume, std::size_t count);
  Families finish();

private:
  bool matches_stencil(std::uint32_t i, const std::uint32_t* neighbors, const double* phi, std::size_t count) const;
  void append_listed(std::uint32_t i, const std::uint32_t* neighbors, const double* phi, std::size_t count);
  void take_stencil_from(std::uint32_t i, const std::uint32_t* neighbors, const double* phi, std::size_t count);

  Families f_;
  std::uint32_t reference_ = Families::none;  // the square whose family defines the stencil
  std::uint32_t next_ = 0;                    // the next particle expected
};

// The compact families of an in-memory particle set (with its families).
Families compact_families(const ParticleSet& particles);

// Reads a particle file without ever holding its families: the particle set
// (with empty family arrays) and the compact families, collected while the
// file streams by. pd::Error naming the file on any defect.
struct ParticlesAndFamilies {
  ParticleSet particles;
  Families families;
};
ParticlesAndFamilies read_compact_particle_file(const std::string& path);

}  // namespace pd
