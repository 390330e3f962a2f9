#include "force_field.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "error.hpp"
#include "lattice_kernel.hpp"
#include "lattice_sweep.hpp"
#include "local_bonds.hpp"
#include "model_registry.hpp"
#include "neighbor_kernel.hpp"
#include "particle_pairs.hpp"
#include "variable_horizon_bonds.hpp"

namespace pd::solver {
namespace {

template <class Model, class Damage>
class ForceFieldOf final : public ForceField {
public:
  ForceFieldOf(const Scene& scene, const ParticleSet& p, const BondSetup& setup, bool lattice_kernel,
               ForceFieldSubdomain* subdomain, const SetupOptions* rows, bool general_pairs_in_float,
               bool finer_level_sweeps)
      : general_pairs_in_float_(general_pairs_in_float),
        finer_level_sweeps_(finer_level_sweeps && scene.refinement.enabled),
        constants_(Model::constants(scene.material, setup.horizon)),
        thresholds_(scene.output.damage_thresholds),
        precrack_cut_(setup.precrack_cut),
        lambda_(setup.lambda),
        bonds_by_pair_(scene.refinement.enabled),
        keeps_families_for_restart_(rows && rows->keep_families) {
    model_ = Model::summary(constants_, scene.material.plane);
    damage_ = Damage::enabled;
    const BondConstantsOf bond_constants = bond_constants_of<Model>(p, setup, constants_);
    // Variable horizons (theory.md Sec. 6; horizon_mode.hpp): each bond with
    // its owner's constants.
    if (setup.horizon_mode != HorizonMode::uniform) {
      if (subdomain) {
        if (setup.horizon_mode == HorizonMode::dual_horizon && lattice_kernel &&
            distributed_dual_horizon_lattice(p, setup, scene.material, *subdomain))
          return;
        distributed_variable_horizon_rows(scene.material, *subdomain);
        return;
      }
      if constexpr (Model::has_pre_pass) {
        // A state-based model: dual horizons only (horizon_mode.cpp refuses
        // ordinary PD), each row's own entries before its dual entries
        // (theory.md Sec. 6.8). The stable step is the whole table's bound,
        // whichever kernel computes its bonds. With the lattice, the split
        // of Sec. 6.7 as for bond-based models: the sweep's pairs add their
        // dilatation terms to both ends, the general particles' rows their
        // own entries to their owners (Sec. 6.8, "With the lattice sweep"):
        // no table of every bond, so the bound is summed from the bonds (bit
        // for bit the table's, as a process of a distributed run sums its
        // rows'), and the table is built only where the rows take every bond.
        const double dilatation_coefficient = Model::dilatation_coefficient(constants_);
        if (lattice_kernel) {
          stable_time_step_ = dual_horizon_state_stable_time_step<Model>(p, setup, scene.material,
                                                                         dilatation_coefficient, scene.material.density);
          make_dual_horizon_lattice(p, setup, scene.material, rows);
        }
        if (lattice_) {
          lattice_->add_dilatation_weights(p, setup);
        } else {
          bonds_ = variable_horizon_table<Model>(p, setup, scene.material, setup.horizon_mode, Damage::enabled,
                                                 Damage::enabled ? &intact_ : nullptr);
          if (!lattice_kernel)
            stable_time_step_ =
                dual_horizon_state_stable_time_step(bonds_, dilatation_coefficient, scene.material.density);
          theta_.assign(p.size(), 0.0);
          pressure_.assign(p.size(), 0.0);
        }
      } else {
        // With dual horizons the squares whose whole family is squares at the
        // stencil's horizon go through the lattice sweep as in a
        // constant-horizon run (theory.md Sec. 6.7), the others keep
        // dual-horizon rows for their bonds among themselves; ordinary PD
        // runs on the neighbour lists.
        if (setup.horizon_mode == HorizonMode::dual_horizon) {
          // Every row's stiffness sum, whichever kernel computes its bonds:
          // the smallest step over both parts.
          KeptRowStiffness row_stiffness;
          row_stiffness.sums = dual_horizon_row_stiffness<Model>(
              p, setup, scene.material, rows ? rows->earlier_row_stiffness : nullptr, &row_stiffness.computed);
          stable_time_step_ = row_stable_time_step(row_stiffness.sums, scene.material.density);
          if (rows && rows->keep_row_stiffness) *rows->keep_row_stiffness = std::move(row_stiffness);
          if (lattice_kernel) make_dual_horizon_lattice(p, setup, scene.material, rows);
          if (lattice_) return;
        }
        bonds_ = variable_horizon_table<Model>(p, setup, scene.material, setup.horizon_mode, Damage::enabled,
                                               Damage::enabled ? &intact_ : nullptr);
        if (setup.horizon_mode == HorizonMode::ordinary_variable)
          stable_time_step_ = row_stable_time_step(bonds_, scene.material.density);
      }
      return;
    }
    if constexpr (Model::has_pre_pass) {
      // A state-based model: the stable step with the dilatation's coupling
      // (theory.md Sec. 5), streamed over the families; the whole bond table
      // only without a lattice.
      // On a process of a distributed run each owned particle's bound, from
      // its local family, with a ghost's own g_j / m_j^2 (which needs the
      // ghost's whole family) from its owner: the smallest over the
      // processes (Simulation) is the one-process value, bit for bit.
      stable_time_step_ = state_based_stable_time_step<Model>(
          p, setup, constants_, scene.material.density, subdomain ? &subdomain->update_ghost_values : nullptr);
      if (lattice_kernel) make_lattice(p, setup, bond_constants, subdomain);
      if (lattice_) {
        lattice_->add_dilatation_weights(p, setup);
      } else {
        bonds_ = bond_table(p, setup, bond_constants, constants_.critical_stretch, Damage::enabled,
                            Damage::enabled ? &intact_ : nullptr);
        add_dilatation_weights(p, setup, bonds_);
        theta_.assign(p.size(), 0.0);
        pressure_.assign(p.size(), 0.0);
      }
      return;
    }
    stable_time_step_ = pd::solver::stable_time_step<Model>(p, setup, constants_, scene.material.density);
    if (lattice_kernel) make_lattice(p, setup, bond_constants, subdomain);
    if (!lattice_)
      bonds_ = bond_table(p, setup, bond_constants, constants_.critical_stretch, Damage::enabled,
                          Damage::enabled ? &intact_ : nullptr);
  }

