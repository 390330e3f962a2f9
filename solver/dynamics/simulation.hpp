#pragma once
// Dynamics: the velocity-Verlet time integration of a particle state under
// the scene's loads (theory.md Sec. 4; Ha & Bobaru 2010). The run driver
// (runs/dynamic_run.hpp) adds files, progress and checkpoints around it;
// tests use it directly.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bond_setup.hpp"
#include "communicator.hpp"
#include "compact_families.hpp"
#include "force_field.hpp"
#include "loads.hpp"
#include "particle_file.hpp"
#include "particle_state.hpp"
#include "partition.hpp"
#include "scene.hpp"
#include "slab_band.hpp"

namespace pd::solver {

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
  bool found = false;  // on any process
  std::size_t particle = 0;  // local index
  std::string quantity;
  bool on_this_process = false;  // `particle` is one of this process's
};

class Simulation {
public:
  // `particles` with their families (tests, a refined set): copied without
  // the cells and families, which the set-up reads where they are.
  Simulation(const Scene& scene, const ParticleSet& particles, const SetupOptions& options = {});
  // `particles` without their families, which come compact (collected while
  // reading the particle file: compact_families.hpp). The simulation keeps
  // the particles as the reference configuration of its state.
  //
  // On several processes (docs/solver.md, "Running on several processes"):
  // `partition` says which particles this process owns (the communicator's
  // partition). The set-up is made on the whole plate as on one process, then
  // the simulation keeps its local particles only (owned first, then ghosts:
  // local_bonds.hpp), its lattice squares on the lattice sweep; a
  // variable-horizon run its owned particles' rows of the whole plate
  // (local_rows), whose dual entries reach ghosts up to the largest horizon
  // away (the partition's ghosts include them). Ghosts carry
  // displacements only (from their owners, before every force evaluation),
  // and with a state-based model theta / m (after its dilatation pass);
  // they have no bonds of their own, and what the sweep computes for them is
  // discarded, so their forces and velocities stay 0 and add nothing to the
  // sums over local particles.
  //
  // `whole_plate` (with `partition`): `particles` and `families` are this
  // process's slab's band only (state/slab_band.hpp), a constant-horizon
  // bond-based scene; the set-up is made on the band, the loads come
  // resolved on the whole plate, and the set-up's counts are summed over the
  // processes. The set-up of every owned particle and ghost equals the whole
  // plate's, so the run does too, bit for bit.
  Simulation(const Scene& scene, ParticleSet particles, Families families, const SetupOptions& options = {},
             const Communicator& communicator = serial_communicator(), const Partition* partition = nullptr,
             const WholePlateFacts* whole_plate = nullptr);
  // A distributed run's force field calls back into this object (its ghost exchange): it stays where it was made.
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // --- set-up facts
  const Scene& scene() const { return scene_; }
  const ModelSummary& model() const { return forces_->model(); }
  const SetupFacts& setup_facts() const { return facts_; }
  std::uint64_t bond_count() const { return facts_.bond_count; }  // directed bonds
  std::size_t precrack_bonds_cut() const { return facts_.precrack_cut; }
  const std::vector<ResolvedLoad>& loads() const { return loads_; }  // on this process's particles
  // The loads on the whole plate (the plan and summary.json).
  const std::vector<ResolvedLoad>& whole_loads() const { return distributed() ? whole_loads_ : loads_; }
  double stable_time_step() const { return stable_dt_; }  // the plate's (all processes), safety 1 [s]
  double time_step() const { return dt_; }                                 // used [s]
  // Whether the automatic step was capped at time.end (a stable step longer than the run).
  bool time_step_capped_at_end() const { return dt_capped_at_end_; }
  std::size_t particle_count() const { return state_.size(); }  // local: owned + ghosts
  std::size_t owned_count() const { return owned_count_; }       // local 0 .. owned_count - 1
  std::size_t whole_particle_count() const { return whole_count_; }
  bool distributed() const { return !global_id_.empty(); }
  // Global id (particle file index) of each local particle; empty on one process.
  const std::vector<std::uint32_t>& global_ids() const { return global_id_; }
  // Particles on the structured-lattice kernel (0 when it is off).
  std::size_t lattice_particle_count() const { return forces_->lattice_particle_count(); }
  std::size_t lattice_grid_cell_count() const { return forces_->lattice_grid_cell_count(); }  // this process's
  // Squares with stencil families that went to the neighbour lists instead (lattice_kernel.hpp).
  std::size_t moved_off_lattice_count() const { return forces_->moved_off_lattice_count(); }
  // Pairs of general particles evaluated once in float (LatticeKernel::GeneralPairs; 0 on the double lists).
  std::size_t general_pair_count() const { return forces_->general_pair_count(); }
  // The lattice kernel's general particles' table (null without the kernel):
  // the rows a refinement event's set-up copies (KeptGeneralRows).
  const BondTable* lattice_general_rows() const { return forces_->lattice_general_rows(); }
  // Per level: the squares whose lattice membership the set-up took over (theory.md Sec. 8.9).
  std::vector<std::size_t> lattice_membership_taken_over() const { return forces_->lattice_membership_taken_over(); }
  // theta_i of the last force evaluation (state-based models; empty otherwise).
  const std::vector<double>& dilatation() const { return forces_->dilatation(); }
  const Communicator& communicator() const { return comm_; }
  // Exchanges of one value per ghost in a force evaluation, besides the
  // displacements' (a state-based model's theta / m: 1; bond-based: 0).
  int ghost_value_exchanges_per_step() const { return forces_->ghost_exchanges_per_evaluation(); }

