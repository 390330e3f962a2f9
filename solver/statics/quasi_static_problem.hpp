#pragma once
// The quasi-static problem: a particle set under displacement-controlled (and
// traction) loads scaled by a load factor, as a total potential energy of the
// free displacement components (theory.md Secs. 1 and 4):
//   Pi(u) = h sum_i A_i W_i(u) - lambda h sum_i A_i b_i . u_i,
// W_i = 1/4 sum_j k^E_ij e_ij^2 with the energy bond table (energy_bonds.hpp)
// for PMB; for OSB (model.type = "osb") W_i is the state-based density of
// osb.hpp and the residual its exact gradient on the energy table
// (state_energy_gradient.hpp, theory.md Sec. 5.6).
// The minimiser (ncg.hpp) sees only the functions below; bond breaking happens
// between minimisations (quasi_static.hpp).
//
// Unknowns: u = (u_x of every particle, then u_y of every particle) [m]; the
// components a displacement or fixed load constrains are set by
// set_load_factor() and never changed by the minimiser (their gradient entries
// are zero).
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "bond_setup.hpp"
#include "bond_table.hpp"
#include "coarse_correction.hpp"
#include "compact_families.hpp"
#include "energy_problem.hpp"
#include "lattice_kernel.hpp"
#include "loads.hpp"
#include "model_summary.hpp"
#include "particle_file.hpp"
#include "particle_state.hpp"
#include "osb.hpp"
#include "pmb.hpp"
#include "scene.hpp"

namespace pd::solver {

class QuasiStaticProblem final : public EnergyProblem {
public:
  // The bond-based model of the energy (the total energy is a sum over
  // bonds, and energy_bonds.hpp makes it symmetric on non-uniform grids).
  // With model.type = "osb" the problem uses Osb instead (state_based()).
  using Model = Pmb;

  // `particles` with their families (tests, small sets): copied.
  QuasiStaticProblem(const Scene& scene, const ParticleSet& particles, const SetupOptions& options = {});
  // `particles` without their families, which come compact; kept as the
  // reference configuration of the problem's state.
  QuasiStaticProblem(const Scene& scene, ParticleSet particles, Families families, const SetupOptions& options);

  // --- set-up facts
  const Scene& scene() const { return scene_; }
  std::size_t particle_count() const { return state_.size(); }
  std::size_t unknown_count() const override { return 2 * state_.size(); }
  const ModelSummary& model() const { return model_; }
  // True for OSB: the state-based energy and its gradient (theory.md Sec. 5.6).
  bool state_based() const { return state_based_; }
  const SetupFacts& setup_facts() const { return facts_; }
  // quasi_static.kernels = "lattice" (PMB): the forces come from the dynamic
  // solver's lattice kernel (float sweep) and its lists, the energy table is
  // empty, and the residual is float until switched to double
  // (set_double_residual; docs/solver.md, "Fast kernels").
  bool lattice_kernels() const { return lattice_ != nullptr; }
  const LatticeKernel* lattice_kernel() const { return lattice_.get(); }
  void set_double_residual(bool in_double) { double_residual_ = in_double; }
  // Lattice kernels: which Hessian product hessian_times() gives (theory.md
  // Sec. 4.12): the small-strain K0 (one float sweep of tiny displacements
  // from rest), the tangent at u (one float sweep of Model::force_change, the
  // default), or central differences of the double force (two double passes).
  enum class LatticeHessian { small_strain, tangent, central_difference };
  void set_lattice_hessian(LatticeHessian kind) { lattice_hessian_ = kind; }
  LatticeHessian lattice_hessian() const { return lattice_hessian_; }
  // Lattice kernels: the damping mu >= 0 of a Levenberg-Marquardt round
  // (theory.md Sec. 4.14). The tangent and K0 products become (H + mu B) d,
  // B the preconditioner's 2 x 2 blocks, and precondition() inverts
  // (1 + mu) B plus the coarse correction of P^T (K0 + mu B) P. 0: undamped.
  void set_lattice_damping(double mu);
  double lattice_damping() const { return damping_; }
  bool double_residual() const { return double_residual_ || !lattice_; }
  const BondTable& energy_bonds() const { return bonds_; }
  std::size_t dynamic_bond_count() const { return facts_.bond_count; }
  double stiffness_asymmetry() const { return asymmetry_; }  // energy_bonds.hpp
  const std::vector<ResolvedLoad>& loads() const { return loads_; }
  std::size_t precrack_bonds_cut() const { return facts_.precrack_cut; }
  const ParticleState& state() const { return state_; }
  const std::vector<double>& reference_x() const { return state_.x0(); }
  const std::vector<double>& reference_y() const { return state_.y0(); }
  const std::vector<double>& area() const { return state_.area(); }
  double thickness() const { return thickness_; }