  void make_lattice(const ParticleSet& p, const BondSetup& setup, const BondConstantsOf& bond_constants,
                    ForceFieldSubdomain* subdomain = nullptr) {
    LatticeModelSetup model;
    model.bond_constants = bond_constants;
    model.stiffness = [this](double energy_weight, double rest_length) {
      return Model::bond_stiffness(constants_, 1.0, energy_weight, rest_length);
    };
    model.critical_stretch = constants_.critical_stretch;
    model.general_pairs_in_float = general_pairs_in_float_;
    if constexpr (Model::has_pre_pass) model.dilatation_coefficient = Model::dilatation_coefficient(constants_);
    if (!subdomain) {
      lattice_ = std::make_unique<LatticeKernel>(p, setup, model, Damage::enabled);
      keeps_families_ = bonds_by_pair_;  // largest_stretch_ratio
    } else {
      // The lattice particles of the whole plate (chosen as a one-process
      // kernel chooses them, without its grid and tables: the set-up is the
      // whole plate's on every process anyway), picked for the local ones.
      LatticeSubdomain local;
      local.owned_count = subdomain->owned_count;
      {
        LatticeModelSetup whole_model = model;
        whole_model.general_pairs_in_float = false;  // membership only: no time loop
        whole_model.bond_constants =
            bond_constants_of<Model>(subdomain->whole_particles, subdomain->whole_setup, constants_);
        const std::vector<std::uint8_t> membership =
            LatticeKernel::lattice_particles(subdomain->whole_particles, subdomain->whole_setup, whole_model);
        local.is_lattice.assign(subdomain->local_ids.size(), 0);
        if (!membership.empty())
          for (std::size_t l = 0; l < local.is_lattice.size(); ++l)
            local.is_lattice[l] = membership[subdomain->local_ids[l]];
      }
      subdomain->release_whole_plate();  // before the local kernel's tables
      lattice_ = std::make_unique<LatticeKernel>(p, setup, model, Damage::enabled, &local);
      keeps_families_ = true;  // for the checkpoints' family-by-family states
    }
    if (lattice_->empty()) lattice_.reset();
  }

  // A process's part of a variable-horizon run (docs/solver.md, "Running on
  // several processes (MPI)"): the rows of the particles set up (the whole
  // plate's, or its slab's band's), cut to the owned particles
  // (local_rows), every bond on them: ordinary PD, and dual horizons
  // without the lattice (distributed_dual_horizon_lattice makes their
  // lattice split), as a one-process run without the lattice sweep
  // evaluates them. The stable step by the
  // one-process formula of the mode over the owned rows (each the whole
  // plate's row, bit for bit; the smallest over the processes, Simulation,
  // is the one-process step): a band's rows at its edges lack bonds.
  // Only the bonds an owned row holds are given constants and rows (an
  // owned particle's own bonds; with dual horizons also the bonds towards
  // it; a state-based model's ghosts' own bonds too, whose g_j / m_j^2 the
  // stable step reads): a row of an owned particle holds the same entries in
  // the same order as the whole set-up's. Made piece by piece, so that a
  // process holds its slab's rows and a piece's bonds at its peak, not its
  // band's bonds and rows beside them.
  void distributed_variable_horizon_rows(const MaterialSpec& material, ForceFieldSubdomain& subdomain) {
    const ParticleSet& whole_particles = subdomain.whole_particles;
    const BondSetup& whole_setup = subdomain.whole_setup;
    const HorizonMode mode = whole_setup.horizon_mode;
    const std::vector<std::uint32_t> owned_rows(
        subdomain.local_ids.begin(), subdomain.local_ids.begin() + static_cast<std::ptrdiff_t>(subdomain.owned_count));
    const std::size_t owned_count = subdomain.owned_count;
    const std::vector<std::uint32_t>& ids = subdomain.local_ids;
    // Per particle of the set-up: 1 where keep() below looks (reset per piece).
    std::vector<std::uint8_t> marked(whole_particles.size(), 0);
    const auto mark = [&](std::size_t from, std::size_t to) {
      std::fill(marked.begin(), marked.end(), std::uint8_t{0});
      for (std::size_t l = from; l < to; ++l) marked[ids[l]] = 1;
    };
    // The rows of the marked particles: with dual horizons their own bonds
    // and the bonds towards them, in ordinary PD their own bonds. A
    // state-based model's stable step also reads its ghosts' own bonds: it
    // marks every local particle and keeps their own bonds.
    KeepBond keep;
    if (Model::has_pre_pass || mode != HorizonMode::dual_horizon)
      keep = [&marked](std::uint32_t i, std::uint32_t) { return marked[i] != 0; };
    else
      keep = [&marked](std::uint32_t i, std::uint32_t j) { return marked[i] != 0 || marked[j] != 0; };
    // Where each particle's family starts among the particle file's bonds
    // (a band's from the file; the whole plate's are the file's own).
    std::vector<std::uint64_t> plate_starts;
    if (!subdomain.file_family_start) plate_starts = family_starts(whole_setup.families);
    const std::vector<std::uint64_t>& file_start =
        subdomain.file_family_start ? *subdomain.file_family_start : plate_starts;
    whole_bond_count_ = subdomain.file_family_start ? subdomain.file_bond_count : whole_setup.families.bond_count();
    // The owned rows in pieces of about equal particle counts, each built
    // from its own bonds and cut at once: a piece's bonds with their
    // constants and its band's table are an eighth of the slab's at a time
    // (a bond between two pieces is made in both). A state-based model's
    // stable step reads the whole table's rows: one piece.
    const std::size_t piece_count =
        Model::has_pre_pass ? 1 : std::max<std::size_t>(1, std::min<std::size_t>(8, owned_count));
    const auto first_of_piece = [&](std::size_t k) { return owned_count * k / piece_count; };
    // Per particle of the set-up, the first and last piece one of its kept
    // bonds belongs to (its own, and with dual horizons those of the owned
    // particles it holds a bond to; no_piece first: none): a piece walks the
    // families of its owners only, the set-up's families once in all.
    constexpr std::uint32_t no_piece = 0xffffffffu;
    std::vector<std::uint32_t> piece_at(whole_particles.size(), no_piece);
    for (std::size_t k = 0; k < piece_count; ++k)
      for (std::size_t l = first_of_piece(k); l < first_of_piece(k + 1); ++l)
        piece_at[ids[l]] = static_cast<std::uint32_t>(k);
    std::vector<std::uint32_t> first_piece(whole_particles.size(), no_piece), last_piece(whole_particles.size(), 0);
    const auto touch = [&](std::uint32_t i, std::uint32_t k) {
      if (k == no_piece) return;
      if (first_piece[i] == no_piece || k < first_piece[i]) first_piece[i] = k;
      last_piece[i] = std::max(last_piece[i], k);
    };
    for (std::uint32_t i = 0; i < whole_particles.size(); ++i) {
      touch(i, piece_at[i]);
      if (mode == HorizonMode::dual_horizon && !Model::has_pre_pass)
        whole_setup.families.for_each_bond(i, [&](const BondRef& b) { touch(i, piece_at[b.neighbor]); });
    }
    const auto owners_of = [&](std::size_t from_piece, std::size_t to_piece) {
      std::vector<std::uint32_t> owners;
      for (std::uint32_t i = 0; i < whole_particles.size(); ++i)
        if (first_piece[i] != no_piece && first_piece[i] <= to_piece && last_piece[i] >= from_piece)
          owners.push_back(i);
      return owners;
    };
    if constexpr (!Model::has_pre_pass) {
      if (mode == HorizonMode::dual_horizon) {
        mark(0, owned_count);
        const std::vector<std::uint32_t> owners = owners_of(0, piece_count - 1);
        stable_time_step_ =
            owned_rows_stable_time_step(whole_particles, whole_setup, material, owned_rows, keep, &owners);
      }
    }
    std::vector<LocalRows> pieces;
    std::vector<std::size_t> first_rows;
    for (std::size_t k = 0; k < piece_count; ++k) {
      const std::size_t from = first_of_piece(k), to = first_of_piece(k + 1);
      mark(from, Model::has_pre_pass ? ids.size() : to);
      // (A state-based model's one piece: every local particle's own bonds.)
      const std::vector<std::uint32_t> owners = Model::has_pre_pass ? std::vector<std::uint32_t>{} : owners_of(k, k);
      std::vector<std::uint8_t> intact;
      std::vector<std::uint64_t> entry_bond;
      BondTable table;
      {
        std::vector<OwnedBond> bonds;
        std::vector<std::uint64_t> file_bond;  // per bond of `bonds`: its number among the file's
        for_each_owned_bond<Model>(
            whole_particles, whole_setup, material, mode, keep,
            [&](const OwnedBond& b, std::uint32_t place) {
              bonds.push_back(b);
              if (Damage::enabled) file_bond.push_back(file_start[b.owner] + place);
            },
            Model::has_pre_pass ? nullptr : &owners);
        if (k + 1 == piece_count) {
          plate_starts = {};
          subdomain.whole_setup = BondSetup{};  // the rows need the particles and the bonds alone
        }
        table = variable_horizon_rows(whole_particles, bonds, mode, Damage::enabled,
                                      Damage::enabled ? &intact : nullptr, Model::has_pre_pass,
                                      Damage::enabled ? &entry_bond : nullptr);
        std::vector<OwnedBond>().swap(bonds);
        for (std::uint64_t& e : entry_bond) e = file_bond[e];  // for the checkpoints' states
      }
      if constexpr (Model::has_pre_pass)
        stable_time_step_ = dual_horizon_state_stable_time_step(table, Model::dilatation_coefficient(constants_),
                                                                material.density, &owned_rows);
      pieces.push_back(local_rows(std::move(table), std::move(intact), std::move(entry_bond), ids, to, from));
      first_rows.push_back(from);
    }
    subdomain.release_whole_plate();
    LocalRows local = joined_rows(std::move(pieces), first_rows, owned_count);
    bonds_ = std::move(local.table);
    intact_ = std::move(local.intact);
    if (Damage::enabled) entry_bond_ = std::move(local.entry_bond);
    // Ordinary PD: the owned rows are the whole plate's, the ghosts' empty.
    if (!Model::has_pre_pass && mode == HorizonMode::ordinary_variable)
      stable_time_step_ = row_stable_time_step(bonds_, material.density);
    distributed_rows_ = true;
    owned_count_ = subdomain.owned_count;
    if constexpr (Model::has_pre_pass) {
      theta_.assign(bonds_.particle_count, 0.0);
      pressure_.assign(bonds_.particle_count, 0.0);
    }
  }

