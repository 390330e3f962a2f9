#pragma once
// One simulation: particle data, bond table, state and the velocity-Verlet
// step (theory.md Sec. 4, Ha & Bobaru 2010). The run driver (run.hpp) adds
// files, progress and checkpoints around it; tests use it directly.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bond_table.hpp"
#include "compact_families.hpp"
#include "neighbor_kernel.hpp"
#include "lattice_kernel.hpp"
#include "loads.hpp"
#include "particle_file.hpp"
#include "pmb.hpp"
#include "scene.hpp"

namespace pd::solver {

struct SimulationOptions {
  std::string surface_correction_cache;  // file for cached lambda; empty = compute, do not cache
  std::string particle_file_hash;        // cache key
  // Lattice squares through the structured-lattice kernel (lattice_kernel.hpp);
  // false = every particle through the neighbour lists (for comparisons).
  bool lattice_kernel = true;
};

// Per constrained or traction load: resultant of the internal forces on its
// particles, and the work it has done.
struct LoadResultant {
  double reaction_x = 0, reaction_y = 0;  // [N]: minus the internal force resultant on the set
                                           // (= the applied resultant for a traction)
};

struct EnergyTotals {
  double kinetic = 0;        // [J], from the velocities at the step
  // [J]: from the product of the half-step velocities, sum 1/2 m (|v|^2 - (dt/2)^2 |a|^2);
  // with the strain energy it is the energy velocity-Verlet conserves exactly for linear
  // forces, whereas kinetic + strain oscillates by O((omega dt)^2) around it.
  double kinetic_half_step = 0;
  double strain = 0;         // [J]
  double external_work = 0;  // [J], accumulated since t = 0
};

// The first non-finite value found, for the error message.
struct NonFinite {
  bool found = false;
  std::size_t particle = 0;
  std::string quantity;
};

class Simulation {
public:
  // `particles` with their families (tests, small sets).
  Simulation(const Scene& scene, const ParticleSet& particles, const SimulationOptions& options = {});
  // `particles` without their families, which come compact (collected while
  // reading the particle file: families.hpp).
  Simulation(const Scene& scene, const ParticleSet& particles, Families families,
             const SimulationOptions& options = {});

  // --- set-up facts
  const Scene& scene() const { return scene_; }
  const PmbConstants& pmb() const { return pmb_; }
  std::uint64_t bond_count() const { return bond_count_; }  // directed bonds
  const std::vector<ResolvedLoad>& loads() const { return loads_; }
  const std::vector<double>& surface_correction() const { return lambda_; }
  int surface_correction_iterations() const { return lambda_iterations_; }
  bool surface_correction_from_cache() const { return lambda_from_cache_; }
  std::size_t precrack_bonds_cut() const { return precrack_cut_; }
  double stable_time_step() const { return stable_dt_; }  // safety 1 [s]
  double time_step() const { return dt_; }                // used [s]
  std::size_t particle_count() const { return ref_x_.size(); }
  // Particles on the structured-lattice kernel (0 when it is off).
  std::size_t lattice_particle_count() const { return lattice_ ? lattice_->particle_count() : 0; }

  // --- stepping
  void step();  // one velocity-Verlet step
  long step_index() const { return step_; }
  double time() const { return time_; }
  const NonFinite& non_finite() const { return non_finite_; }

  // --- state and derived quantities
  const Kinematics& kinematics() const { return k_; }
  bool has_damage() const { return scene_.effects.damage; }
  const std::vector<double>& damage() const;  // all 0 without damage
  std::size_t broken_bond_count() const;  // directed bonds broken (incl. pre-cracks)
  std::vector<double> strain_energy_density() const;
  EnergyTotals energies() const;
  std::vector<LoadResultant> load_resultants() const;
  std::vector<double> displacement_xyz() const;  // 3 components per particle [m]
  std::vector<double> velocity_xyz() const;      // [m/s]
  // arrival_times()[t * n + i]: first time damage_i >= threshold t [s], -1 if never.
  const std::vector<double>& arrival_times() const { return arrival_; }
  const std::vector<double>& reference_x() const { return ref_x_; }
  const std::vector<double>& reference_y() const { return ref_y_; }
  const std::vector<double>& area() const { return area_; }

  // --- for checkpoints: the complete evolving state. damage.intact holds the
  // bond states in the kernel's own layout (the bond table's, or the lattice
  // kernel's: LatticeKernel::bond_states).
  struct State {
    long step = 0;
    double time = 0;
    double external_work = 0;
    Kinematics kinematics;
    DamageState damage;
    std::vector<double> arrival;
  };
  State save_state() const;
  // The same into an existing state, reusing its storage (no second copy in memory at once).
  void save_state(State& into) const;
  void restore_state(const State& state);
  // Breaks the bonds between the given pairs (i < j), in whichever directions
  // exist; the forces and damage follow at the next force computation.
  void break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs);

  // Moves particle positions directly (tests: impose a homogeneous deformation), then
  // recomputes the forces.
  void set_positions(const std::vector<double>& x, const std::vector<double>& y);
  // Sets all velocities (tests: a smooth initial velocity field) [m/s].
  void set_velocities(const std::vector<double>& vx, const std::vector<double>& vy);

private:
  void compute_forces();  // the kernel chosen at start, plus reactions and body forces
  void apply_velocity_constraints(double time_half, double time_end);
  void record_damage_arrivals();

  Scene scene_;
  PmbConstants pmb_;
  std::vector<double> ref_x_, ref_y_, area_;
  std::vector<double> lambda_;
  int lambda_iterations_ = 0;
  bool lambda_from_cache_ = false;
  std::uint64_t bond_count_ = 0;
  BondTable bonds_;  // all bonds, for the neighbour-list kernel; empty with the lattice kernel
  std::vector<ResolvedLoad> loads_;
  std::size_t precrack_cut_ = 0;
  double stable_dt_ = 0, dt_ = 0;
  double density_ = 0, thickness_ = 1;
  void (*kernel_)(const BondTable&, Kinematics&, DamageState*) = nullptr;

  long step_ = 0;
  double time_ = 0;
  double external_work_ = 0;
  Kinematics k_;
  // Without damage: no bond states, damage all zero. With the lattice kernel
  // the bond states are the kernel's and `intact` is empty.
  DamageState damage_;
  std::unique_ptr<LatticeKernel> lattice_;  // null when no particle qualifies or when disabled
  void (LatticeKernel::*lattice_compute_)(Kinematics&, const std::vector<double>&, const std::vector<double>&,
                                          std::vector<double>&) = nullptr;
  std::vector<double> arrival_;
  std::vector<LoadResultant> resultants_;
  NonFinite non_finite_;
};

}  // namespace pd::solver
