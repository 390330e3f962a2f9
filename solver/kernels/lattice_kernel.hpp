#pragma once
// The structured-lattice fast path of the bond forces (theory.md Sec. 1), for
// a bond-based model's pair law (Model::force_over_length, Model::holds,
// written once for scalars and 8 float lanes: deformed_bond.hpp, simd.hpp).
//
// NB-NUG grids are 97-99 % dx squares. A square whose whole family is squares
// at the same offsets as every other such square ("lattice particle") needs no
// neighbour list: its neighbours sit at fixed offsets in a padded 2D grid and
// every bond constant depends on the offset only. This kernel computes every
// bond that has a lattice particle at one end or both:
//
//  - Each pair is evaluated once, for the half of the stencil that points
//    "forward" (up, or right within a row), and its force is added to one end
//    and subtracted from the other: both directions of a bond carry exactly
//    opposite forces, and a pair has one state, so both directions break
//    together.
//  - Single precision (float) throughout the sweep: displacements, bond
//    constants, arithmetic and the per-particle sums. The extension is formed
//    as (2 xi.du + |du|^2) / (|y| + |xi|) from the displacement difference du,
//    free of the cancellation of |y| - |xi|, so its relative error stays at
//    float round-off (about 1e-7, far below the strains of interest). Float
//    sums make linear momentum conserved to float round-off (about 3e-8 of
//    its magnitude over 10,000 steps) instead of double round-off; double
//    sums cost 20 % of the speed and would not make the forces more accurate,
//    since the bond forces themselves are float (docs/solver.md, "Single
//    precision").
//  - A pair has one state: one bit (1/16 byte per directed bond), a byte per
//    8 cells and offset, tested and updated as a lane mask (simd.hpp). The damage index needs no arithmetic in the
//    sweep: when a pair breaks (rare), its weight is added, in integer units,
//    to the broken-bond sums of both ends.
//  - Nothing per bond is stored for lattice particles: their bonds come from
//    the stencil (compact_families.hpp). Memory: docs/performance.md.
//  - The sweep runs along grid rows, 8 consecutive cells at a time (SIMD), all
//    stencil offsets per 8 cells. Forces of the far ends land up to one
//    horizon of rows ahead: rows are processed in blocks of at least that
//    height, even blocks in parallel, then odd blocks. Each cell receives its
//    contributions in a fixed order whatever the thread count, and whatever
//    part of the grid is swept: the column tiles start at whole multiples of
//    the tile width, so that a process of a distributed run, sweeping its
//    slab only (LatticeSubdomain), adds in the one-process order.
//
// Lattice particles are those with stencil families (compact_families.hpp),
// less the squares that a general particle's bond reaches without the
// stencil's mirror (one-way bonds of NB-NUG grids at half-integer horizon
// factors; leave_lattice_where_pairs_differ). The others ("general") keep a
// neighbour list (the bond table, neighbor_kernel.hpp) for their bonds to
// other general particles, evaluated in the time loop each pair once in
// float (GeneralPairs below; dual-horizon rows of a bond-based model too);
// their bonds to lattice particles come from the sweep.
//
// Finer levels (the children of an adaptive refinement, theory.md Sec. 8.9):
// each level with lattice particles of its own has a sweep of its own, a
// LatticeKernel of that level alone (finer_ below) whose general particles
// are the owning kernel's; a pair between two levels is never a sweep's.
#include <cmath>
#include <cstdint>
#include <vector>

#include <functional>
#include <utility>

#include "bond_setup.hpp"
#include "bond_table.hpp"
#include "ghost_exchange.hpp"
#include "neighbor_kernel.hpp"
#include "particle_file.hpp"
#include "simd.hpp"
#include "uninitialised_vector.hpp"

namespace pd::solver {

struct EarlierLatticeMembership;  // below

// What the lattice kernel needs to know of the model at set-up (the sweep
// itself calls the model's law).
struct LatticeModelSetup {
  BondConstantsOf bond_constants;  // any bond's constants (checks; the general particles' table)
  // k of a bond with quadrature weight E [m^3] and rest length |xi| [m], before the surface correction.
  std::function<double(double energy_weight, double rest_length)> stiffness;
  double critical_stretch = 0;  // s0
  double dilatation_coefficient = 0;  // a of a state-based model (theory.md Sec. 5); unused by bond-based ones
  // Dual-horizon PD (theory.md Sec. 6.7); empty for one horizon. The rows of
  // the general particles' bonds among themselves (keep(i, j): both ends
  // general), each bond with its owner's constants and its dual entry
  // (variable_horizon_table), in place of the constant-horizon table. The
  // sweep's pairs then need both ends at the stencil's horizon (its
  // constants, `stiffness` and `critical_stretch`, are that horizon's), and
  // a pair stands for a bond and its dual bond: two entries of a row. A
  // state-based model's general particles sum their rows' own entries into
  // their dilatation, besides their pairs of the sweep (theory.md Sec. 6.8).
  // Called with each particle's lattice membership (1: lattice particle);
  // the rows hold the bonds whose ends are both general.
  std::function<BondTable(const std::vector<std::uint8_t>& is_lattice, std::vector<std::uint8_t>* intact)>
      dual_horizon_rows;
  double stencil_horizon = 0;  // [m], with dual_horizon_rows
  // The general particles' bonds among themselves each pair once in single
  // precision (GeneralPairs below; with dual horizons a bond-based model's
  // rows); false keeps the double lists or rows that evaluate each entry on
  // its own (for comparisons).
  bool general_pairs_in_float = true;
  // A plate on which no particle qualifies for the lattice (a free mesh has
  // no squares): false leaves the kernel empty, for the caller's own
  // neighbour lists (the dynamic force field); true makes every particle
  // general, so that the kernel's lists do all its work (the quasi-static
  // solver, whose held states, products and blocks are the kernel's).
  bool general_lists_without_lattice = false;
  // The set-up of a finer level's sweep (adaptive refinement's children,
  // theory.md Sec. 8.9): this set-up with `stiffness`, `critical_stretch` and
  // `stencil_horizon` of the level's horizon [m]. Empty: the sweep covers
  // level 0 only, and every square of a finer level is a general particle.
  std::function<LatticeModelSetup(double horizon)> at_level_horizon;
  // At an adaptive refinement event: every level's lattice membership
  // of the set before it, to take over where the event left a square's
  // family and neighbourhood alone (theory.md Sec. 8.9); null: decided for all.
  const EarlierLatticeMembership* earlier_membership = nullptr;
};

// The lattice membership of the particle set before a refinement event, and
// how the event's set descends from it (theory.md Sec. 8.9).
struct EarlierLatticeMembership {
  const Families* families = nullptr;  // the earlier set's
  const PerBond<double>* energy_weight = nullptr;  // its bond weights (the stencils' are compared)
  // Per earlier particle: 1 on a sweep of any level (KeptGeneralRows::is_lattice).
  const std::vector<std::uint8_t>* is_lattice = nullptr;
  // Per particle: its particle in the earlier set (Families::none for a
  // child), and the earlier particle whose family the split copied
  // (Families::none where the family was built).
  const std::vector<std::uint32_t>* origin = nullptr;
  const std::vector<std::uint32_t>* same_family = nullptr;
  // The event's set's longest possible bond [m] (EarlierRowStiffness::longest_bond):
  // the one-way checks look for bonds into the squares decided again only
  // among the particles within it (particles_near); 0: among all.
  double longest_bond = 0;
};

// One process's part of a run on several processes (docs/solver.md,
// "Running on several processes (MPI)"): its local particles are the owned
// ones (0 .. owned_count - 1) and the ghosts after them, and which of them
// are lattice particles was decided on the whole plate (a ghost's family is
// not local, so the local set-up cannot decide it). The sweep then computes
// every pair with an owned end exactly as a one-process run does; what it
// computes for ghosts is discarded by the caller.
struct LatticeSubdomain {
  std::size_t owned_count = 0;
  std::vector<std::uint8_t> is_lattice;  // per local particle: a lattice particle of the whole plate
};

class LatticeKernel {
public:
  using Real = float;                    // the sweep's arithmetic and storage (see above)
  static constexpr int lanes = simd::lanes;  // cells per SIMD step (8 floats = 256 bits)
  // SIMD steps per column tile of the sweeps (lattice_sweep.hpp): the rows a
  // tile reads and adds into stay in the L1 cache while it moves up a block.
  static constexpr std::int64_t tile_steps = 16;