  // The stable step of a process's dual-horizon rows (bond-based model): the
  // one-process formula over the owned rows' whole stiffness sums (`keep`
  // holds every bond with an owned end), bit for bit each the whole plate's
  // sum; the smallest over the processes (Simulation) is the one-process step.
  static double owned_rows_stable_time_step(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                                            const std::vector<std::uint32_t>& owned_rows, const KeepBond& keep,
                                            const std::vector<std::uint32_t>* owners) {
    const std::vector<double> sums =
        dual_horizon_row_stiffness<Model>(p, setup, material, nullptr, nullptr, keep, owners);
    std::vector<double> owned_sums;
    owned_sums.reserve(owned_rows.size());
    for (const std::uint32_t i : owned_rows) owned_sums.push_back(sums[i]);
    return row_stable_time_step(owned_sums, material.density);
  }

  // A process's part of a dual-horizon run with the lattice split
  // (theory.md Secs. 6.7 and 6.8; docs/solver.md, "Running on several
  // processes (MPI)"): the lattice particles chosen on the set-up (the whole
  // plate's, or the slab's band's, whose families of the local particles and
  // of every particle within reach of them are whole) as a one-process run
  // chooses them; the sweep on the slab (LatticeSubdomain); the general
  // particles' rows of the owned ones, for their bonds among general
  // particles, built from the set-up's bonds with an owned end and cut as
  // local_rows cuts (a ghost's row empty: the float pairs with a ghost end
  // take all from the owned end's row); the stable step over the owned
  // rows. A state-based model's rows carry the dilatation's weights and
  // stay on the double rows (as on one process): each owned particle's
  // theta sums its rows' own entries and the sweep's pairs, a dual entry
  // reads its owner's theta / m, and a ghost's arrives with the step's
  // second exchange (LatticeKernel::compute). False (nothing made) where
  // the plate has no lattice particle.
  bool distributed_dual_horizon_lattice(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                                        ForceFieldSubdomain& subdomain) {
    const ParticleSet& whole_particles = subdomain.whole_particles;
    const BondSetup& whole_setup = subdomain.whole_setup;
    if (whole_setup.families.levels.empty()) return false;
    const double stencil_horizon = whole_setup.families.levels[0].horizon;
    if (!(stencil_horizon > 0)) return false;
    std::vector<std::uint8_t> membership;
    {
      LatticeModelSetup choice = dual_horizon_lattice_model(whole_particles, whole_setup, material, stencil_horizon);
      choice.general_pairs_in_float = false;  // membership only: no time loop
      // (Rows only mark the model dual-horizon: the choice builds none.)
      choice.dual_horizon_rows = [](const std::vector<std::uint8_t>&, std::vector<std::uint8_t>*) {
        return BondTable{};
      };
      membership = LatticeKernel::lattice_particles(whole_particles, whole_setup, choice);
      if (membership.empty()) membership.assign(whole_particles.size(), 0);  // (no lattice particle on the band)
    }
    // Whether the plate has a lattice particle: a band may have none where
    // the plate has some, and then its general rows go on the float pairs
    // as one process's do. (Collective: every process of the run asks.)
    const bool band_has_lattice = std::count(membership.begin(), membership.end(), std::uint8_t{1}) > 0;
    if (!(subdomain.any_process ? subdomain.any_process(band_has_lattice) : band_has_lattice)) return false;
    const std::vector<std::uint32_t>& ids = subdomain.local_ids;
    const std::size_t owned_count = subdomain.owned_count;
    const std::vector<std::uint32_t> owned_rows(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(owned_count));
    std::vector<std::uint8_t> owned(whole_particles.size(), 0);
    for (const std::uint32_t i : owned_rows) owned[i] = 1;
    if constexpr (Model::has_pre_pass) {
      // A state-based model's bound (theory.md Secs. 5.4, 6.8) also reads the
      // g_j / m_j^2 of the owners of the owned rows' dual entries, which are
      // local with their whole families: from the local particles' bonds,
      // without their table (which distributed_variable_horizon_rows builds).
      std::vector<std::uint32_t> owners(ids);
      std::sort(owners.begin(), owners.end());
      stable_time_step_ = dual_horizon_state_stable_time_step<Model>(
          whole_particles, whole_setup, material, Model::dilatation_coefficient(constants_), material.density,
          &owned_rows, &owners);
    } else {
      stable_time_step_ = owned_rows_stable_time_step(
          whole_particles, whole_setup, material, owned_rows,
          [&owned](std::uint32_t i, std::uint32_t j) { return owned[i] != 0 || owned[j] != 0; }, nullptr);
    }
    // The general rows of the owned particles: the bonds between general
    // particles with an owned end, each owned row as the whole plate's.
    LocalRows rows;
    {
      std::vector<std::uint64_t> plate_starts;
      if (!subdomain.file_family_start) plate_starts = family_starts(whole_setup.families);
      const std::vector<std::uint64_t>& file_start =
          subdomain.file_family_start ? *subdomain.file_family_start : plate_starts;
      whole_bond_count_ = subdomain.file_family_start ? subdomain.file_bond_count : whole_setup.families.bond_count();
      std::vector<OwnedBond> bonds;
      std::vector<std::uint64_t> file_bond;  // per bond of `bonds`: its number among the file's
      for_each_owned_bond<Model>(
          whole_particles, whole_setup, material, HorizonMode::dual_horizon,
          [&](std::uint32_t i, std::uint32_t j) {
            return !membership[i] && !membership[j] && (owned[i] != 0 || owned[j] != 0);
          },
          [&](const OwnedBond& b, std::uint32_t place) {
            bonds.push_back(b);
            if (Damage::enabled) file_bond.push_back(file_start[b.owner] + place);
          });
      std::vector<std::uint8_t> intact;
      std::vector<std::uint64_t> entry_bond;
      BondTable table = variable_horizon_rows(whole_particles, bonds, HorizonMode::dual_horizon, Damage::enabled,
                                              Damage::enabled ? &intact : nullptr, Model::has_pre_pass,
                                              Damage::enabled ? &entry_bond : nullptr);
      for (std::uint64_t& e : entry_bond) e = file_bond[e];  // for the checkpoints' states
      rows = local_rows(std::move(table), std::move(intact), std::move(entry_bond), ids, owned_count);
      if (Damage::enabled) {
        owned_file_start_.reserve(owned_count);
        for (const std::uint32_t i : owned_rows) owned_file_start_.push_back(file_start[i]);
      }
    }
    LatticeSubdomain local;
    local.owned_count = owned_count;
    local.is_lattice.reserve(ids.size());
    for (const std::uint32_t i : ids) local.is_lattice.push_back(membership[i]);
    subdomain.release_whole_plate();  // before the local kernel's tables
    LatticeModelSetup model = dual_horizon_lattice_model(p, setup, material, stencil_horizon);
    // A slab without a lattice particle: its general rows hold every bond.
    model.general_lists_without_lattice = true;
    std::vector<std::uint64_t> entry_bond = std::move(rows.entry_bond);
    model.dual_horizon_rows = [&rows](const std::vector<std::uint8_t>&, std::vector<std::uint8_t>* intact) {
      if (intact) *intact = std::move(rows.intact);
      return std::move(rows.table);
    };
    lattice_ = std::make_unique<LatticeKernel>(p, setup, model, Damage::enabled, &local);
    // m_i over each owned particle's whole family (the local set-up's; a
    // ghost has none locally, and its theta_j / m_j comes from its owner).
    if constexpr (Model::has_pre_pass) lattice_->add_dilatation_weights(p, setup);
    if (Damage::enabled) entry_bond_ = std::move(entry_bond);
    distributed_lattice_ = true;
    owned_count_ = owned_count;
    keeps_families_ = true;  // for the checkpoints' family-by-family states
    return true;
  }

