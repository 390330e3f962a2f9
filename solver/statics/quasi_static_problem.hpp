#pragma once
// The quasi-static problem: a particle set under displacement-controlled (and
// traction) loads scaled by a load factor, as a total potential energy of the
// free displacement components (theory.md Secs. 1 and 4):
//   Pi(u) = h sum_i A_i W_i(u) - lambda h sum_i A_i b_i . u_i,
// W_i = 1/4 sum_j k^E_ij e_ij^2 with the energy bond table (energy_bonds.hpp).
// The minimiser (ncg.hpp) sees only the functions below; bond breaking happens
// between minimisations (quasi_static.hpp).
//
// Unknowns: u = (u_x of every particle, then u_y of every particle) [m]; the
// components a displacement or fixed load constrains are set by
// set_load_factor() and never changed by the minimiser (their gradient entries
// are zero).
#include <cstdint>
#include <utility>
#include <vector>

#include "bond_table.hpp"
#include "loads.hpp"
#include "particle_file.hpp"
#include "pmb.hpp"
#include "scene.hpp"
#include "simulation.hpp"

namespace pd::solver {

class QuasiStaticProblem {
public:
  QuasiStaticProblem(const Scene& scene, const ParticleSet& particles, const SimulationOptions& options = {});

  // --- set-up facts
  std::size_t particle_count() const { return area_.size(); }
  std::size_t unknown_count() const { return 2 * area_.size(); }
  const PmbConstants& pmb() const { return pmb_; }
  const BondTable& energy_bonds() const { return bonds_; }
  std::size_t dynamic_bond_count() const { return dynamic_bond_count_; }
  double stiffness_asymmetry() const { return asymmetry_; }  // energy_bonds.hpp
  const std::vector<ResolvedLoad>& loads() const { return loads_; }
  std::size_t precrack_bonds_cut() const { return precrack_cut_; }
  int surface_correction_iterations() const { return lambda_iterations_; }
  bool surface_correction_from_cache() const { return lambda_from_cache_; }
  const std::vector<double>& reference_x() const { return ref_x_; }
  const std::vector<double>& reference_y() const { return ref_y_; }
  const std::vector<double>& area() const { return area_; }
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
  void residual(const std::vector<double>& u, std::vector<double>& r);
  // Hd = (d^2 Pi/du^2) d for free components (0 on constrained ones), the exact
  // second derivative of the bond energies at u (geometric stiffness included).
  void hessian_times(const std::vector<double>& u, const std::vector<double>& d, std::vector<double>& hd) const;
  // A positive diagonal approximating the Hessian: h A_i sum_j k^E_ij (per component).
  const std::vector<double>& preconditioner() const { return diagonal_; }
  // Euclidean norm [N] of the constraint forces at the last residual(): the
  // scale against which the residual is judged.
  double reaction_norm() const { return reaction_norm_; }
  // Total potential energy Pi(u) [J].
  double energy(const std::vector<double>& u) const;
  double strain_energy(const std::vector<double>& u) const;  // [J]

  // --- results at the last residual()
  // Per load: minus the resultant of the internal forces on its particles [N]
  // (the force the support applies; for a traction the applied resultant).
  const std::vector<LoadResultant>& reactions() const { return reactions_; }

  // --- damage
  // Breaks every intact bond with stretch above s0 at u (both directions of a
  // pair together); returns the number of pairs broken.
  std::size_t break_overstretched_bonds(const std::vector<double>& u);
  std::size_t broken_bond_count() const;  // directed bonds of the energy table (pre-cracks included)
  // The broken pairs (i, j), i < j, sorted (pre-cracks included): the bond
  // states handed to a dynamic run (static_then_dynamic.hpp).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs() const;
  // Per directed bond of the energy table: 1 intact, 0 broken (checkpoints).
  const std::vector<std::uint8_t>& bond_states() const { return intact_; }
  // Restores saved bond states on a freshly built problem (broken bonds lose their stiffness).
  void set_bond_states(const std::vector<std::uint8_t>& intact);
  // D_i = 1 - sum intact phi A / sum phi A  [004:(10)]; all 0 without damage.
  std::vector<double> damage() const;

private:
  // work_.fx, work_.fy = internal force densities at u [N/m^3]: the forces of
  // the kernel of kernel.hpp on the energy table, computed from displacements.
  void internal_force_density(const std::vector<double>& u) const;

  Scene scene_;
  PmbConstants pmb_;
  std::vector<double> ref_x_, ref_y_, area_;
  double thickness_ = 1;
  int lambda_iterations_ = 0;
  bool lambda_from_cache_ = false;
  std::size_t dynamic_bond_count_ = 0;
  double asymmetry_ = 0;
  BondTable bonds_;                   // energy table; broken bonds have stiffness 0
  std::vector<std::uint8_t> intact_;  // per directed bond of bonds_
  std::vector<ResolvedLoad> loads_;
  std::size_t precrack_cut_ = 0;
  std::vector<std::uint8_t> free_;
  std::vector<double> diagonal_;
  std::vector<double> body_x_, body_y_;  // traction body force density at load factor 1 [N/m^3]
  double factor_ = 0;
  mutable Kinematics work_;
  std::vector<LoadResultant> reactions_;
  double reaction_norm_ = 0;
};

}  // namespace pd::solver
