#pragma once
// The internal forces of a run: the kernels of one model with one set of
// effects, chosen once (make_force_field, through model_registry.hpp) and
// then called through this interface, one virtual call per force evaluation.
// Inside, every loop is compiled for that model and those effects: a
// switched-off effect costs no test and no array.
//
// Kernels: dx squares whose family is the stencil go through the
// structured-lattice kernel (lattice_kernel.hpp), the other particles'
// bonds among themselves through neighbour lists (neighbor_kernel.hpp); with
// the lattice off (SetupOptions::lattice_kernel), every bond through the lists.
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "bond_setup.hpp"
#include "ghost_exchange.hpp"
#include "model_summary.hpp"
#include "particle_state.hpp"
#include "scene.hpp"

namespace pd::solver {

// The accumulated normal strains of the particles (ForceField::normal_strains).
struct NormalStrains {
  std::vector<double> xx, yy;            // eps_xx, eps_yy per particle
  std::vector<double> critical_stretch;  // s0 of each particle's own horizon
};

class ForceField {
public:
  virtual ~ForceField() = default;

  const ModelSummary& model() const { return model_; }
  bool damage_enabled() const { return damage_; }
  double stable_time_step() const { return stable_time_step_; }  // safety 1 [s]
  virtual std::size_t lattice_particle_count() const = 0;           // 0 without the lattice kernel
  virtual std::size_t lattice_grid_cell_count() const = 0;          // LatticeKernel::grid_cell_count, 0 without it
  // Squares with stencil families the lattice kernel left to the neighbour
  // lists (one-way bonds into them, LatticeKernel::moved_off_count).
  virtual std::size_t moved_off_lattice_count() const = 0;
  // Pairs of general particles evaluated each pair once in float (0 on the double lists).
  virtual std::size_t general_pair_count() const = 0;
  // The lattice kernel's table of its general particles' bonds among
  // themselves (LatticeKernel::general_rows), null without the kernel.
  virtual const BondTable* lattice_general_rows() const { return nullptr; }
  // The set-up's families, where the force field keeps them for the run
  // (a refinement run's, checkpoints of a distributed run), else null.
  virtual const Families* kept_families() const { return nullptr; }
  // Per level: the squares whose lattice membership the set-up took over
  // from the set before a refinement event (LatticeKernel::membership_taken_over_counts).
  virtual std::vector<std::size_t> lattice_membership_taken_over() const { return {}; }
  // A state-based model's dilatation theta_i of the last compute() (theory.md
  // Sec. 5); empty for a bond-based model. On a process of a distributed
  // run, for the owned particles only (a ghost's family is not local).
  virtual const std::vector<double>& dilatation() const = 0;

  // A distributed run (docs/solver.md, "Running on several processes"):
  // `exchange` brings the ghosts' displacements up to date from their owners
  // at the start of every compute() (which finishes it before anything reads
  // a ghost's displacement, computing what reads none in between), and a
  // state-based model's theta_i / m_i between its dilatation pass and its
  // forces, which read it at both ends of a bond; a bond-based model
  // exchanges no values. Unset (one process): no exchange.
  virtual void set_ghost_exchange(GhostExchange exchange) = 0;
  virtual int ghost_exchanges_per_evaluation() const = 0;  // value exchanges per compute()

  // Internal force densities of every particle into state.motion.fx, fy
  // [N/m^3], from the current positions; with damage, bonds over the critical
  // stretch break first and state.damage follows. With `energy_density` (a
  // step that reports energies) also W_i of the same displacements and bond
  // states [J/m^3], as strain_energy_density() gives it; the lattice sweep of
  // a bond-based model sums it during the force evaluation, in single
  // precision (docs/solver.md, "Single precision"), instead of a pass of its own.
  virtual void compute(ParticleState& state, std::vector<double>* energy_density = nullptr) = 0;
  // Frees what an evaluation uses as scratch only, before output files take
  // their own arrays; the next compute() makes it again (LatticeKernel::release_step_sums).
  virtual void release_evaluation_scratch() = 0;
  // After a completed step at `time`: the damage arrival times (with
  // damage). A loop for the threads of a running team, ending without a
  // barrier (an orphaned `omp for`, neighbor_kernel.hpp "in team"), so that
  // the step runs it in the region of its last per-particle pass; called
  // outside a parallel region, one thread runs it all.
  virtual void record_arrivals_in_team(ParticleState& state, double time) const = 0;
  // W_i = 1/4 sum_j k_ij e_ij^2 over intact bonds [J/m^3] (theory.md Sec. 1).
  virtual void strain_energy_density(const ParticleState& state, std::vector<double>& w) const = 0;
  // Directed bonds broken, pre-cracks included (the pre-cracks' only, without damage).
  virtual std::uint64_t broken_bond_count() const = 0;