  // The lattice model of a dual-horizon run on `p`: the sweep's pairs with
  // the constants of the stencil's horizon, any bond with its owner's.
  LatticeModelSetup dual_horizon_lattice_model(const ParticleSet& p, const BondSetup& setup,
                                               const MaterialSpec& material, double stencil_horizon) const {
    const auto stencil = Model::constants(material, stencil_horizon);
    auto own = std::make_shared<std::vector<typename Model::Constants>>();
    own->reserve(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) own->push_back(Model::constants(material, p.horizon[i]));
    LatticeModelSetup model;
    model.bond_constants = [&p, &setup, own](std::uint32_t i, const BondRef& b) {
      return bond_constants<Model>(p, setup, (*own)[i], i, b);
    };
    model.stiffness = [stencil](double energy_weight, double rest_length) {
      return Model::bond_stiffness(stencil, 1.0, energy_weight, rest_length);
    };
    model.critical_stretch = stencil.critical_stretch;
    // a of a state-based model does not depend on the horizon (theory.md Sec. 6.8).
    if constexpr (Model::has_pre_pass) model.dilatation_coefficient = Model::dilatation_coefficient(stencil);
    model.stencil_horizon = stencil_horizon;
    model.general_pairs_in_float = general_pairs_in_float_;
    return model;
  }

