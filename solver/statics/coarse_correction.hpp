#pragma once
// The coarse-space correction of the quasi-static solver's preconditioner
// (theory.md Sec. 4.13): a two-level additive preconditioner
//
//   M^-1 r = B^-1 r + P (P^T K0 P)^-1 P^T r,
//
// with B the 2 x 2 blocks of the particles (quasi_static_problem.hpp), K0 the
// small-strain stiffness of the bonds that hold, and P the rigid motions of
// aggregates of particles (two translations and one rotation each). The
// blocks settle the local part of an error; the coarse solve spreads a load
// across the plate in one application, which a preconditioner acting
// particle by particle needs O(plate / horizon) iterations to do (Toselli &
// Widlund 2005; the rigid-motion coarse space of smoothed aggregation,
// Vanek, Mandel & Brezina 1996).
//
// An aggregate is a connected part of the particles in one square of a grid
// of side 2 delta: connected by bonds that hold, so that a crack through a
// square makes two aggregates, each side moving on its own, and a fragment
// cut loose is never moved with the body it left; a body cut loose from
// every support (debris) takes no part at all. A_c = P^T K0 P is summed
// bond by bond in double precision and factorised by sparse Cholesky
// (Eigen's SimplicialLDLT), once per change of the bond states.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace pd::solver {

class LatticeKernel;

class CoarseCorrection {
public:
  // Unknowns ordered as the quasi-static problem's: u_x of every particle,
  // then u_y. `square_side` [m]: the grid of the aggregates; `free`: 1 where
  // the minimiser moves a component (the coarse motions are zero on the
  // prescribed ones); `scale`: h A_i per particle [m^3], the factor of K0's
  // row i (QuasiStaticProblem::hessian_times).
  CoarseCorrection(const std::vector<double>& x, const std::vector<double>& y, double square_side,
                   std::vector<std::uint8_t> free, std::vector<double> scale);
  ~CoarseCorrection();
  CoarseCorrection(const CoarseCorrection&) = delete;
  CoarseCorrection& operator=(const CoarseCorrection&) = delete;

  // The aggregates of the bonds that hold in `bonds`, A_c and its factorisation.
  void assemble(const LatticeKernel& bonds);
  // A damped round's coarse matrix (theory.md Sec. 4.14): A_c + mu P^T B P,
  // B the particles' 2 x 2 blocks [[diagonal_x, coupling], [coupling,
  // diagonal_y]] (diagonal: x block, then y block), refactorised; mu = 0
  // restores A_c. assemble() restores it too.
  void set_damping(double mu, const std::vector<double>& diagonal, const std::vector<double>& coupling);
  // s += P A_c^-1 P^T r.
  void add_correction(const std::vector<double>& r, std::vector<double>& s) const;

  std::size_t aggregate_count() const { return aggregate_count_; }
  std::size_t coarse_unknown_count() const { return 3 * aggregate_count_; }

private:
  // The value of coarse motion `mode` (0: x translation, 1: y, 2: rotation)
  // of particle i's aggregate at the particle: (x part, y part).
  void mode_at(std::size_t i, int mode, double& vx, double& vy) const;

  std::size_t particle_count_ = 0;
  std::vector<std::uint8_t> free_;
  std::vector<double> scale_;
  std::vector<std::uint32_t> square_;     // per particle: its square of the grid
  std::vector<double> dx_, dy_;           // per particle: position from its square's centre, over the side
  std::vector<std::uint32_t> aggregate_;  // per particle (assemble)
  std::vector<std::uint8_t> held_;        // per particle: 1 if its body is held by a support (assemble)
  std::size_t aggregate_count_ = 0;
  struct Factor;
  std::unique_ptr<Factor> factor_;
};

}  // namespace pd::solver