  // --- loading
  // Sets the constrained components of u to value x factor (fixed: 0) and scales the tractions.
  void set_load_factor(double factor, std::vector<double>& u);
  double load_factor() const { return factor_; }
  // 1 where the minimiser may move the component, 0 where a load prescribes it.
  const std::vector<std::uint8_t>& free_mask() const { return free_; }

  // --- what the minimiser needs (all forces in N)
  // r = -dPi/du on free components, 0 on constrained ones. Also remembers the
  // constraint forces at u (reaction_norm(), reactions()).
  void residual(const std::vector<double>& u, std::vector<double>& r) override;
  // Hd = (d^2 Pi/du^2) d for free components (0 on constrained ones), the exact
  // second derivative of the bond energies at u (geometric stiffness included).
  // OSB: the derivative of -r along d by central differences of the exact
  // gradient (theory.md Sec. 5.6).
  // Lattice kernels: as set_lattice_hessian says (theory.md Sec. 4.12).
  void hessian_times(const std::vector<double>& u, const std::vector<double>& d,
                     std::vector<double>& hd) const override;
  // A positive diagonal approximating the Hessian: h A_i sum_j k^E_ij (per
  // component). Lattice kernels: the diagonal of the 2 x 2 blocks below.
  const std::vector<double>& preconditioner() const override { return diagonal_; }
  // Lattice kernels: s = M^-1 r with M the blocks h A_i sum_j k_ij n n^T of
  // the bonds that hold (theory.md Sec. 4.12), plus the coarse correction of
  // Sec. 4.13 unless the scene turns it off; otherwise r / diagonal.
  void precondition(const std::vector<double>& r, std::vector<double>& s) const override;
  // Lattice kernels: the blocks' off-diagonal entries, one per particle (the
  // block of i is [[diagonal_x, c], [c, diagonal_y]]); empty otherwise.
  const std::vector<double>& preconditioner_coupling() const { return coupling_; }
  // The coarse space's unknowns (3 per aggregate; 0 without it).
  std::size_t coarse_unknown_count() const { return coarse_ ? coarse_->coarse_unknown_count() : 0; }
  // Euclidean norm [N] of the constraint forces at the last residual(): the
  // scale against which the residual is judged.
  double reaction_norm() const override { return reaction_norm_; }
  // Total potential energy Pi(u) [J].
  double energy(const std::vector<double>& u) const;
  double strain_energy(const std::vector<double>& u) const;  // [J]
  // W_i of every particle at u [J/m^3] (the model's energy density).
  std::vector<double> strain_energy_density(const std::vector<double>& u) const;

  // --- results at the last residual()
  // Per load: minus the resultant of the internal forces on its particles [N]
  // (the force the support applies; for a traction the applied resultant).
  const std::vector<LoadResultant>& reactions() const { return reactions_; }