  // The lattice of a dual-horizon run: the sweep with the constants of the
  // stencil's horizon (its squares' pairs are constant-horizon PD, theory.md
  // Secs. 6.7 and 6.8), the general particles' dual-horizon rows, and the
  // checks of the general particles' bonds into the lattice with each owner's
  // constants. A state-based model adds the dilatation weights after it.
  void make_dual_horizon_lattice(const ParticleSet& p, const BondSetup& setup, const MaterialSpec& material,
                                 const SetupOptions* rows) {
    if (setup.families.levels.empty()) return;
    const double stencil_horizon = setup.families.levels[0].horizon;
    if (!(stencil_horizon > 0)) return;  // no square has a whole family: no lattice
    LatticeModelSetup model = dual_horizon_lattice_model(p, setup, material, stencil_horizon);
    // At an adaptive refinement event the rows the event left alone come
    // from the set before it (theory.md Sec. 8.7), and the set's own are
    // kept for the next event (bond-based models: a state-based model's
    // rows are built whole).
    const EarlierRowStiffness* earlier = rows ? rows->earlier_row_stiffness : nullptr;
    KeptGeneralRows* keep = rows && !Model::has_pre_pass ? rows->keep_general_rows : nullptr;
    model.dual_horizon_rows = [&p, &setup, &material, earlier, keep](const std::vector<std::uint8_t>& is_lattice,
                                                                     std::vector<std::uint8_t>* intact) {
      std::size_t copied = 0;
      BondTable table = dual_horizon_general_rows<Model>(p, setup, material, is_lattice, Damage::enabled, intact,
                                                         earlier, &copied);
      if (keep) {
        keep->intact = intact ? *intact : std::vector<std::uint8_t>(table.size(), 1);
        keep->is_lattice = is_lattice;
        keep->copied = copied;
      }
      return table;
    };
    // The squares of finer levels (an adaptive run's children) on sweeps of
    // their own level (theory.md Sec. 8.9), for a bond-based model: this
    // set-up (its dual-horizon rows too) at the level's horizon.
    if constexpr (!Model::has_pre_pass)
      if (finer_level_sweeps_)
        model.at_level_horizon = [base = model, &material](double horizon) {
          LatticeModelSetup level = base;
          const auto constants = Model::constants(material, horizon);
          level.stiffness = [constants](double energy_weight, double rest_length) {
            return Model::bond_stiffness(constants, 1.0, energy_weight, rest_length);
          };
          level.critical_stretch = constants.critical_stretch;
          level.stencil_horizon = horizon;
          return level;
        };
    // At an adaptive refinement event every level's lattice membership of the
    // squares the event left alone comes from the set before it (theory.md
    // Sec. 8.9): with the general rows taken over (no surface correction,
    // whose factors are the whole set's) and the weights of copied families.
    EarlierLatticeMembership earlier_membership;
    const EarlierBondWeights* earlier_weights = rows ? rows->earlier_weights : nullptr;
    if (model.at_level_horizon && earlier && earlier->general_rows && earlier_weights &&
        earlier_weights->families && earlier_weights->weights) {
      earlier_membership.families = earlier_weights->families;
      earlier_membership.energy_weight = earlier_weights->weights;
      earlier_membership.is_lattice = &earlier->general_rows->is_lattice;
      earlier_membership.origin = &earlier->origin;
      earlier_membership.same_family = &earlier_weights->same_family;
      earlier_membership.longest_bond = earlier->longest_bond;
      model.earlier_membership = &earlier_membership;
    }
    lattice_ = std::make_unique<LatticeKernel>(p, setup, model, Damage::enabled);
    if (lattice_->empty()) {
      lattice_.reset();
      return;
    }
    if (!bonds_by_pair_) return;
    keeps_families_ = true;  // largest_stretch_ratio
    own_critical_stretch_.reserve(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      own_critical_stretch_.push_back(Model::constants(material, p.horizon[i]).critical_stretch);
  }

  // The set-up's families, kept when the constructor found them needed
  // (keeps_families_): moved in where the caller's set-up is done with them.
  template <class SetupFamilies>
  void keep_families(SetupFamilies&& families) {
    if (keeps_families_ || keeps_families_for_restart_) families_ = std::forward<SetupFamilies>(families);
  }

  void release_families_kept_for_restart() override {
    if (keeps_families_for_restart_ && !keeps_families_) families_ = Families{};
    keeps_families_for_restart_ = false;
  }

  const std::vector<double>& dilatation() const override {
    return lattice_ ? lattice_->dilatation() : theta_;
  }

  void set_ghost_exchange(GhostExchange exchange) override {
    ghost_exchange_ = std::move(exchange);
    if (lattice_) lattice_->set_ghost_exchange(ghost_exchange_);
  }
  int ghost_exchanges_per_evaluation() const override { return Model::has_pre_pass ? 1 : 0; }

  std::size_t lattice_particle_count() const override { return lattice_ ? lattice_->particle_count() : 0; }
  std::size_t lattice_grid_cell_count() const override { return lattice_ ? lattice_->grid_cell_count() : 0; }
  std::size_t moved_off_lattice_count() const override { return lattice_ ? lattice_->moved_off_count() : 0; }
  std::size_t general_pair_count() const override {
    return lattice_ && lattice_->general_pairs_in_float() ? lattice_->general_pair_count() : 0;
  }
  const BondTable* lattice_general_rows() const override { return lattice_ ? &lattice_->general_rows() : nullptr; }
  const Families* kept_families() const override { return keeps_families_ ? &families_ : nullptr; }
  std::vector<std::size_t> lattice_membership_taken_over() const override {
    return lattice_ ? lattice_->membership_taken_over_counts() : std::vector<std::size_t>{};
  }

  void compute(ParticleState& s, std::vector<double>* energy_density) override {
    // The lattice kernel exchanges the ghosts' displacements itself, around
    // what reads no ghost; the neighbour lists alone read ghosts from the start.
    if (lattice_ && !Model::has_pre_pass) {  // the sweep sums the energy itself
      lattice_->compute<Model, Damage>(s.motion, s.damage, energy_density);
      return;
    }
    if (!lattice_) ghost_exchange_.displacements();
    compute_forces(s);
    if (energy_density) strain_energy_density(s, *energy_density);
  }

  void compute_forces(ParticleState& s) {
    if (lattice_) {
      lattice_->compute<Model, Damage>(s.motion, s.damage);
    } else if constexpr (Model::has_pre_pass) {
      // A state-based model: its per-particle pass (the dilatation, theory.md
      // Sec. 5) before the bond forces that read it at both ends of a bond.
      // For a bond-based model this branch is not compiled.
      std::uint8_t* intact = Damage::enabled ? intact_.data() : nullptr;
      double* damage = Damage::enabled ? s.damage.data() : nullptr;
      const double a = Model::dilatation_coefficient(constants_);
      if (!bonds_.dual_begin.empty()) {
        // Dual horizons (theory.md Sec. 6.8): each particle's dilatation over
        // its own bonds, each breaking at its owner's critical extension; a
        // dual entry carries its owner's theta / m, which for an owner on
        // another process arrives with the ghost exchange.
        compute_dilatation_with<Model, Damage>(bonds_, s.motion, intact, theta_.data(), pressure_.data(),
                                               PerBondCriticalExtension{bonds_.critical_extension.data()},
                                               OwnEntries{bonds_.dual_begin.data()});
        ghost_exchange_.values(pressure_);
        compute_dual_horizon_state_forces<Model, Damage>(bonds_, s.motion, intact, damage, pressure_.data(), a);
      } else {
        compute_dilatation<Model, Damage>(bonds_, s.motion, intact, theta_.data(), pressure_.data());
        ghost_exchange_.values(pressure_);  // the ghosts' theta_j / m_j from their owners
        compute_state_forces<Model, Damage>(bonds_, s.motion, intact, damage, pressure_.data(), a);
      }
    } else if (!bonds_.critical_extension.empty()) {
      // Variable horizons: each bond breaks at its owner's critical extension.
      compute_bond_forces_with<Model, Damage>(bonds_, s.motion, Damage::enabled ? intact_.data() : nullptr,
                                              Damage::enabled ? s.damage.data() : nullptr, nullptr,
                                              static_cast<std::int64_t>(bonds_.particle_count),
                                              PerBondCriticalExtension{bonds_.critical_extension.data()});
    } else {
      compute_bond_forces<Model, Damage>(bonds_, s.motion, Damage::enabled ? intact_.data() : nullptr,
                                         Damage::enabled ? s.damage.data() : nullptr, nullptr,
                                         static_cast<std::int64_t>(bonds_.particle_count));
    }
  }

  void record_arrivals_in_team(ParticleState& s, double time) const override {
    if constexpr (Damage::enabled) {
      const std::size_t n = s.size();
      const std::int64_t count = static_cast<std::int64_t>(n);
      const double* damage = s.damage.data();
      double* arrival = s.arrival.data();
      const auto& thresholds = thresholds_;
#pragma omp for schedule(static) nowait
      for (std::int64_t i = 0; i < count; ++i) {
        if (damage[i] == 0.0) continue;  // most particles: one test
        for (std::size_t t = 0; t < thresholds.size(); ++t) {
          double& first = arrival[t * n + static_cast<std::size_t>(i)];
          if (first < 0 && damage[i] >= thresholds[t]) first = time;
        }
      }
    }
  }

  void strain_energy_density(const ParticleState& s, std::vector<double>& w) const override {
    w.assign(s.size(), 0.0);
    if (lattice_)
      lattice_->strain_energy_density<Model>(s.motion, lambda_, w);
    else if constexpr (Model::has_pre_pass)
      add_state_energy_density<Model>(bonds_, s.motion, Damage::enabled ? intact_.data() : nullptr,
                                      Model::dilatation_coefficient(constants_), w);
    else
      add_bond_energy_density<Model>(bonds_, s.motion, Damage::enabled ? intact_.data() : nullptr, w);
  }

  void release_evaluation_scratch() override {
    if (lattice_) lattice_->release_step_sums();
  }
  std::uint64_t broken_bond_count() const override {
    if constexpr (!Damage::enabled) return precrack_cut_;
    if (lattice_) return lattice_->broken_bond_count();
    // A process's rows: the owned particles' own bonds (their dual entries
    // here are other processes' bonds, counted there).
    if (distributed_rows_) return broken_own_entries(bonds_, intact_);
    return broken_directed_bonds(bonds_, intact_);
  }

  void bond_states(std::vector<std::uint8_t>& states) const override {
    if constexpr (!Damage::enabled) states.clear();
    else if (lattice_) lattice_->bond_states(states);
    else states = intact_;
  }

  void set_bond_states(const std::vector<std::uint8_t>& states) override {
    if constexpr (Damage::enabled) {
      if (lattice_) lattice_->set_bond_states(states);
      else intact_ = states;
    }
  }

  void family_bond_states(std::vector<std::uint8_t>& states) const override {
    if constexpr (!Damage::enabled) states.clear();
    else if (lattice_) lattice_->family_bond_states(families_, states);
    else if (distributed_rows_ || !bonds_.dual_begin.empty()) own_entry_states(states);
    else states = intact_;  // the neighbour lists keep the families' order (bond_table)
  }

  // The owned rows' own entries in row order (every row on one process):
  // each owned particle's bonds in family order (variable_horizon_rows fills
  // a row's front so).
  void own_entry_states(std::vector<std::uint8_t>& states) const {
    states.clear();
    const std::size_t rows = distributed_rows_ ? owned_count_ : bonds_.particle_count;
    for (std::size_t i = 0; i < rows; ++i)
      states.insert(states.end(), intact_.begin() + static_cast<std::ptrdiff_t>(bonds_.offsets[i]),
                    intact_.begin() + static_cast<std::ptrdiff_t>(bonds_.own_end(i)));
  }

  bool reads_whole_family_bond_states() const override { return distributed_rows_ || distributed_lattice_; }

  void set_family_bond_states(const std::vector<std::uint8_t>& states) override {
    if constexpr (Damage::enabled) {
      if (lattice_ && distributed_lattice_) {
        // The whole plate's states: the sweep's pairs and the general
        // entries' own bonds from the owned families, then every general
        // entry from its bond's state (a dual entry takes its owner's, which
        // may be a ghost's).
        if (states.size() != whole_bond_count_)
          throw Error("the saved bond states do not fit the particle set's families");
        std::vector<std::uint8_t> owned_states;
        for (std::size_t l = 0; l < owned_count_; ++l) {
          const auto from = states.begin() + static_cast<std::ptrdiff_t>(owned_file_start_[l]);
          owned_states.insert(owned_states.end(), from,
                              from + static_cast<std::ptrdiff_t>(families_.family_size(static_cast<std::uint32_t>(l))));
        }
        lattice_->set_family_bond_states(families_, owned_states);
        std::vector<std::uint8_t> entry_states(entry_bond_.size());
        for (std::size_t e = 0; e < entry_bond_.size(); ++e) entry_states[e] = states[entry_bond_[e]];
        lattice_->set_general_entry_states(entry_states);
      } else if (lattice_) {
        lattice_->set_family_bond_states(families_, states);
        // One process's dual-horizon general rows: their dual entries from their owners' bonds.
        const BondTable& rows = lattice_->general_rows();
        if (!rows.dual_begin.empty()) {
          std::vector<std::uint8_t> entry_states = lattice_->general_entry_states();
          set_entry_states_from_families(rows, nullptr, entry_states);
          lattice_->set_general_entry_states(entry_states);
        }
      } else if (distributed_rows_) {
        // The whole plate's states: a dual entry takes its owner's bond's.
        if (states.size() != whole_bond_count_)
          throw Error("the saved bond states do not fit the particle set's families");
        for (std::size_t e = 0; e < intact_.size(); ++e) intact_[e] = states[entry_bond_[e]];
      } else if (!bonds_.dual_begin.empty()) {
        // One process's dual-horizon rows: the own entries in family order, a dual entry its owner's bond's.
        set_entry_states_from_families(bonds_, &states, intact_);
      } else {
        if (states.size() != intact_.size())
          throw Error("the saved bond states do not fit this process's families");
        intact_ = states;
      }
    }
  }

  std::size_t bond_state_count() const override {
    if constexpr (!Damage::enabled) return 0;
    return lattice_ ? lattice_->bond_state_count() : intact_.size();
  }

  void break_pairs(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) override {
    if constexpr (Damage::enabled) {
      if (lattice_) {
        lattice_->break_pairs(pairs);
        return;
      }
      // A pair is broken in whichever directions the bond table holds (on
      // non-uniform grids a pair may be there in one only).
      for (std::uint32_t i = 0; i < bonds_.particle_count; ++i)
        for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) {
          const std::uint32_t j = bonds_.neighbor[b];
          if (std::binary_search(pairs.begin(), pairs.end(), std::pair{std::min(i, j), std::max(i, j)}))
            intact_[b] = 0;
        }
    }
  }

