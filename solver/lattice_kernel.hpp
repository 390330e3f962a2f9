#pragma once
// The structured-lattice fast path of the PMB force kernel (theory.md Sec. 1).
//
// NB-NUG grids are 97-99 % dx squares. A square whose whole family is squares
// at the same offsets as every other such square ("lattice particle") needs
// no neighbour list: its neighbours sit at fixed offsets in a padded 2D grid
// and every bond constant depends on the offset only. The kernel then runs
// along lattice rows, one offset at a time, vectorised across consecutive
// particles, on displacement differences: the extension is computed as
// (2 xi.du + |du|^2) / (|y| + |xi|), free of the cancellation of |y| - |xi|
// (which is what would make single precision possible later; `Real` is
// double today, and the tests compare it with the neighbour lists). Bond
// states of lattice particles live here, offset-major; the bond table's
// states are brought up to date on demand.
//
// The same bond seen from both ends gives the same stretch bit for bit
// between two lattice particles (subtraction is antisymmetric), so both
// directions break at the same step; between a lattice particle and a general
// one the two formulas may differ in the last bit.
#include <cstdint>
#include <vector>

#include "bonds.hpp"
#include "kernel.hpp"
#include "particle_file.hpp"

namespace pd::solver {

using Real = double;  // the kernel's arithmetic (see above)

class LatticeKernel {
public:
  // Finds the lattice particles of `particles` whose bonds in `bonds` match
  // the stencil of a reference square exactly (neighbours, rest lengths,
  // stiffness up to the surface-correction factors, damage weights, no cut
  // bonds). `lambda`: surface-correction factor per particle.
  LatticeKernel(const ParticleSet& particles, const BondTable& bonds, const std::vector<double>& lambda,
                bool with_damage);

  bool empty() const { return particle_.empty(); }
  std::size_t particle_count() const { return particle_.size(); }
  std::size_t stencil_size() const { return offset_.size(); }
  // Particles the general kernel must handle (all the others), ascending.
  const std::vector<std::uint32_t>& general_particles() const { return general_; }

  // Bond states between the bond table's layout (CSR) and the lattice's.
  void load_states(const BondTable& bonds, const std::vector<std::uint8_t>& intact);
  void store_states(const BondTable& bonds, std::vector<std::uint8_t>& intact) const;

  // Force densities (and, with damage, bond states and damage index) of the
  // lattice particles. `ref_x`, `ref_y`: reference positions.
  template <class DamageMode>
  void compute(Kinematics& k, const std::vector<double>& ref_x, const std::vector<double>& ref_y,
               const BondTable& bonds, DamageState* state);

private:
  struct Segment {
    std::uint32_t first_particle, first_lattice, length;
    std::int64_t first_cell;
  };
  // Grid geometry: padded row length and the grid cell of every square
  // particle that lattice particles read (scattered every step).
  std::int64_t row_length_ = 0;
  std::vector<std::uint32_t> grid_particle_;
  std::vector<std::int64_t> grid_cell_;
  // Stencil: per offset, the grid-index step and the bond constants.
  std::vector<std::int64_t> offset_;
  std::vector<Real> xi_x_, xi_y_, rest_, stiffness_, critical_extension_, damage_weight_;
  // Lattice particles in row order, grouped into runs of consecutive cells.
  std::vector<std::uint32_t> particle_;
  std::vector<Segment> segments_;
  std::vector<std::uint32_t> general_;
  // Per-step work arrays on the grid, and bond states [offset][lattice particle].
  std::vector<Real> ux_, uy_, lambda_;
  std::vector<std::uint8_t> intact_;
};

}  // namespace pd::solver