  // --- stepping
  // One velocity-Verlet step. `report_energy`: the step's force evaluation
  // also sums the strain energy density (for energies() and
  // strain_energy_density() at this step; on the lattice path inside the
  // force sweep, docs/performance.md), so that an energy row or a snapshot
  // needs no pass of its own.
  void step(bool report_energy = false);
  long step_index() const { return step_; }
  double time() const { return time_; }
  const NonFinite& non_finite() const { return non_finite_; }
  // Kinetic energy [J] summed during the last step's final pass, before the
  // end-of-step velocity constraints: cheap, for the per-step stability
  // check (energies() gives the exact value, in a fixed order).
  double step_kinetic_energy() const { return step_kinetic_energy_; }
  double external_work() const { return external_work_; }  // [J], accumulated since t = 0
  // The work the traction loads do over the next half step at today's
  // velocities [J], 0.5 dt sum_i f(t) b_i . v_i A_i h (all processes): what
  // the trapezoidal external work, which counts a step's loads over its
  // displacement, has not yet counted of the last half kick (docs/solver.md,
  // "Safety"). Collective.
  double traction_work_ahead() const;
  // Wall time of one force evaluation at set-up (at rest, or continue_from's) [s], for run-time estimates.
  double force_evaluation_seconds() const { return force_evaluation_seconds_; }

  // --- state and derived quantities
  const ParticleState& state() const { return state_; }
  const Kinematics& kinematics() const { return state_.motion; }
  bool has_damage() const { return forces_->damage_enabled(); }
  const std::vector<double>& damage() const { return state_.damage; }  // all 0 without damage
  std::uint64_t broken_bond_count() const;  // directed bonds broken (incl. pre-cracks)
  // W_i [J/m^3] at the current state: the one the last step summed when it
  // was asked to, else from a pass over the bonds (kept until the state changes).
  const std::vector<double>& strain_energy_density() const;
  EnergyTotals energies() const;
  const std::vector<LoadResultant>& load_resultants() const { return resultants_; }
  std::vector<double> displacement_xyz() const;  // 3 components per particle [m]
  std::vector<double> velocity_xyz() const;      // [m/s]
  // arrival_times()[t * n + i]: first time damage_i >= threshold t [s], -1 if never.
  const std::vector<double>& arrival_times() const { return state_.arrival; }
  const std::vector<double>& reference_x() const { return state_.x0(); }
  const std::vector<double>& reference_y() const { return state_.y0(); }
  const std::vector<double>& area() const { return state_.area(); }