  std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs() const override {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if constexpr (Damage::enabled) {
      if (lattice_) lattice_->broken_pairs(pairs);
      else append_broken_list_pairs(intact_, pairs);
    }
    return sorted_unique_pairs(pairs);  // (a pair broken both ways, or in a dual entry too, comes twice)
  }

  std::vector<std::pair<std::uint32_t, std::uint32_t>> broken_pairs_in(
      const std::vector<std::uint8_t>& states) const override {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if constexpr (Damage::enabled) {
      if (lattice_) {
        lattice_->broken_pairs(states, pairs);
      } else {
        if (states.size() != intact_.size())
          throw Error("ForceField::broken_pairs_in: the bond states do not fit this force field's bonds");
        append_broken_list_pairs(states, pairs);
      }
    }
    return sorted_unique_pairs(pairs);  // (a pair broken both ways, or in a dual entry too, comes twice)
  }

  void largest_stretch_ratio(const ParticleState& s, std::vector<double>& ratio,
                             const std::vector<std::uint8_t>& wanted) const override {
    if (lattice_) {
      lattice_stretch_ratio(s, ratio, wanted);
      return;
    }
    const Kinematics& k = s.motion;
    ratio.assign(bonds_.particle_count, 0.0);
    const std::int64_t n = static_cast<std::int64_t>(bonds_.particle_count);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      if (!wanted.empty() && !wanted[i]) continue;
      double largest = 0;
      for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b) {
        if (Damage::enabled && !intact_[b]) continue;
        const auto j = bonds_.neighbor[b];
        const double yx = bonds_.xi_x[b] + (k.ux[j] - k.ux[i]), yy = bonds_.xi_y[b] + (k.uy[j] - k.uy[i]);
        const double rest = bonds_.rest_length[b];
        const double critical =
            bonds_.critical_extension.empty() ? bonds_.critical_stretch * rest : bonds_.critical_extension[b];
        if (!(critical > 0)) continue;
        // Only a bond that may beat `largest` needs its length: |y| > rest + largest * critical.
        const double beaten = rest + largest * critical;
        if (yx * yx + yy * yy <= beaten * beaten) continue;
        largest = std::max(largest, (std::hypot(yx, yy) - rest) / critical);
      }
      ratio[i] = largest;
    }
  }