  // The bond states in the kernels' own layout, for checkpoints (empty without damage).
  virtual void bond_states(std::vector<std::uint8_t>& states) const = 0;
  virtual void set_bond_states(const std::vector<std::uint8_t>& states) = 0;
  virtual std::size_t bond_state_count() const = 0;
  // The owned particles' bond states family by family, in the particle
  // file's order of each family's bonds (empty without damage): the layout
  // of the gathered checkpoints of distributed runs, whatever the kernel.
  virtual void family_bond_states(std::vector<std::uint8_t>& states) const = 0;
  virtual void set_family_bond_states(const std::vector<std::uint8_t>& states) = 0;
  // Whether set_family_bond_states takes the whole plate's states in that
  // layout instead of the owned particles' (a distributed run's
  // variable-horizon rows: an owned particle's row holds the dual entries of
  // bonds that particles of other processes own).
  virtual bool reads_whole_family_bond_states() const = 0;
  // Drops the families kept for a restart only (SetupOptions::keep_families),
  // once the bond states are converted.
  virtual void release_families_kept_for_restart() = 0;
  // Breaks the bonds between the given pairs (i < j, sorted) in whichever
  // directions exist; forces and damage follow at the next compute().
  virtual void break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) = 0;

  // For adaptive refinement (runs/adaptive_refinement.hpp): the pairs
  // (i < j, sorted) with a broken bond in either direction, the inverse of
  // break_pairs; and per particle the largest ratio of an intact bond's
  // extension to its critical extension (0 without intact bonds): on the
  // neighbour lists among the entries of its row, with the lattice kernel
  // among its own bonds (its family; a dual entry's bond is its owner's).
  // Not on the time-stepping path: called every few steps. `wanted` (per
  // particle, or empty for all): the particles whose ratio is asked for; the
  // others get 0 without their bonds being looked at.
  virtual std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs() const = 0;
  // The same pairs of bond states that bond_states gave earlier (of this force field).
  virtual std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs_in(
      const std::vector<std::uint8_t>& states) const = 0;
  virtual void largest_stretch_ratio(const ParticleState& state, std::vector<double>& ratio,
                                     const std::vector<std::uint8_t>& wanted) const = 0;
  // Per particle the accumulated normal strains along x and y over its own
  // intact bonds (its family; theory.md Sec. 8.1) and its own critical
  // stretch s0(delta_i). All three are 0 for the particles not `wanted`; an
  // axis's strain is 0 where no intact bond has an extent along it.
  virtual void normal_strains(const ParticleState& state, NormalStrains& strains,
                              const std::vector<std::uint8_t>& wanted) const = 0;

protected:
  ModelSummary model_;
  bool damage_ = false;
  double stable_time_step_ = 0;
};

// One process's part of a distributed run (docs/solver.md, "Running on
// several processes (MPI)"): the force field's particles are its local ones
// (owned first, then ghosts: setup/local_bonds.hpp); the lattice particles
// among them are chosen on the particles and set-up the process made: the
// whole plate's, or its slab's band's (three bond reaches wide, enough for
// the choice of every local particle: state/slab_band.hpp). `local_ids` are
// indices into those. The force field empties those particles and set-up
// (release_whole_plate) as soon as it has taken from them what it needs, so
// that they never live beside its own tables: a process's peak memory at
// set-up is then the larger of the two, not their sum.
struct ForceFieldSubdomain {
  ParticleSet& whole_particles;
  BondSetup& whole_setup;
  const std::vector<std::uint32_t>& local_ids;  // the local particles' indices in whole_particles, in local order
  std::size_t owned_count = 0;
  // The owners' values of one value per local particle overwrite the
  // ghosts' (Communicator::update_ghost_values; collective): the state-based
  // stable step's per-particle part, which a ghost's family gives.
  std::function<void(std::vector<double>&)> update_ghost_values;
  // A variable-horizon set-up on a slab's band (state/slab_band.hpp): per
  // particle of whole_particles, the first of its family's bonds among the
  // particle file's, and the file's directed bonds, so that the rows name
  // their bonds by the file's numbers (checkpoints). Null: the whole plate's
  // numbers are the file's.
  const std::vector<std::uint64_t>* file_family_start = nullptr;
  std::uint64_t file_bond_count = 0;
  // Whether any process's value is true (Communicator::any; collective):
  // a dual-horizon lattice split asks whether the plate has a lattice
  // particle. Empty: this process's value alone.
  std::function<bool(bool)> any_process = nullptr;
  void release_whole_plate() {
    whole_setup = BondSetup{};
    whole_particles = ParticleSet{};
  }
};

// The force field of `scene`'s model and effects on `particles` (cell
// polygons not read: the set-up has released them; families in `setup`);
// `subdomain` on a process of a distributed run.
// `rows`: the row stiffness sums to take over and to keep (SetupOptions;
// only the sums' two fields are read). `finer_level_sweeps`: in an adaptive
// run (scene.refinement.enabled) the squares of a finer level (the
// children) on sweeps of their own level (theory.md Sec. 8.9); false keeps
// them general particles of the lattice kernel (for comparisons).
std::unique_ptr<ForceField> make_force_field(const Scene& scene, const ParticleSet& particles,
                                             const BondSetup& setup, bool lattice_kernel,
                                             ForceFieldSubdomain* subdomain = nullptr,
                                             const SetupOptions* rows = nullptr,
                                             bool general_pairs_in_float = true, bool finer_level_sweeps = true);
// The same from a set-up that is no longer needed: the families it keeps are moved out of `setup`.
std::unique_ptr<ForceField> make_force_field(const Scene& scene, const ParticleSet& particles, BondSetup&& setup,
                                             bool lattice_kernel, ForceFieldSubdomain* subdomain = nullptr,
                                             const SetupOptions* rows = nullptr,
                                             bool general_pairs_in_float = true, bool finer_level_sweeps = true);

}  // namespace pd::solver