  // --- for checkpoints: the complete evolving state. `bond_states` in the
  // force field's own layout (ForceField::bond_states). On several processes,
  // save_state and restore_state take the whole plate's state (gathered on
  // the root; every process picks its own particles out of it), with the
  // bond states of every particle's family one after the other in the
  // particle file's order: a checkpoint that any process count can restart.
  // One process restores either layout (bond_states_by_family); several
  // need the family layout, which a one-process state takes through
  // bond_states_by_family() of a one-process simulation (runs/checkpoint_layout.hpp).
  struct State {
    long step = 0;
    double time = 0;
    double external_work = 0;
    Kinematics kinematics;
    std::vector<double> damage;
    std::vector<std::uint8_t> bond_states;
    std::vector<double> arrival;
    bool bond_states_by_family = false;  // the family layout (saved on several processes)
  };
  State save_state() const;
  // The same state by reference, for writing it out without a copy: on one
  // process the simulation's own arrays (only the bond states, a few bits
  // per bond, are copied, into scratch.bond_states), on several the whole
  // plate gathered into `scratch` on the root (collective, as save_state).
  // Valid while the simulation and `scratch` stay as they are.
  struct StateView {
    long step = 0;
    double time = 0, external_work = 0;
    const Kinematics* kinematics = nullptr;
    const std::vector<double>* damage = nullptr;
    const std::vector<std::uint8_t>* bond_states = nullptr;
    const std::vector<double>* arrival = nullptr;
  };
  static StateView view_of(const State& s) {
    return {s.step, s.time, s.external_work, &s.kinematics, &s.damage, &s.bond_states, &s.arrival};
  }
  StateView state_view(State& scratch) const;
  // This process's bond states family by family (ForceField::family_bond_states:
  // the layout of a state saved on several processes). On one process the
  // set-up's families must be kept (SetupOptions::keep_families).
  void bond_states_by_family(std::vector<std::uint8_t>& into) const { forces_->family_bond_states(into); }
  // The same into an existing state, reusing its storage (no second copy in memory at once).
  void save_state(State& into) const;
  void restore_state(const State& state);
  // The same on one process with the state read straight into the
  // simulation's arrays: read(state) gets the simulation's own per-particle
  // vectors (their sizes the saved state's) and overwrites them, so a large
  // restart holds the saved state once (runs/dynamic_run.cpp). The saved
  // forces and damage are copied once more while the forces are recomputed.
  void restore_state_in_place(const std::function<void(State&)>& read);
  // A cheaper copy for rolling back after a blow-up, saved at every energy
  // row: displacements, velocities and bond states only (about 40 % of
  // save_state). roll_back recomputes the forces and the damage index from
  // them and clears the arrival times recorded after the saved time.
  void save_rollback_state(State& into) const;
  void roll_back(const State& state);
  // Before output files: frees the force evaluation's scratch, which the
  // next step makes again (ForceField::release_evaluation_scratch), so that
  // the files' arrays do not come on top of it. Results do not change.
  void release_evaluation_scratch() { forces_->release_evaluation_scratch(); }
  // Breaks the bonds between the given pairs (i < j, sorted), in whichever
  // directions exist; the forces and damage follow at the next force computation.
  void break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
    forces_->break_pairs(pairs);
    energy_density_current_ = false;
  }

  // --- adaptive refinement (runs/adaptive_refinement.hpp)
  // Pairs (i < j, sorted) with a broken bond in either direction; per particle
  // the largest extension / critical extension of its intact bonds.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs() const { return forces_->broken_pairs(); }
  // The bond states as they are now (the force field's own layout, a few
  // bits per bond), and the pairs they had broken, asked later (the same
  // simulation): what broke in between, without listing the pairs twice.
  void bond_states(std::vector<std::uint8_t>& into) const { forces_->bond_states(into); }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs_in(const std::vector<std::uint8_t>& states) const {
    return forces_->broken_pairs_in(states);
  }
  void largest_stretch_ratio(std::vector<double>& ratio, const std::vector<std::uint8_t>& wanted = {}) const {
    forces_->largest_stretch_ratio(state_, ratio, wanted);
  }
  // Per particle the accumulated normal strains along x and y and its own critical stretch.
  void normal_strains(NormalStrains& strains, const std::vector<std::uint8_t>& wanted = {}) const {
    forces_->normal_strains(state_, strains, wanted);
  }
  // Where a run left off, carried to a new (refined) particle set: the clock,
  // the external work, the motion and the arrival times per particle of this
  // set, and the pairs whose bonds are born broken.
  struct Continuation {
    long step = 0;
    double time = 0;
    double external_work = 0;
    std::vector<double> ux, uy, vx, vy;
    std::vector<double> arrival;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs;
    // The first set-up's pieces (a split joins each child to its parent's
    // piece, so the count stands; an event's set-up does not count them).
    PlatePieces pieces;
    std::size_t pieces_without_cuts = 0;
  };
  // Takes a run over on this particle set (built from the refined set,
  // SetupOptions::start_at_rest false):
  // breaks the pairs, then computes the forces and the damage from the carried
  // displacements. Returns the directed bonds that this force evaluation broke
  // (over-stretched by the carried displacements: damage the split made, 0 when it placed its children well).
  // The motion and arrival arrays are moved out of `c` (a refinement event
  // builds them for this set alone); its clock, pieces and pairs stay.
  std::uint64_t continue_from(Continuation&& c);

  // Sets the displacements directly [m] (tests: impose a homogeneous deformation;
  // the start of a switching scene), then recomputes the forces.
  void set_displacements(const std::vector<double>& ux, const std::vector<double>& uy);
  // Sets all velocities (tests: a smooth initial velocity field) [m/s].
  void set_velocities(const std::vector<double>& vx, const std::vector<double>& vy);