  void normal_strains(const ParticleState& s, NormalStrains& strains,
                      const std::vector<std::uint8_t>& wanted) const override {
    if (lattice_) {
      lattice_normal_strains(s, strains, wanted);
      return;
    }
    const Kinematics& k = s.motion;
    const auto& area = s.area();
    const std::size_t n = bonds_.particle_count;
    strains.xx.assign(n, 0.0);
    strains.yy.assign(n, 0.0);
    strains.critical_stretch.assign(n, 0.0);
    const std::int64_t count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < count; ++i) {
      if (!wanted.empty() && !wanted[i]) continue;
      // i's own entries only: a dual entry is a bond of another horizon (theory.md Sec. 8.1).
      const auto begin = bonds_.offsets[i], end = bonds_.own_end(i);
      if (begin == end) continue;
      strains.critical_stretch[i] = bonds_.critical_extension.empty()
                                        ? bonds_.critical_stretch
                                        : bonds_.critical_extension[begin] / bonds_.rest_length[begin];
      AxisStrainSums sums;
      for (auto b = begin; b < end; ++b) {
        if (Damage::enabled && !intact_[b]) continue;
        const auto j = bonds_.neighbor[b];
        sums.add(area[j], bonds_.xi_x[b], bonds_.xi_y[b], k.ux[j] - k.ux[i], k.uy[j] - k.uy[i]);
      }
      strains.xx[i] = sums.xx();
      strains.yy[i] = sums.yy();
    }
  }