  // The lattice particles are those with stencil families (compact_families.hpp;
  // a pre-crack's particles have listed ones), less the squares a pair of
  // the sweep would not compute as the model does (one-way bonds into them,
  // other constants: leave_lattice_where_pairs_differ).
  // With `subdomain` (a process of a distributed run), the lattice
  // particles are the subdomain's, and broken bonds count at owned ends only.
  LatticeKernel(const ParticleSet& particles, const BondSetup& bonds, const LatticeModelSetup& model,
                bool with_damage, const LatticeSubdomain* subdomain = nullptr);
  // Per particle: 1 for a lattice particle, as the constructor picks them
  // (empty when there is no lattice), without the sweep's grid, bond states
  // and the general particles' table: what the processes of a distributed run
  // pick their local lattice particles from (LatticeSubdomain::is_lattice).
  static std::vector<std::uint8_t> lattice_particles(const ParticleSet& particles, const BondSetup& bonds,
                                                     const LatticeModelSetup& model);

  // No lattice particle (with LatticeModelSetup::general_lists_without_lattice
  // the general particles' lists still do the work).
  bool empty() const { return particle_.empty(); }
  // Lattice particles among the owned ones (all particles on one process).
  // Lattice particles among the owned ones (all particles on one process), of every swept level.
  std::size_t particle_count() const;
  // Cells of the sweeps' grids (the local particles' window of each level's grid, about 40 bytes each).
  std::size_t grid_cell_count() const;
  // Squares with stencil families that left the lattice for the neighbour lists (owned ones).
  std::size_t moved_off_count() const;
  // Per level: the squares whose membership this set-up took over from the
  // set before a refinement event (LatticeModelSetup::earlier_membership);
  // empty when it took none over.
  const std::vector<std::size_t>& membership_taken_over_counts() const { return taken_over_by_level_; }
  // Per particle (local numbering): 1 for a lattice particle of this kernel.
  const std::vector<std::uint8_t>& lattice_membership() const { return is_lattice_; }
  std::size_t stencil_size() const { return 2 * offset_.size(); }  // bonds of a lattice particle