private:
  // The constructors' work: the set-up on `set_up_particles` (with their
  // cells and families) when given, `particles` being a copy without them
  // (copy_without_set_up_geometry), else on `particles`.
  Simulation(const Scene& scene, ParticleSet particles, const ParticleSet* set_up_particles, Families families,
             const SetupOptions& options, const Communicator& communicator, const Partition* partition,
             const WholePlateFacts* whole_plate);
  // The force field (with `energy_density`, also W_i), plus reactions and body forces.
  void compute_forces(std::vector<double>* energy_density = nullptr);
  // compute_forces(), its wall time kept in force_evaluation_seconds_.
  void compute_forces_timed();
  // The state at t = 0 (SetupOptions::start_at_rest): the initial
  // velocities, the forces, damage and velocity constraints at rest, the
  // damage already there (pre-cracks) as arrivals at t = 0, and the external work.
  void start_at_rest();
  // Kinetic energies (and the strain energy from `energy_density`, if given) in a fixed order.
  EnergyTotals energy_sums(const std::vector<double>* energy_density) const;
  void apply_velocity_constraints(double time_half, double time_end);
  // Distributed runs: the whole state from the local ones (root), and this process's part of a whole one.
  void gather_state(const State& local, State& whole) const;
  State local_part(const State& whole) const;
  // This process's own particles' state (the whole state on one process).
  void save_own_state(State& into) const;
  // `states_by_family`: the bond states in the gathered layout (ForceField::family_bond_states).
  void restore_own_state(State state, bool states_by_family);
  // Zeroes the ghosts' forces, damage and (if given) strain energy density
  // after a force evaluation (nothing on one process: there are no ghosts).
  void discard_ghost_results(std::vector<double>* energy_density);
  void discard_ghost_energy(std::vector<double>& energy_density) const;
  // Where each owned particle's bond states sit in the whole plate's (the particle file's order).
  void note_bond_state_rows(const Families& whole, const Partition& partition);
  void note_bond_state_rows(const WholePlateFacts& whole);

  Scene scene_;
  const Communicator& comm_;
  SetupFacts facts_;
  std::unique_ptr<ForceField> forces_;
  std::vector<ResolvedLoad> loads_;
  std::vector<ResolvedLoad> whole_loads_;  // distributed runs only
  double dt_ = 0;
  bool dt_capped_at_end_ = false;
  double stable_dt_ = 0;  // [s] the plate's stable limit at safety 1, the minimum over the processes
  double density_ = 0, thickness_ = 1;

  long step_ = 0;
  double time_ = 0;
  double external_work_ = 0;
  ParticleState state_;
  std::size_t owned_count_ = 0, whole_count_ = 0;
  std::vector<std::uint32_t> global_id_;             // per local particle (distributed runs)
  std::vector<std::uint64_t> owned_bond_state_start_;  // per owned particle: its row in the whole bond states
  std::vector<std::uint32_t> owned_bond_state_count_;  // per owned particle: the row's length
  std::uint64_t whole_bond_state_count_ = 0;
  std::vector<LoadResultant> resultants_;
  NonFinite non_finite_;
  double step_kinetic_energy_ = 0;
  double force_evaluation_seconds_ = 0;
  // W_i of the current state once computed (the state changes only through
  // this class, which marks it stale then, and frees it: a stale W_i is of
  // no use until an energy row or strain_energy_density() computes it again).
  mutable std::vector<double> energy_density_;
  mutable bool energy_density_current_ = false;
};

}  // namespace pd::solver