private:
  // The least-squares normal strains of one family (theory.md Sec. 8.1):
  // eps_ii = sum_j V_j (du.n_i)(xi.n_i) / sum_j V_j (xi.n_i)^2, no square root.
  struct AxisStrainSums {
    double du_xi_x = 0, xi_xi_x = 0, du_xi_y = 0, xi_xi_y = 0;
    void add(double volume, double xi_x, double xi_y, double du_x, double du_y) {
      du_xi_x += volume * du_x * xi_x;
      xi_xi_x += volume * xi_x * xi_x;
      du_xi_y += volume * du_y * xi_y;
      xi_xi_y += volume * xi_y * xi_y;
    }
    double xx() const { return xi_xi_x > 0 ? du_xi_x / xi_xi_x : 0.0; }
    double yy() const { return xi_xi_y > 0 ? du_xi_y / xi_xi_y : 0.0; }
  };

  // normal_strains with the lattice kernel: each particle's own bonds from
  // its family, with their states from the lattice (as lattice_stretch_ratio).
  void lattice_normal_strains(const ParticleState& s, NormalStrains& strains,
                              const std::vector<std::uint8_t>& wanted) const {
    require_bonds_by_pair("normal_strains");
    const Kinematics& k = s.motion;
    const auto& x = s.x0();
    const auto& y = s.y0();
    const auto& area = s.area();
    const std::size_t n = families_.particle_count;
    strains.xx.assign(n, 0.0);
    strains.yy.assign(n, 0.0);
    strains.critical_stretch.assign(n, 0.0);
    for (std::uint32_t i = 0; i < n; ++i) {
      if (!wanted.empty() && !wanted[i]) continue;
      strains.critical_stretch[i] = own_critical_stretch_.empty() ? constants_.critical_stretch : own_critical_stretch_[i];
      AxisStrainSums sums;
      lattice_->for_each_family_bond(families_, i, [&](const BondRef& b, const auto& intact) {
        if (!intact()) return;
        const auto j = b.neighbor;
        sums.add(area[j], x[j] - x[i], y[j] - y[i], k.ux[j] - k.ux[i], k.uy[j] - k.uy[i]);
      });
      strains.xx[i] = sums.xx();
      strains.yy[i] = sums.yy();
    }
  }

  // The pairs of the lists' entries that `intact` (per entry of bonds_) has broken.
  void append_broken_list_pairs(const std::vector<std::uint8_t>& intact,
                                std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) const {
    for (std::uint32_t i = 0; i < bonds_.particle_count; ++i)
      for (auto b = bonds_.offsets[i]; b < bonds_.offsets[i + 1]; ++b)
        if (!intact[b]) pairs.emplace_back(std::min(i, bonds_.neighbor[b]), std::max(i, bonds_.neighbor[b]));
  }

  // With the lattice kernel the bonds by pair come from a copy of the
  // families, kept for adaptive refinement, which asks for them (and on a
  // process of a distributed run, for its checkpoints): another run does
  // not hold them (0.7 bytes per directed bond on C3-A at dx = 0.04 mm).
  void require_bonds_by_pair(const char* what) const {
    if (families_.particle_count == 0)
      throw Error(std::string("ForceField::") + what +
                  " with the lattice kernel needs a scene with refinement.enabled (the families are kept for it)");
  }

  // largest_stretch_ratio with the lattice kernel: each particle's own bonds
  // from its family (the sweep lists no bond by pair), each with its owner's
  // critical stretch and its state from the lattice, in double precision.
  // Only the `wanted` particles (all when empty) are looked at, family by family.
  void lattice_stretch_ratio(const ParticleState& s, std::vector<double>& ratio,
                             const std::vector<std::uint8_t>& wanted) const {
    require_bonds_by_pair("largest_stretch_ratio");
    const Kinematics& k = s.motion;
    const auto& x = s.x0();
    const auto& y = s.y0();
    ratio.assign(families_.particle_count, 0.0);
    for (std::uint32_t i = 0; i < families_.particle_count; ++i) {
      if (!wanted.empty() && !wanted[i]) continue;
      const double critical_stretch = own_critical_stretch_.empty() ? constants_.critical_stretch : own_critical_stretch_[i];
      if (!(critical_stretch > 0)) continue;
      double largest = 0;
      lattice_->for_each_family_bond(families_, i, [&](const BondRef& b, const auto& intact) {
        const auto j = b.neighbor;
        const double xi_x = x[j] - x[i], xi_y = y[j] - y[i];
        const double yx = xi_x + (k.ux[j] - k.ux[i]), yy = xi_y + (k.uy[j] - k.uy[i]);
        // Only a bond that may beat `largest` needs its lengths (squares compared:
        // |y| > (1 + largest s0) |xi|), and only such a bond its state.
        const double beaten = 1 + largest * critical_stretch;
        if (yx * yx + yy * yy <= beaten * beaten * (xi_x * xi_x + xi_y * xi_y)) return;
        if (!intact()) return;
        const double rest = std::hypot(xi_x, xi_y);
        largest = std::max(largest, (std::hypot(yx, yy) - rest) / (critical_stretch * rest));
      });
      ratio[i] = largest;
    }
  }

  bool general_pairs_in_float_ = true;  // SetupOptions::general_pairs_in_float
  // make_force_field's finer_level_sweeps, in an adaptive run (a plate meshed
  // finer in boxes keeps its finer squares general: not measured yet).
  bool finer_level_sweeps_ = true;
  typename Model::Constants constants_;
  std::vector<double> thresholds_;
  std::size_t precrack_cut_ = 0;
  std::vector<double> lambda_;  // surface-correction factors (the lattice kernel's strain energy)
  std::unique_ptr<LatticeKernel> lattice_;  // null when no particle qualifies or when disabled
  bool bonds_by_pair_ = false;  // keep the families for largest_stretch_ratio (refinement)
  bool keeps_families_ = false;  // keep_families keeps them
  // SetupOptions::keep_families: kept besides for a restart between one
  // process and several, until release_families_kept_for_restart.
  bool keeps_families_for_restart_ = false;
  Families families_;  // with the lattice: the families (local ones on a process: checkpoints; bonds_by_pair_)
  std::vector<double> own_critical_stretch_;  // dual-horizon lattice: s_c of each particle's own horizon
  BondTable bonds_;                         // all bonds, without the lattice kernel
  std::vector<std::uint8_t> intact_;        // per bond of bonds_, with damage
  // Per particle, for a model with a pre-pass: the dilatation theta_i and theta_i / m_i.
  std::vector<double> theta_, pressure_;
  GhostExchange ghost_exchange_;  // distributed runs (set_ghost_exchange)
  // A distributed variable-horizon run's rows (distributed_variable_horizon_rows;
  // the members below are false, empty or 0 otherwise): per entry of bonds_
  // the whole plate's directed bond whose state it carries (with damage), the
  // whole plate's directed bonds, and the owned particles (the rows' first).
  bool distributed_rows_ = false;
  // A distributed dual-horizon run with the lattice split
  // (distributed_dual_horizon_lattice): entry_bond_ per entry of the
  // lattice's general rows, and per owned particle the first of its
  // family's bonds among the file's.
  bool distributed_lattice_ = false;
  std::vector<std::uint64_t> owned_file_start_;
  std::vector<std::uint64_t> entry_bond_;
  std::uint64_t whole_bond_count_ = 0;
  std::size_t owned_count_ = 0;
};

}  // namespace

namespace {

// `setup`: a const BondSetup (its families copied where kept) or an rvalue (moved).
template <class Setup>
std::unique_ptr<ForceField> force_field_of(const Scene& scene, const ParticleSet& particles, Setup&& setup,
                                           bool lattice_kernel, ForceFieldSubdomain* subdomain,
                                           const SetupOptions* rows, bool general_pairs_in_float,
                                           bool finer_level_sweeps) {
  return with_model_and_effects(scene.model, scene.osb_failure, scene.effects.damage,
                                [&](auto model, auto damage) -> std::unique_ptr<ForceField> {
                                  using Model = decltype(model);
                                  using Damage = decltype(damage);
                                  auto forces = std::make_unique<ForceFieldOf<Model, Damage>>(
                                      scene, particles, std::as_const(setup), lattice_kernel, subdomain, rows,
                                      general_pairs_in_float, finer_level_sweeps);
                                  forces->keep_families(std::forward<Setup>(setup).families);
                                  return forces;
                                });
}

}  // namespace

std::unique_ptr<ForceField> make_force_field(const Scene& scene, const ParticleSet& particles,
                                             const BondSetup& setup, bool lattice_kernel,
                                             ForceFieldSubdomain* subdomain, const SetupOptions* rows,
                                             bool general_pairs_in_float, bool finer_level_sweeps) {
  return force_field_of(scene, particles, setup, lattice_kernel, subdomain, rows, general_pairs_in_float,
                        finer_level_sweeps);
}

std::unique_ptr<ForceField> make_force_field(const Scene& scene, const ParticleSet& particles, BondSetup&& setup,
                                             bool lattice_kernel, ForceFieldSubdomain* subdomain,
                                             const SetupOptions* rows, bool general_pairs_in_float,
                                             bool finer_level_sweeps) {
  return force_field_of(scene, particles, std::move(setup), lattice_kernel, subdomain, rows,
                        general_pairs_in_float, finer_level_sweeps);
}

}  // namespace pd::solver