  // The bond states in the kernel's own layout (the sweep's state bytes, one
  // bit per pair slot, then one byte per bond of the general particles'
  // table), for checkpoints; empty without damage. set_bond_states takes them back.
  void bond_states(std::vector<std::uint8_t>& states) const;
  void set_bond_states(const std::vector<std::uint8_t>& states);
  // (The sweeps' state bytes level by level, then the general particles' table.)
  std::size_t bond_state_count() const;
  // The owned particles' bond states family by family, in the order of
  // `families` (1 intact, 0 broken): the layout of the neighbour lists, which
  // the gathered checkpoints of distributed runs keep whatever the kernel
  // (docs/formats.md). set_family_bond_states takes them back.
  void family_bond_states(const Families& families, std::vector<std::uint8_t>& states) const;
  void set_family_bond_states(const Families& families, const std::vector<std::uint8_t>& states);
  // The general particles' table's states entry by entry (with damage; 1
  // intact, 0 broken): on a process of a distributed dual-horizon run, whose
  // owned rows' dual entries carry bonds its families do not hold.
  void set_general_entry_states(const std::vector<std::uint8_t>& states);
  const std::vector<std::uint8_t>& general_entry_states() const { return general_intact_; }
  // The states of owned particle i's family alone, appended to `out` (with damage).
  void append_family_bond_states(const Families& families, std::uint32_t i, std::vector<std::uint8_t>& out) const;
  // Calls f(bond, intact) for each bond of owned particle i's family in the
  // family's order, where intact() looks the bond's state up only when
  // called (true without damage): the refinement criteria skip most bonds
  // on their lengths alone and need no state for those.
  template <class F>
  void for_each_family_bond(const Families& families, std::uint32_t i, F&& f) const {
    const bool with_damage = has_bond_states();
    auto general = with_damage ? general_bonds_.offsets[i] : 0;  // i's next own entry in the general table
    families.for_each_bond(i, [&](const BondRef& b) {
      const auto j = b.neighbor;
      const bool on_sweep = is_lattice_[i] || is_lattice_[j];
      const auto entry = on_sweep || !with_damage ? general : general++;
      f(b, [&, j, on_sweep, entry] {
        if (!with_damage) return true;
        return on_sweep ? sweep_of(i, j).pair_intact(sweep_of(i, j).pair_state_index(i, j)) : general_intact_[entry] != 0;
      });
    });
  }
  // The pairs (i < j) with a broken bond and an owned end, each once, in no
  // particular order, appended to `out`: those of the sweep from the zero
  // bits of `states` (the layout of bond_states: the state bytes, then the
  // general particles' table), those between general particles from their
  // rows' own entries. The same pairs as the family walk of
  // family_bond_states finds, without a lookup per bond (with damage).
  void broken_pairs(const std::vector<std::uint8_t>& states,
                    std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const;
  void broken_pairs(std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const;  // the current states
  std::size_t broken_bond_count() const;  // directed bonds (incl. pre-cracks)
  // Breaks the bond between i and j (both directions); false if there is none.
  bool break_pair(std::uint32_t i, std::uint32_t j);
  // Breaks the bonds of every pair (i, j) that has one, as break_pair one
  // pair at a time does; the general particles' rows each read once.
  void break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs);

  // Force densities of all particles (and, with damage, bond states and
  // damage index) from the displacements. `damage`: the damage index per
  // particle (unused without damage). With `energy_density` (a step that
  // reports energies), a bond-based model's sweep also sums every pair's
  // strain energy density 1/4 k e^2 to both ends, in single precision, and
  // fills energy_density [J/m^3] (all particles; the general particles'
  // bonds among themselves in double); a state-based model leaves it alone.
  // Defined in lattice_sweep.hpp.
  template <class Model, class Damage>
  void compute(Kinematics& k, std::vector<double>& damage, std::vector<double>* energy_density = nullptr);
  // Frees the sweep's per-cell sums (forces, and an energy row's energies)
  // and the general pairs' values until the next compute() or
  // force_change(), which allocates them again:
  // between evaluations they hold nothing (cleared as read), and an output
  // file's arrays can take their place (docs/performance.md, "Where the
  // memory goes"). Results do not change.
  void release_step_sums();

  // Whether the general particles' bonds among themselves go through the
  // float pairs (GeneralPairs) rather than the double lists.
  bool general_pairs_in_float() const { return general_pairs_.padded > 0; }
  std::size_t general_pair_count() const { return general_pairs_.pairs; }
  // The general particles' table (dual-horizon rows, or their bonds among
  // themselves), as set up: a later set-up copies rows of it (KeptGeneralRows).
  const BondTable& general_rows() const { return general_bonds_; }

  // For a state-based model (Model::has_pre_pass, theory.md Sec. 5): the
  // dilatation weights V_ij/|xi| of the sweep's pairs and the general
  // particles' bonds, and m_i. Throws if a pair's two directions differ.
  void add_dilatation_weights(const ParticleSet& particles, const BondSetup& bonds);
  // theta_i of the last compute() (state-based models; empty otherwise).
  const std::vector<double>& dilatation() const { return theta_; }
  // A process of a distributed run: the ghost exchanges
  // (ForceField::set_ghost_exchange). compute() starts the displacements'
  // exchange first and finishes it once the general pairs with owned ends
  // only are evaluated and the owned displacements are on the grid; a
  // state-based compute() does the same with theta_i / m_i between its
  // dilatation pass and its force pass (docs/solver.md, "Time loop").
  void set_ghost_exchange(GhostExchange exchange) { ghost_exchange_ = std::move(exchange); }

  // --- Energy minimisation (the quasi-static solver, docs/solver.md "Fast
  // kernels"). A minimisation evaluates forces at trial states at which no
  // bond may break (bonds break between minimisations, theory.md Sec. 4):
  // while held, compute() reads the bond states and changes none.
  void hold_bond_states(bool hold);
  // Replaces the general particles' table by its energy-symmetric form
  // (energy_bonds.hpp; the sweep's pairs are symmetric already), so that the
  // forces are minus the gradient of an energy. Needs damage on (states).
  void symmetrise_general_bonds(const ParticleSet& particles);
  // The force densities of compute() in double precision from the double
  // displacements (bond states read, not changed; `lambda`: the
  // surface-correction factors; `scratch`: per particle, overwritten): the
  // residual near convergence, where the float sweep's round-off is too
  // coarse. Defined in lattice_double.hpp.
  template <class Model>
  void compute_in_double(Kinematics& k, const std::vector<double>& lambda, std::vector<double>& scratch);

  // The tangent product: the change of the force densities of compute() when
  // the displacements of `k` (k.ux, k.uy: the state u, read) change by
  // (dx, dy), i.e. minus the Hessian of the energy at u times (dx, dy) per
  // unit area (Model::force_change: deformed directions and the geometric
  // term, theory.md Sec. 4.12), into k.fx, k.fy. The sweep's pairs in float
  // (8 lanes), the general particles' bonds among themselves in double;
  // bond states read, never changed. Defined in lattice_tangent.hpp.
  template <class Model>
  void force_change(Kinematics& k, const std::vector<double>& dx, const std::vector<double>& dy);

  // Per particle, the sum of k_ij n n^T [N/m^4] over its intact bonds (n the
  // reference direction; the sweep's pairs at both ends, surface correction
  // included, and the general particles' lists): the diagonal 2 x 2 block of
  // the small-strain Hessian per unit area, the quasi-static solver's
  // preconditioner (theory.md Sec. 4.12). Its trace is sum_j k_ij.
  void intact_stiffness_blocks(std::vector<double>& xx, std::vector<double>& xy, std::vector<double>& yy) const;
  // f(i, j, k_ij, n_x, n_y) for every intact bond i -> j (both directions of
  // a pair; n the reference direction xi / |xi|; k_ij as in the blocks above,
  // [N/m^4]), serially: the bonds the small-strain Hessian is made of (the
  // quasi-static solver's coarse correction, theory.md Sec. 4.13).
  template <class F>
  void for_each_intact_bond(F&& f) const {
    for_each_intact_general_bond(f);
    for (std::size_t g = 0; g < grid_particle_.size(); ++g) for_each_intact_pair_of(g, f);
  }

  // The strain energy density of every particle [J/m^3] (theory.md Sec. 1),
  // in double precision from the displacements; `lambda`: surface-correction
  // factors. Defined in lattice_sweep.hpp.
  template <class Model>
  void strain_energy_density(const Kinematics& k, const std::vector<double>& lambda,
                             std::vector<double>& energy_density) const;

private:
  // The constructor's work up to the choice of the lattice particles only
  // (lattice_particles); `swept`: the resolution level the kernel sweeps (a
  // finer level's kernel sweeps its level alone and has no general table).
  struct ChoiceOnly {};
  LatticeKernel(const ParticleSet& particles, const BondSetup& bonds, const LatticeModelSetup& model,
                bool with_damage, const LatticeSubdomain* subdomain, const ChoiceOnly* choice_only,
                std::uint8_t swept = 0, const std::vector<std::uint8_t>* earlier_verdict = nullptr);
  // Per particle, for the sweeps of every level: the earlier set's lattice
  // membership (0 or 1) where the event left the particle's family and
  // neighbourhood alone, decide_again where it is decided afresh (theory.md
  // Sec. 8.9); empty: every square decided afresh. decide_again_family_fits:
  // decided afresh for its neighbourhood's sake only, its own family copied
  // by the split from a particle on a sweep before the event, whose set test
  // that family passed (the same members, cells, weights and cuts): the
  // one-way check runs, the set test does not.
  static constexpr std::uint8_t decide_again = 2, decide_again_family_fits = 3;
  static bool decided_again(std::uint8_t verdict) { return verdict >= decide_again; }
  static std::vector<std::uint8_t> earlier_verdicts(const Families& families, const PerBond<double>& energy_weight,
                                                    const EarlierLatticeMembership& earlier);
  std::size_t membership_taken_over_ = 0;          // of this kernel's level
  std::vector<std::size_t> taken_over_by_level_;  // level 0's kernel: of every level
  std::uint8_t swept_ = 0;  // the level of the squares on this kernel's grid
  // The sweeps of the finer levels that have lattice particles (level 0's
  // kernel only; theory.md Sec. 8.9), and per particle which sweep holds it
  // as a lattice particle: 0 this one, l for finer_[l - 1], no_sweep for a
  // general particle (empty without finer sweeps).
  std::vector<LatticeKernel> finer_;
  static constexpr std::uint8_t no_sweep = 0xff;
  std::vector<std::uint8_t> sweep_index_;
  // The sweep that holds the pair of i and j (one of them a lattice particle).
  const LatticeKernel& sweep_of(std::uint32_t i, std::uint32_t j) const {
    if (finer_.empty()) return *this;
    const auto l = std::min(sweep_index_[i], sweep_index_[j]);
    return l == 0 ? *this : finer_[l - 1];
  }
  LatticeKernel& sweep_of(std::uint32_t i, std::uint32_t j) {
    return const_cast<LatticeKernel&>(std::as_const(*this).sweep_of(i, j));
  }
  bool has_bond_states() const;
  // Clears the state of the general table's entry b (bond b of row `from`
  // to `to`) and of its pair (break_pair, break_pairs).
  void break_general_entry(std::uint64_t b, std::uint32_t from, std::uint32_t to);
  // The sweep after `sweep` (this one, then finer_ in order), null after the last.
  LatticeKernel* next_sweep(const LatticeKernel* sweep) {
    if (finer_.empty()) return nullptr;
    const std::size_t next = sweep == this ? 0 : static_cast<std::size_t>(sweep - finer_.data()) + 1;
    return next < finer_.size() ? &finer_[next] : nullptr;
  }  // with damage (any sweep's state bits, or the general table's)
  // A finer level's square i qualifies for its level's sweep by its family:
  // the level's stencil (in any order: a child's built family lists its
  // members by index), each bond intact with the pair's constants.
  // The stencil bond o (forward[h] or backward[h]) that bond b of this
  // level's square i at column ci, row ri is, if the sweep's pair computes it
  // as the model does (rest length, stiffness with the surface correction,
  // partial volume, not cut by a pre-crack); -1 if not.
  long fitting_stencil_bond(const Families& families, const std::vector<double>& lambda,
                            const LatticeModelSetup& model, const std::vector<double>& rest,
                            const std::vector<std::size_t>& forward, const std::vector<std::size_t>& backward,
                            std::uint32_t i, long ci, long ri, const BondRef& b) const;
  // The same for bond b of i whose step is pair_of_step_'s v (>= 0: stencil_step).
  long fitting_stencil_step(const Families& families, const std::vector<double>& lambda,
                            const LatticeModelSetup& model, const std::vector<double>& rest,
                            const std::vector<std::size_t>& forward, const std::vector<std::size_t>& backward,
                            std::uint32_t i, const BondRef& b, int v) const;
  // The entry of pair_of_step_ for the step from the square at column ci,
  // row ri of this level to particle j; -1 if j is no square of this level
  // at a stencil step from it.
  int stencil_step(const Families& families, long ci, long ri, std::uint32_t j) const;
  bool family_is_stencil(std::uint32_t i, const Families& families, const std::vector<double>& lambda,
                         const LatticeModelSetup& model, const std::vector<double>& rest,
                         const std::vector<std::size_t>& forward, const std::vector<std::size_t>& backward) const;
  // This sweep's pair of i and j: breaks it (true) if it is one, leaves it alone (false) if not.
  bool break_sweep_pair(std::uint32_t i, std::uint32_t j);
  // The broken pairs of this sweep from its state bytes `state_bytes` (the layout of state_bits_).
  void append_sweep_broken_pairs(const std::uint8_t* state_bytes,
                                 std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const;
  // Takes off the lattice every square j with a general particle i whose
  // bond i -> j the sweep's pair would not reproduce, or that lacks the bond
  // to a lattice particle whose stencil holds it (lattice_kernel.cpp). `rest`,
  // `forward`, `backward`: the stencil's rest lengths and its two halves.
  // `earlier_verdict` (earlier_verdicts): only the squares decided again are
  // checked; the others keep the earlier set's membership.
  // `near_decided_again`: particles_near_decided_again's `near`.
  void leave_lattice_where_pairs_differ(const Families& families, const std::vector<double>& lambda,
                                        const LatticeModelSetup& model, const std::vector<double>& rest,
                                        const std::vector<std::size_t>& forward,
                                        const std::vector<std::size_t>& backward,
                                        const ParticleSet& particles,
                                        const std::vector<std::uint8_t>* earlier_verdict = nullptr,
                                        const std::vector<std::uint32_t>* near_decided_again = nullptr);
  // With `earlier_verdict`: the particles off the sweep whose check can
  // take a square off, those holding a bond into a square decided again or
  // at one of its stencil steps (theory.md Sec. 8.9); the check starts from
  // them instead of every particle off the sweep. `longest_bond` [m] > 0:
  // the listed families looked at are those of the particles within it of
  // such a square (particles_near), else every one; `near` (optional):
  // particles_near's answer for a superset of those squares, found before.
  std::vector<std::uint32_t> particles_near_decided_again(const Families& families,
                                                          const std::vector<std::uint8_t>& earlier_verdict,
                                                          const ParticleSet& particles, double longest_bond,
                                                          const std::vector<std::uint32_t>* near = nullptr) const;
  // A finer level's kernel at a refinement event: per particle, whether a
  // particle off this level's grid holds a bond into it (1), looked for
  // around this level's squares decided again; `near` gets the particles
  // within `longest_bond` [m] (> 0) of those squares (particles_near), for
  // particles_near_decided_again; with 0 every particle is looked at.
  std::vector<std::uint8_t> squares_held_from_off_grid(const Families& families,
                                                       const std::vector<std::uint8_t>& earlier_verdict,
                                                       const ParticleSet& particles, double longest_bond,
                                                       std::vector<std::uint32_t>& near) const;
  std::size_t moved_off_ = 0;
  // Without a lattice (LatticeModelSetup::general_lists_without_lattice):
  // every particle general, no grid; the table as make_general_table builds it.
  void take_every_particle_as_general(const ParticleSet& particles, const BondSetup& bonds,
                                      const LatticeModelSetup& model, bool with_damage);
  // The general particles' table of their bonds among themselves (general_
  // and, with dual horizons, border_ set), its states and float pairs.
  void make_general_table(const ParticleSet& particles, const BondSetup& bonds, const LatticeModelSetup& model,
                          bool with_damage);
  bool held_ = false;  // hold_bond_states
  // Dual horizons (LatticeModelSetup::dual_horizon_rows): a pair of the
  // sweep is a bond and its dual bond, two entries of a whole row, and weighs
  // twice in a general particle's damage index. 1 with one horizon.
  bool dual_horizon_ = false;
  double entries_per_pair_ = 1;

  // The force sweep of rows [first_row, last_row); with SumEnergy also the
  // pairs' strain energy densities into energy_ (compiled out otherwise).
  template <class Model, class Damage, bool SumEnergy>
  void sweep_rows(std::size_t first_row, std::size_t last_row);
  // The tangent product's sweep of rows [first_row, last_row) (lattice_tangent.hpp):
  // the displacements in ux_, uy_, the direction in dx_, dy_.
  template <class Model>
  void tangent_rows(std::size_t first_row, std::size_t last_row);
  std::vector<Real> dx_, dy_;  // the tangent product's direction on the grid (allocated at its first use)
  // A state-based model's two sweeps (lattice_sweep.hpp): the dilatation sums
  // of the pairs (where bonds break), then the forces from the pressures.
  template <class Model, class Damage>
  void dilatation_rows(std::size_t first_row, std::size_t last_row);
  template <class Model, class Damage>
  void state_force_rows(std::size_t first_row, std::size_t last_row);
  template <class Model, class Damage>
  void compute_state_based(Kinematics& k, std::vector<double>& damage);
  // compute()'s evaluation in one team of threads (compute() then clears the pairs' change flag).
  template <class Model, class Damage>
  void compute_in_one_team(Kinematics& k, std::vector<double>& damage, std::vector<double>* energy_density);
  // The general particles' dilatation sums over their rows into sum[i] (a
  // loop of a running team): whole rows with one horizon; with dual horizons
  // each row's own entries, which break at their owner's critical extension
  // (theory.md Sec. 6.8): a particle's theta is its rows' own entries plus
  // the sweep's pairs, its whole family.
  template <class Model, class Damage>
  void add_general_dilatation_sums_in_team(const Kinematics& k, std::uint8_t* intact, double* sum) const;
  // The steps of compute(), each a loop shared by the threads of a running
  // team (orphaned `omp for`; neighbor_kernel.hpp, "in team"). Scatters the
  // displacements to the grid; gathers the sweep's force sums (and damage)
  // into the particles after it (both end without a barrier).
  // Entries [first_entry, last_entry) of grid_particle_: the owned
  // particles' are [0, owned_grid_entries_), the ghosts' follow.
  void scatter_displacements_in_team(const Kinematics& k, std::int64_t first_entry, std::int64_t last_entry);
  // An overlapped evaluation's first part, once the owned particles' share
  // is done: waits for the ghosts' displacements, then runs the general
  // pairs' groups [early_groups, groups) (`pairs_in_team(first, last)`) and
  // scatters the ghosts' entries [early_entries, grid_entries()).
  template <class PairsInTeam>
  void finish_with_ghost_displacements_in_team(const Kinematics& k, std::int64_t early_groups, std::int64_t groups,
                                               std::int64_t early_entries, PairsInTeam&& pairs_in_team);
  std::int64_t grid_entries() const { return static_cast<std::int64_t>(grid_particle_.size()); }
  // `family_area`: the general particles' (the owning kernel's table's).
  template <class Damage, bool SumEnergy>
  void gather_forces_in_team(Kinematics& k, std::vector<double>& damage, double* energy_density,
                             const std::vector<double>& family_area);
  // Runs rows(first, last) over all row blocks in two colours (a block adds
  // only into itself and the next one); ends with a barrier.
  template <class Rows>
  void two_colour_sweep_in_team(Rows&& rows);
  // f(i, j, pair h, di, dj, state index) for every bond i -> j of grid particle
  // number g with a lattice end.
  template <class F>
  void for_each_pair_of(std::size_t g, F&& f) const {
    const auto i = grid_particle_[g];
    const auto cell = grid_cell_[g];
    const std::int64_t row = cell / row_length_;  // (once per particle: a division is slow)
    const std::size_t half = offset_.size();
    for (std::size_t o = 0; o < stencil_di_.size(); ++o) {
      const long di = stencil_di_[o], dj = stencil_dj_[o];
      const auto j = particle_at_[static_cast<std::size_t>(cell + dj * row_length_ + di)];
      if (j == Families::none || !(is_lattice_[i] || is_lattice_[j])) continue;
      const int v = pair_of_step_[static_cast<std::size_t>((dj + halo_) * (2 * halo_ + 1) + (di + halo_))];
      f(i, j, static_cast<std::size_t>(v) % half, di, dj, state_index(cell, row, di, dj));
    }
  }

  // for_each_intact_bond's two parts: the general particles' lists, and the
  // bonds of grid particle number g with a lattice end (the pair's stiffness
  // with the mean surface-correction factor of its ends).
  template <class F>
  void for_each_intact_general_bond(F&& f) const {
    for (auto i : general_)
      for (auto b = general_bonds_.offsets[i]; b < general_bonds_.offsets[i + 1]; ++b)
        if (general_intact_.empty() || general_intact_[b]) {
          const double length = general_bonds_.rest_length[b];
          f(i, general_bonds_.neighbor[b], general_bonds_.stiffness[b], general_bonds_.xi_x[b] / length,
            general_bonds_.xi_y[b] / length);
        }
  }
  template <class F>
  void for_each_intact_pair_of(std::size_t g, F&& f) const {
    for_each_pair_of(g, [&](std::uint32_t i, std::uint32_t j, std::size_t h, long di, long dj, std::uint64_t slot) {
      if (!state_bits_.empty() && !pair_intact(slot)) return;
      const double lambda_i = lambda_[static_cast<std::size_t>(cell_of_[i])];
      const double lambda_j = lambda_[static_cast<std::size_t>(cell_of_[j])];
      const double length = std::hypot(static_cast<double>(di), static_cast<double>(dj));
      f(i, j, 0.5 * (lambda_i + lambda_j) * pair_stiffness_[h], static_cast<double>(di) / length,
        static_cast<double>(dj) / length);
    });
  }

  // Grid geometry: padded row length (a multiple of `lanes`), the halo (the
  // stencil's reach in cells), and the grid cell of every square particle the
  // sweep reads (scattered every step).
  double spacing_ = 0;  // dx [m]
  std::int64_t row_length_ = 0, halo_ = 0;
  // A grid cell's index in the per-particle lists: 32 bits (4 bytes per
  // particle and list instead of 8; the grid is refused above 2^31 - 2 cells).
  using GridCell = std::int32_t;
  std::vector<std::uint32_t> grid_particle_;
  std::vector<GridCell> grid_cell_;
  // Forward half of the stencil: per offset, the grid-index step and the bond constants.
  std::vector<std::int64_t> offset_;
  std::vector<Real> xi_x_, xi_y_, rest_, half_stiffness_, critical_extension_;
  std::vector<Real> direction_x_, direction_y_;  // xi/|xi| (the state-based sweeps)
  std::vector<Real> released_critical_extension_;  // while held (hold_bond_states)
  double released_critical_stretch_ = 0;
  std::vector<double> pair_stiffness_;  // k of the pair without lambda, double (energies, checks)
  // Per grid row, the cells the sweep visits (a multiple of `lanes` from
  // first_cell) and where the row's state bytes start.
  struct RowSpan {
    std::int64_t first_cell = 0;
    std::int64_t steps = 0;  // SIMD steps of `lanes` cells
    std::uint64_t first_state = 0;
  };
  std::vector<RowSpan> rows_;
  std::size_t block_rows_ = 1;  // rows per block of the two-colour sweep
  // Pair states, one bit per pair (1 intact, 0 broken): a byte per row step
  // and offset, bit t for lane t (1/16 byte per directed bond). A state's
  // "slot" (state_index) is the bit's number. Empty without damage.
  std::vector<std::uint8_t> state_bits_;
  bool pair_intact(std::uint64_t slot) const { return (state_bits_[slot / lanes] >> (slot % lanes)) & 1u; }
  // Arrays on the grid: inputs (displacement, lambda, 1 at lattice particles)
  std::vector<Real> ux_, uy_, lambda_, lattice_mask_;
  // and the sums of the step: a cell's own forward pairs, and the far ends
  // of the pairs of the cells behind it.
  std::vector<Real> own_fx_, own_fy_, far_fx_, far_fy_;
  void allocate_step_sums();  // zeroed, if release_step_sums freed them (once per evaluation: no cost)
  // The strain energy density sums of an energy row's sweep, per cell (both
  // ends of every pair; cleared as read). Allocated at the first such row.
  std::vector<Real> energy_;
  // Damage: the broken pairs' weights phi A per cell, in whole units of
  // unit_area_ (kept up to date when a pair breaks, which is rare: the sweep
  // does no damage arithmetic); per pair its weight in units; the units of a
  // lattice particle's whole family; per border particle the float weights of
  // its bonds to lattice particles [m^2].
  std::vector<std::uint32_t> broken_units_;
  std::vector<std::uint32_t> weight_units_;
  std::uint64_t family_units_ = 0;
  double unit_area_ = 0;  // [m^2]
  std::vector<double> border_lattice_area_;
  std::uint64_t broken_directed_ = 0;  // directed bonds of the sweep broken (2 per pair; owned ends only)
  // Local particles 0 .. owned_count_ - 1 are owned (all on one process): a
  // broken pair counts one directed bond per owned end.
  std::size_t owned_count_ = 0, owned_lattice_count_ = 0;
  unsigned owned_ends(std::size_t cell, std::size_t far) const {
    return (particle_at_[cell] < owned_count_ ? 1u : 0u) + (particle_at_[far] < owned_count_ ? 1u : 0u);
  }
  // The pair states of offset h at 8 cells from `cell` went from `before` to
  // `after`: count the broken bonds (the caller stores the new states).
  void count_breaks(unsigned before, unsigned after, std::int64_t cell, std::size_t h);
  void recount_broken_units();  // from the states

  // The state-based sweeps' constants of each forward offset side by side,
  // refreshed at every compute (they follow critical_extension_ when bond
  // states are held). From separate arrays the sweeps' loops reloaded each
  // array's address for every pair: the stores into the far-end sums may
  // alias any memory as far as the compiler knows, so it cannot keep the
  // addresses in registers, and it has too few to keep them all anyway.
  struct PairConstants {
    std::int64_t offset;  // grid-index step to the far end
    Real xi_x, xi_y, rest, direction_x, direction_y;  // xi [m], |xi| [m], xi/|xi|
    Real half_stiffness, critical_extension, volume_over_length;
  };
  std::vector<PairConstants> pair_constants_;
  void refresh_pair_constants();

  // State-based models (theory.md Sec. 5): a, and per forward offset V/|xi|
  // (float for the sweep, double for the energy); per particle m_i, the sums
  // of the dilatation pass, theta_i and theta_i/m_i; per cell the pair sums
  // (own and far ends, as the forces) and theta/m for the force sweep.
  double dilatation_coefficient_ = 0;
  std::vector<Real> volume_over_length_;
  std::vector<double> pair_volume_over_length_;
  std::vector<double> weighted_volume_, theta_sum_, theta_, pressure_;
  std::vector<Real> own_theta_, far_theta_, pressure_grid_;
  GhostExchange ghost_exchange_;  // set_ghost_exchange (unset on one process)
  // The entries of grid_particle_ / grid_cell_ (ascending particles) of
  // owned particles: the ghosts' entries follow them (none on one process).
  std::int64_t owned_grid_entries_ = 0;

  // Lattice particles and their cells; general particles with a lattice
  // neighbour ("border") and their cells; all general particles.
  std::vector<std::uint32_t> particle_, border_;
  std::vector<GridCell> particle_cell_, border_cell_;
  std::vector<std::uint32_t> general_;
  // The general particles' bonds to general particles: a bond table of its own
  // (lattice particles have no bonds in it; family_area covers all particles)
  // and its states.
  BondTable general_bonds_;
  std::vector<std::uint8_t> general_intact_;

  // The general particles' bonds among themselves in the time loop: each
  // unordered pair once, in single precision, its
  // force formed once and added to both ends, as the sweep's pairs
  // (theory.md Sec. 1.6, "Each pair once"). The two directions of a pair
  // may differ on NB-NUG grids (k_ij != k_ji, V_ij != V_ji between free
  // cells, or no bond j -> i at all): a pair holds both directions'
  // constants, 0 for a direction that is no bond, so that each end gets
  // exactly its own list's force. With one horizon a pair has one state and breaks in both
  // directions at once (both directions see the same extension, so the
  // lists broke them together too). general_intact_ stays the record of the
  // states bond by bond (checkpoints, energies, the quasi-static products):
  // the pairs' states are copied into it by the gathers (the rows whose
  // pairs changed), and taken back from it wherever it is set from outside.
  // Empty in the quasi-static solver (energy-symmetric lists, held states), for a
  // state-based model's dual-horizon rows and when
  // LatticeModelSetup::general_pairs_in_float is off.
  // Dual horizons (bond-based models; make_dual_horizon_pairs): a pair's two
  // directions are two bonds, i -> j with i's constants and j -> i with j's
  // (either may be absent), each breaking on its own at its owner's critical
  // extension (theory.md Sec. 6.2). The pair's deformed bond is formed once;
  // each end gets its own bond's force with its own entry's stiffness and the
  // reaction of the other end's bond with its dual entry's (the rows' entries,
  // variable_horizon_bonds.hpp), so that each end receives what its row gives.
  // The pairs are stored as structures of arrays padded to a whole number
  // of 8-lane groups (padding pairs have zero constants and are broken), so
  // that the passes run 8 pairs at a time as the sweep does (simd.hpp).
  struct GeneralPairs {
    std::size_t pairs = 0;                     // the pairs of the table
    std::size_t padded = 0;                    // `pairs` rounded up to a multiple of 8
    // Groups [0, owned_groups) hold pairs of two owned particles only (every
    // group on one process): a distributed run evaluates them while the
    // ghosts' values travel. The pairs with a ghost end come after them.
    std::int64_t owned_groups = 0;
    // (Written pair by pair: make_dual_horizon_pairs sizes them for the most
    // pairs a table can give, unwritten, and cuts them to the pairs made.)
    UninitialisedVector<std::uint32_t> first, second;  // i and j: y = xi + u_j - u_i
    UninitialisedVector<Real> xi_x, xi_y, rest;        // xi_ij [m], |xi| [m]
    Real critical_stretch = 0;                 // s0: a pair breaks when e > s0 |xi|
    std::vector<Real> stiffness_first, stiffness_second;  // k_ij, k_ji [N/m^4] (0: no bond)
    // Dual horizons only, empty otherwise. Bond i -> j ("forward") pulls i
    // with stiffness_first and j with reaction_second; bond j -> i
    // ("backward") pulls j with stiffness_second and i with reaction_first
    // (the dual entries' k V_owner / V_end; a combined entry, which holds a
    // bond and its reverse's reaction, is all in its own direction's
    // stiffness: both break at the same step). Per direction its owner's
    // s0(delta) |xi| [m] (0 for an absent bond, whose state bit stays 0).
    std::vector<Real> reaction_first, reaction_second;  // [N/m^4]
    std::vector<Real> critical_extension_forward, critical_extension_backward;  // [m]
    // State-based models only (add_dilatation_weights), empty otherwise:
    std::vector<Real> volume_first, volume_second;  // V_ij/|xi|, V_ji/|xi| [m]
    // With damage: per group of 8 pairs one byte, bit t set while pair 8 g + t
    // holds (with dual horizons: while its bond i -> j holds; backward_intact_bits
    // the same for j -> i).
    std::vector<std::uint8_t> intact_bits, backward_intact_bits;
    // Per bond of general_bonds_: its end of its pair, p (i -> j) or padded + p (j -> i).
    // With dual horizons a row may hold two entries of a pair (a bond and
    // the reaction of its reverse): the first in row order reads the end's
    // value, the other zero_slot() (a value that stays 0).
    std::vector<std::uint32_t> slot;
    // Dual horizons only: per entry of general_bonds_, 2 p + 1 if it carries
    // bond j -> i of pair p, 2 p if i -> j (a combined entry: its own direction).
    std::vector<std::uint32_t> entry_direction;
    // Per end (index as slot), what it receives this step: the force density
    // [N/m^3] (x and y), or in the dilatation pass its term (value_x). Every
    // pass writes all 2 padded ends before a gather reads them, so they are
    // allocated unwritten (allocate_step_sums), only zero_slot() set to 0.
    UninitialisedVector<Real> value_x, value_y;
    // With damage: whether the states were set from outside since the last
    // gather (every row then takes them), and per particle whether a pass
    // changed the state of one of its pairs (its row takes them; both
    // cleared by the gather). A row none of whose pairs changed keeps its
    // damage over these bonds, `damage` below, and its per-bond states.
    std::uint8_t states_changed = 1;
    std::vector<std::uint8_t> row_changed;  // per particle
    std::vector<double> damage;  // per general particle (order of general_)
    std::size_t pair_of(std::uint32_t end) const { return end < padded ? end : end - padded; }
    bool holds(std::size_t pair) const { return (intact_bits[pair / 8] >> (pair % 8)) & 1u; }
    bool backward_holds(std::size_t pair) const { return (backward_intact_bits[pair / 8] >> (pair % 8)) & 1u; }
    // The state of the bond entry b of general_bonds_ carries.
    bool entry_holds(std::size_t b) const {
      if (entry_direction.empty()) return holds(pair_of(slot[b]));
      const std::uint32_t d = entry_direction[b];
      return d % 2 ? backward_holds(d / 2) : holds(d / 2);
    }
    std::uint32_t zero_slot() const { return static_cast<std::uint32_t>(2 * padded); }
    std::size_t value_count() const { return padded > 0 ? 2 * padded + 1 : 0; }  // both ends' values and the zero
  };
  GeneralPairs general_pairs_;
  void make_general_pairs(bool with_damage);
  void make_dual_horizon_pairs(bool with_damage);
  void pad_general_pairs();  // whole groups of 8 (both forms)
  void release_general_pairs();           // back to the double lists for good
  void take_general_pair_states();        // each pair's state from general_intact_
  // The pairs' loops (lattice_sweep.hpp), loops of a running team without a
  // barrier at their end: the pairs' forces (bond-based), the gather of the
  // values into the ends' sums (forces, damage and general_intact_), and a
  // state-based model's two pair passes and the dilatation's gather.
  // The passes over the pairs run over the groups [first_group, last_group).
  template <class Model, class Damage>
  void general_pair_forces_in_team(const Kinematics& k, std::int64_t first_group, std::int64_t last_group);
  template <class Model, class Damage>
  void dual_horizon_pair_forces_in_team(const Kinematics& k, std::int64_t first_group, std::int64_t last_group);
  template <class Damage>
  void gather_general_pair_forces_in_team(Kinematics& k, double* damage);
  template <class Model, class Damage>
  void general_pair_dilatation_in_team(const Kinematics& k, std::int64_t first_group, std::int64_t last_group);
  void gather_general_pair_dilatation_in_team();
  template <class Model, class Damage>
  void general_pair_state_forces_in_team(const Kinematics& k, std::int64_t first_group, std::int64_t last_group);
  std::int64_t general_pair_groups() const { return static_cast<std::int64_t>(general_pairs_.padded / simd::lanes); }
  // The full stencil in the bond table's order (a lattice particle's bond o
  // goes to cell + (di[o], dj[o])), and for any cell step (di, dj) within the
  // halo the pair it belongs to: forward offset h, or h + offsets for the
  // backward direction, -1 outside the stencil.
  std::vector<long> stencil_di_, stencil_dj_;
  std::vector<int> pair_of_step_;
  std::vector<GridCell> cell_of_;          // per particle: its grid cell, -1 if none
  std::vector<std::uint32_t> particle_at_;  // per grid cell: the particle the sweep reads there, or none
  std::vector<std::uint8_t> is_lattice_;  // per particle
  // Where the state of the pair (cell, cell + step (di, dj)) is.
  std::uint64_t state_index(std::int64_t cell, long di, long dj) const;
  // row = cell / row_length_. Inline: the energy and damage passes call it per pair.
  std::uint64_t state_index(std::int64_t cell, std::int64_t row, long di, long dj) const {
    int v = pair_of_step_[static_cast<std::size_t>((dj + halo_) * (2 * halo_ + 1) + (di + halo_))];
    const int half = static_cast<int>(offset_.size());
    if (v >= half) {  // backward: the pair is stored at the other end
      v -= half;
      cell += dj * row_length_ + di;
      row += dj;
    }
    const auto& span = rows_[static_cast<std::size_t>(row)];
    const auto index = static_cast<std::uint64_t>(cell - span.first_cell);
    return span.first_state + (index / lanes * offset_.size() + static_cast<std::uint64_t>(v)) * lanes + index % lanes;
  }
  // The same for the pair of grid particles i and j (a stencil step apart).
  std::uint64_t pair_state_index(std::uint32_t i, std::uint32_t j) const;
  // broken_pairs from the state bytes (every sweep's, level by level) and the general table's states.
  void append_broken_pairs(const std::uint8_t* state_bytes, const std::uint8_t* general_intact,
                           std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) const;
};

}  // namespace pd::solver