  // --- damage
  // Breaks every intact bond with stretch above s0 at u (both directions of a
  // pair together); returns the number of pairs broken.
  std::size_t break_overstretched_bonds(const std::vector<double>& u);
  // Breaks the given pairs (i, j) (both directions) whatever their stretch:
  // a crack state set by hand (tests, studies). Returns how many pairs held
  // before; a pair that is not a bond is an error.
  std::size_t break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs);
  std::size_t broken_bond_count() const;  // directed bonds of the energy table (pre-cracks included)
  // The broken pairs (i, j), i < j, sorted (pre-cracks included): the bond
  // states handed to a dynamic run (static_then_dynamic.hpp).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs() const;
  // Per directed bond of the energy table: 1 intact, 0 broken (checkpoints);
  // lattice kernels: the kernel's own layout (LatticeKernel::bond_states).
  const std::vector<std::uint8_t>& bond_states() const;
  // Restores saved bond states on a freshly built problem (broken bonds lose their stiffness).
  void set_bond_states(const std::vector<std::uint8_t>& intact);
  // D_i = 1 - sum intact phi A / sum phi A  [004:(10)]; all 0 without damage.
  std::vector<double> damage() const;

private:
  // work_.fx, work_.fy = internal force densities at u [N/m^3]: the forces of
  // the neighbour-list kernel (neighbor_kernel.hpp) on the energy table.
  void internal_force_density(const std::vector<double>& u) const;
  // OSB: minus the energy gradient per h A_i at the displacements in k (pre-pass, then gradient).
  void state_force_density(Kinematics& k) const;
  // Takes bond b out of the energy: its state and stiffness, and for OSB
  // variant (a) its dilatation weight (theory.md Sec. 5.8).
  void cut_bond(std::size_t b);
  // Lattice kernels: the set-up (constructor), the force densities at the
  // displacements in k (float sweep, or double), and the damage index after
  // the bond states changed.
  void build_lattice(const ParticleSet& p, const BondSetup& setup);
  void lattice_force_density(Kinematics& k, bool in_double) const;
  void refresh_lattice_damage();
  // Lattice kernels: the block preconditioner from the bonds that hold (set-up, after breaking).
  void refresh_lattice_preconditioner();

  Scene scene_;
  Model::Constants constants_;
  ModelSummary model_;
  SetupFacts facts_;
  ParticleState state_;  // reference configuration; damage follows the bond states
  double thickness_ = 1;
  double asymmetry_ = 0;
  BondTable bonds_;                   // energy table; broken bonds have stiffness 0
  std::vector<std::uint8_t> intact_;  // per directed bond of bonds_
  std::vector<ResolvedLoad> loads_;
  std::vector<std::uint8_t> free_;
  std::vector<double> diagonal_;
  // Lattice kernels: the off-diagonal entry of each particle's 2 x 2
  // preconditioner block (diagonal_ holds its diagonal); 0 where a load
  // prescribes a component. Empty otherwise.
  std::vector<double> coupling_;
  // Lattice kernels with quasi_static.coarse_correction: the coarse space of
  // the preconditioner (coarse_correction.hpp), assembled with the blocks.
  std::unique_ptr<CoarseCorrection> coarse_;
  std::vector<double> body_x_, body_y_;  // traction body force density at load factor 1 [N/m^3]
  double factor_ = 0;
  mutable Kinematics work_;
  bool state_based_ = false;
  Osb::Constants osb_;                          // OSB only
  mutable Kinematics probe_;                    // Hessian products (OSB, lattice kernels)
  mutable std::vector<double> tangent_dx_, tangent_dy_;  // lattice kernels: the tangent product's direction
  mutable std::vector<double> theta_, pressure_;  // OSB pre-pass, per particle
  bool broken_bond_in_dilatation_ = false;        // OSB failure variants (b), (c) (theory.md Sec. 5.8)
  std::vector<LoadResultant> reactions_;
  double reaction_norm_ = 0;
  // Lattice kernels (null otherwise): the kernel with held bond states, the
  // surface-correction factors, the damage index of the states, scratch.
  std::unique_ptr<LatticeKernel> lattice_;
  std::vector<double> lambda_;
  mutable std::vector<double> lattice_damage_, scratch_;
  mutable std::vector<std::uint8_t> lattice_states_;
  bool double_residual_ = false;
  LatticeHessian lattice_hessian_ = LatticeHessian::tangent;
  double damping_ = 0;  // set_lattice_damping
};

}  // namespace pd::solver
