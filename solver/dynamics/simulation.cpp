#include "simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <sstream>

#include "bond_setup.hpp"
#include "error.hpp"
#include "horizon_mode.hpp"
#include "local_bonds.hpp"
#include "material_scales.hpp"
#include "precrack.hpp"
#include "processes.hpp"
#include "state_surface_correction.hpp"
#include "surface_correction.hpp"

namespace pd::solver {

namespace {

// The loads of the owned particles, in local numbering (a ghost's motion
// comes from its owner).
std::vector<ResolvedLoad> owned_part(const std::vector<ResolvedLoad>& whole, const std::vector<std::uint32_t>& ids,
                                     std::size_t owned_count, std::size_t whole_count) {
  std::vector<std::uint32_t> local_of(whole_count, Families::none);
  for (std::size_t l = 0; l < owned_count; ++l) local_of[ids[l]] = static_cast<std::uint32_t>(l);
  std::vector<ResolvedLoad> owned;
  for (const ResolvedLoad& load : whole) {
    ResolvedLoad mine = load;
    mine.particles.clear();
    mine.value_x.clear();
    mine.value_y.clear();
    for (std::size_t m = 0; m < load.particles.size(); ++m) {
      const std::uint32_t l = local_of[load.particles[m]];
      if (l == Families::none) continue;
      mine.particles.push_back(l);
      if (!load.value_x.empty()) mine.value_x.push_back(load.value_x[m]);
      if (!load.value_y.empty()) mine.value_y.push_back(load.value_y[m]);
    }
    owned.push_back(std::move(mine));
  }
  return owned;
}

// The whole plate's bond and pre-crack counts of a set-up made on slabs'
// bands, from each process's owned particles' whole families (local_bonds:
// ghosts have none, and each directed bond has one owner). Collective.
void sum_counts_over_processes(const BondSetup& local, const Communicator& comm, SetupFacts& facts) {
  facts.bond_count = comm.sum(static_cast<std::uint64_t>(local.families.bond_count()));
  facts.precrack_cut = static_cast<std::size_t>(comm.sum(static_cast<std::uint64_t>(local.precrack_cut)));
}

}  // namespace

void Simulation::note_bond_state_rows(const Families& whole, const Partition& partition) {
  // One state per directed bond, with damage only (ForceField::bond_states).
  const bool with_states = scene_.effects.damage;
  whole_bond_state_count_ = with_states ? whole.bond_count() : 0;
  std::uint64_t start = 0;
  std::size_t next = 0;
  for (std::uint32_t i = 0; i < whole.particle_count && next < partition.owned.size(); ++i) {
    const std::uint64_t length = with_states ? whole.family_size(i) : 0;
    if (partition.owned[next] == i) {
      owned_bond_state_start_.push_back(start);
      owned_bond_state_count_.push_back(static_cast<std::uint32_t>(length));
      ++next;
    }
    start += length;
  }
}

void Simulation::note_bond_state_rows(const WholePlateFacts& whole) {
  // The file's family offsets and lengths (a compact family holds its file family's bonds in order).
  const bool with_states = scene_.effects.damage;
  whole_bond_state_count_ = with_states ? whole.bond_count : 0;
  owned_bond_state_start_ = with_states ? whole.owned_family_start : std::vector<std::uint64_t>(owned_count_, 0);
  owned_bond_state_count_ = with_states ? whole.owned_family_length : std::vector<std::uint32_t>(owned_count_, 0);
}

Simulation::Simulation(const Scene& scene, const ParticleSet& p, const SetupOptions& options)
    : Simulation(scene, copy_without_set_up_geometry(p), &p, compact_families(p, options.earlier_weights), options,
                 serial_communicator(), nullptr, nullptr) {}

Simulation::Simulation(const Scene& scene, ParticleSet p, Families families, const SetupOptions& options,
                       const Communicator& communicator, const Partition* partition,
                       const WholePlateFacts* whole_plate)
    : Simulation(scene, std::move(p), nullptr, std::move(families), options, communicator, partition, whole_plate) {}

Simulation::Simulation(const Scene& scene, ParticleSet p, const ParticleSet* set_up_particles, Families families,
                       const SetupOptions& options, const Communicator& communicator, const Partition* partition,
                       const WholePlateFacts* whole_plate)
    : scene_(scene), comm_(communicator) {
  const ParticleSet& geometry = set_up_particles ? *set_up_particles : p;
  density_ = scene.material.density;
  thickness_ = scene.material.thickness;
  whole_count_ = whole_plate ? whole_plate->particle_count : p.size();
  {
    // The surface-correction factors that couple the whole plate through
    // their fixed point (a bond-based model's scalar factors, the
    // state-based model's dilatation factors); on several processes each
    // iterates them for its own particles only and exchanges the ghosts'
    // (iterate_scalar_factors, iterate_dilatation_factors below), so the
    // set-up of the whole plate (or of the band) leaves them out.
    const bool distributed = partition && partition->size > 1;
    if (whole_plate && !distributed)
      throw Error(scene.particle_file + ": a set-up on a slab's band needs the partition of several processes");
    // (A band's own horizons may differ from the plate's: the file's mode and horizon.)
    const HorizonMode mode = whole_plate ? whole_plate->horizons.mode : horizon_mode(scene, geometry);
    const bool factors_on_slabs = distributed && scene.effects.surface_correction && mode == HorizonMode::uniform;
    SetupOptions whole_options = options;
    if (factors_on_slabs) whole_options.coupled_factors = false;
    whole_options.part_of_plate = whole_plate != nullptr;
    if (whole_plate) whole_options.plate_horizons = &whole_plate->horizons;
    // On several processes each makes the same set-up (the whole plate's, or
    // its band's) and resolves the same loads: their errors (a pre-crack that
    // cuts no bond, a load's set or point) are agreed on and said once, by
    // the root (before 7 December 2026 each process said them with its rank,
    // and MPI_Abort ended the run). Neither makes a collective call.
    const auto agreed = [&](const std::function<void()>& step) {
      if (distributed)
        on_every_process(step);
      else
        step();
    };
    BondSetup setup;
    agreed([&] { setup = build_bond_setup(scene, geometry, std::move(families), whole_options); });
    facts_ = facts_of(setup);
    if (whole_plate) {
      // A crack cuts a bond of the plate exactly when it cuts one in some
      // process's band (each owned bond is in its owner's band). Collective;
      // every process finds the same, so the root reports it once.
      for (auto& count : setup.bonds_cut_per_crack) count = comm_.sum(count);
      on_every_process([&] { require_precrack_cuts(setup.bonds_cut_per_crack, p, scene.precracks, scene.path); });
    }
    // The cells and listed families served the set-up only: they go before
    // the force field's arrays come, which would otherwise add to them at
    // the run's peak memory.
    release_set_up_geometry(p);
    // (On a band the loads come resolved on the whole plate.)
    if (!whole_plate) agreed([&] { loads_ = resolve_loads(scene, p); });
    if (distributed) {
      if (options.keep_weights)
        throw Error("Simulation: the bond weights are kept for a later set-up on one process only");
      // Each process saw its own part's bonds. (Collective.)
      facts_.largest_bonded_horizon_ratio = comm_.max(facts_.largest_bonded_horizon_ratio);
      global_id_ = partition->local_ids();
      owned_count_ = partition->owned.size();
      if (whole_plate) {
        note_bond_state_rows(*whole_plate);
        whole_loads_ = whole_plate->loads;
      } else {
        note_bond_state_rows(setup.families, *partition);
        whole_loads_ = std::move(loads_);
      }
      loads_ = owned_part(whole_loads_, global_id_, owned_count_, whole_count_);
      // The local particles' indices in `p` (the whole plate's or the band's).
      const std::vector<std::uint32_t>& setup_ids = whole_plate ? whole_plate->band_index : global_id_;
      LocalBonds local = local_bonds(p, setup, setup_ids, owned_count_);
      if (whole_plate) sum_counts_over_processes(local.setup, comm_, facts_);
      // Whether the plate holds together (the pre-cracks, or a grid's lost
      // neck): a band's set-up cannot tell (a piece may close beyond it),
      // the processes together can.
      if (whole_plate) {
        const Families& f = local.setup.families;
        const PieceExchange exchange{
            [this](std::vector<double>& values) { comm_.update_ghost_values(values); },
            [this](bool local_value) { return comm_.any(local_value); },
            [this](std::uint64_t local_value) { return comm_.sum(local_value); },
            [this](const double* owned, std::size_t count, std::vector<double>& whole) {
              comm_.gather_owned(owned, count, 1, whole);
            }};
        facts_.pieces = plate_pieces_on_processes(f, local.setup.listed_intact, global_id_, owned_count_, exchange);
        facts_.pieces_without_cuts = facts_.pieces.count;
        if (facts_.pieces.count > 1 && !scene.precracks.empty())
          facts_.pieces_without_cuts =
              plate_pieces_on_processes(f, std::vector<std::uint8_t>(local.setup.listed_intact.size(), 1),
                                        global_id_, owned_count_, exchange)
                  .count;
      }
      if (factors_on_slabs) {
        // The same fixed point and convergence test as on one process: every
        // owned factor equals a one-process run's bit for bit. (The lattice
        // particles are still chosen on the set-up of the whole plate or the
        // band, with scalar factors of 1 there: its test compares a bond's
        // stiffness with its pair's, both carrying the same factor
        // (lambda_i + lambda_j) / 2; the dilatation factors are not in it.)
        const ScalarFactorExchange exchange{[this](std::vector<double>& values) { comm_.update_ghost_values(values); },
                                            [this](double value) { return comm_.max(value); }};
        BondSetup& s = local.setup;
        // Every process stops at the same iteration (the largest change is
        // the processes' maximum), so a fixed point that does not converge
        // fails on all of them together: agreed after the iteration's
        // exchanges, and said once, by the root (before 7 December 2026
        // each process said it with its rank, and MPI_Abort ended the run).
        std::exception_ptr failure;
        try {
          s.lambda_iterations =
              scene.model == ModelType::osb
                  ? iterate_dilatation_factors(local.particles, s.families, s.energy_weight, s.listed_intact,
                                               surface_correction_tolerance, s.dilatation_shapes, &exchange)
                  : iterate_scalar_factors(local.particles, s.families, s.energy_weight, s.listed_intact, s.shapes,
                                           s.horizon, surface_correction_tolerance, s.lambda, &exchange);
        } catch (const Error& e) {
          failure = std::make_exception_ptr(Error(scene.source_of("effects.surface_correction") +
                                                  ": key 'effects.surface_correction' = true on " +
                                                  scene.particle_file + ": " + e.what()));
        }
        on_every_process([&] {
          if (failure) std::rethrow_exception(failure);
        });
        facts_.lambda_iterations = s.lambda_iterations;
      }
      // (The force field frees `p` and `setup`, the whole plate's or the
      // band's, once it has what it needs.)
      ForceFieldSubdomain subdomain{p, setup, setup_ids, owned_count_,
                                    [this](std::vector<double>& values) { comm_.update_ghost_values(values); }};
      if (whole_plate && mode != HorizonMode::uniform) {
        subdomain.file_family_start = &whole_plate->band_family_start;
        subdomain.file_bond_count = whole_plate->bond_count;
      }
      subdomain.any_process = [this](bool value) { return comm_.any(value); };
      forces_ = make_force_field(scene, local.particles, std::move(local.setup), options.lattice_kernel, &subdomain,
                                 nullptr, options.general_pairs_in_float);
      // The ghosts' displacements at the start of every evaluation, and a
      // state-based model's theta_j / m_j between its dilatation pass and its
      // forces (the second exchange of a step), from their owners; the force
      // field computes what reads no ghost while they travel.
      GhostExchange exchange;
      exchange.start_displacements = [this] { comm_.start_ghost_update(state_); };
      exchange.finish_displacements = [this] { comm_.finish_ghost_update(state_); };
      exchange.start_values = [this](std::vector<double>& values) { comm_.start_ghost_value_update(values); };
      exchange.finish_values = [this](std::vector<double>& values) { comm_.finish_ghost_value_update(values); };
      forces_->set_ghost_exchange(std::move(exchange));
      p = std::move(local.particles);
    } else {
      owned_count_ = p.size();
      forces_ = make_force_field(scene, p, std::move(setup), options.lattice_kernel, nullptr, &options,
                                 options.general_pairs_in_float);
      // The families and weights kept for a later set-up (KeptBondWeights):
      // the force field's families, and the weights the set-up is done with.
      if (options.keep_weights) {
        KeptBondWeights& kept = *options.keep_weights;
        kept.simulation_families = forces_->kept_families();
        if (!kept.simulation_families) kept.own_families = std::move(setup.families);
        if (!scene.effects.surface_correction) kept.energy_weight = std::move(setup.energy_weight);
      }
    }
  }
  resultants_.resize(loads_.size());

  // The plate's limit: the smallest over the processes (each knows its own particles').
  stable_dt_ = comm_.min(forces_->stable_time_step());
  // The checks below, made alike by this simulation's processes, are agreed
  // on and said once; a one-process simulation checks alone, also inside a
  // run on several (the root's, for a restart's bond states:
  // runs/checkpoint_layout.hpp), where an agreement would wait for processes
  // that make none.
  const auto agreed_by_the_processes = [this](const std::function<void()>& check) {
    if (comm_.size() > 1)
      on_every_process(check);
    else
      check();
  };
  // No bond anywhere: no stiffness limits the step (infinite), and no force
  // would ever act (before 5 December 2026 the run "became unstable" at t = inf).
  agreed_by_the_processes([&] {
    if (!std::isfinite(stable_dt_))
      throw Error(scene.particle_file + ": no particle has a bond (every family is empty: a horizon below "
                  "the spacing, or cells cut off from each other by holes): no force can act; mesh with a larger "
                  "horizon or a smaller spacing");
    // A density this far below Young's modulus: 2 rho / (the bond
    // stiffnesses' sum) underflows (before, "a time step of 0 s ... is inf
    // steps"). (A quasi-static scene may leave the density out: 0, no step.)
    if (stable_dt_ == 0 && scene.material.density > 0)
      throw Error(material_keys_described(scene, {"density", "youngs_modulus"}) +
                  ": the stable time step sqrt(2 rho / (a particle's sum of bond stiffnesses)) of " +
                  options.particle_set_name + " underflows to 0 s; a value written with its unit is taken as given, "
                  "but not one the run cannot compute with");
  });
  if (scene.time.automatic) {
    dt_ = scene.time.safety * stable_dt_;
    // A material far outside what solids have (a density of 1e300 kg/m^3:
    // a stable step of 1e141 s) can give a step longer than the whole run,
    // whose one step would reach far past time.end (and the loads' time
    // functions with it): the run needs no more than time.end, which is as
    // stable (docs/scenes.md, [time]). (A quasi-static scene has no end: 0.)
    if (scene.time.end > 0 && dt_ > scene.time.end) {
      dt_ = scene.time.end;
      dt_capped_at_end_ = true;
    }
  } else {
    dt_ = scene.time.step;
    // Every process sees the same limit and step: the refusal is printed once.
    agreed_by_the_processes([&] {
      if (dt_ > stable_dt_ && !scene.time.force) {
        std::ostringstream m;
        m << scene.source_of("time.step") << ": key 'time.step' = " << dt_ << " s is above the stable limit "
          << stable_dt_ << " s of " << options.particle_set_name
          << " (theory.md Sec. 4); use a smaller step, step = \"auto\", "
             "or set time.force = true to run anyway";
        throw Error(m.str());
      }
    });
  }

  state_ = state_at_rest(std::move(p), scene.output.damage_thresholds.size());
  if (options.start_at_rest) start_at_rest();
}

void Simulation::start_at_rest() {
  Kinematics& k = state_.motion;
  for (const auto& load : loads_) {
    if (load.spec.kind != LoadKind::initial_velocity) continue;
    for (std::size_t m = 0; m < load.particles.size(); ++m) {
      if (load.spec.has_x) k.vx[load.particles[m]] = load.value_x[m];
      if (load.spec.has_y) k.vy[load.particles[m]] = load.value_y[m];
    }
  }
  compute_forces_timed();
  apply_velocity_constraints(0.0, 0.0);
  forces_->record_arrivals_in_team(state_, time_);  // (one thread: once per run)
  // The plate was at rest: the loads did the work of its kinetic energy at t = 0
  // (initial velocities, velocity loads applied suddenly; theory.md Sec. 4.3).
  external_work_ = energy_sums(nullptr).kinetic;
}

void Simulation::compute_forces_timed() {
  const auto start = std::chrono::steady_clock::now();
  compute_forces();
  force_evaluation_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Simulation::discard_ghost_results(std::vector<double>* energy_density) {
  // The lattice sweep evaluates the pairs of ghosts too (they are computed
  // where they are owned); a ghost keeps no force, damage or energy here, so
  // that it stays at rest between ghost updates and adds nothing to any sum.
  Kinematics& k = state_.motion;
  for (std::size_t i = owned_count_; i < particle_count(); ++i) k.fx[i] = k.fy[i] = state_.damage[i] = 0;
  if (energy_density) discard_ghost_energy(*energy_density);
}

void Simulation::discard_ghost_energy(std::vector<double>& energy_density) const {
  std::fill(energy_density.begin() + static_cast<std::ptrdiff_t>(owned_count_), energy_density.end(), 0.0);
}

void Simulation::compute_forces(std::vector<double>* energy_density) {
  // (A distributed run's ghost displacements: the force field's compute()
  // exchanges them, set_ghost_exchange above.)
  // W_i of the state before goes before the evaluation's arrays come.
  if (energy_density != &energy_density_) std::vector<double>().swap(energy_density_);
  forces_->compute(state_, energy_density);
  discard_ghost_results(energy_density);
  energy_density_current_ = energy_density == &energy_density_;
  Kinematics& k = state_.motion;
  const std::vector<double>& area = state_.area();
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const auto& load = loads_[l];
    auto& r = resultants_[l];
    r = {};
    if (load.constrains_motion()) {
      for (auto i : load.particles) {
        r.reaction_x -= k.fx[i] * area[i] * thickness_;
        r.reaction_y -= k.fy[i] * area[i] * thickness_;
      }
    } else if (load.spec.kind == LoadKind::traction) {
      const double f = load.spec.time_function(time_);
      double loaded_area = 0;
      for (auto i : load.particles) {
        k.fx[i] += f * load.body_force_x;
        k.fy[i] += f * load.body_force_y;
        loaded_area += area[i];
      }
      loaded_area = comm_.sum(loaded_area);
      r.reaction_x = f * load.body_force_x * loaded_area * thickness_;
      r.reaction_y = f * load.body_force_y * loaded_area * thickness_;
    }
    if (load.constrains_motion()) {
      r.reaction_x = comm_.sum(r.reaction_x);
      r.reaction_y = comm_.sum(r.reaction_y);
    }
  }
}

// Velocity of constrained components over the step from time_ to time_end; at
// time_half = time_end (end of a step) it sets the final velocities.
void Simulation::apply_velocity_constraints(double time_half, double time_end) {
  const double dt = time_end - time_;
  Kinematics& k = state_.motion;
  for (const auto& load : loads_) {
    const auto& s = load.spec;
    if (s.kind == LoadKind::velocity) {
      const double f = s.time_function(time_half);
      for (std::size_t m = 0; m < load.particles.size(); ++m) {
        const auto i = load.particles[m];
        if (s.has_x) k.vx[i] = load.value_x[m] * f;
        if (s.has_y) k.vy[i] = load.value_y[m] * f;
      }
    } else if (s.kind == LoadKind::displacement || s.kind == LoadKind::fixed) {
      const double f = s.kind == LoadKind::fixed ? 0.0 : s.time_function(time_end);
      for (std::size_t m = 0; m < load.particles.size(); ++m) {
        const auto i = load.particles[m];
        // The velocity that carries the particle to its prescribed place at time_end.
        if (dt > 0) {
          if (s.has_x) k.vx[i] = (load.value_x[m] * f - k.ux[i]) / dt;
          if (s.has_y) k.vy[i] = (load.value_y[m] * f - k.uy[i]) / dt;
        } else if (s.kind == LoadKind::fixed) {
          k.vx[i] = k.vy[i] = 0;
        }
      }
    }
  }
}

void Simulation::step(bool report_energy) {
  const double dt = dt_, half = 0.5 * dt, inv_density = 1.0 / density_;
  const double t0 = time_, t1 = time_ + dt;
  const std::int64_t n = static_cast<std::int64_t>(particle_count());

  // Loaded particles at t_n, for the external work of this step.
  struct Before { double ux, uy, vx, vy, fx, fy; };
  Kinematics& k = state_.motion;
  const std::vector<double>& area = state_.area();
  std::vector<std::vector<Before>> before(loads_.size());
  for (std::size_t l = 0; l < loads_.size(); ++l)
    if (loads_[l].spec.kind != LoadKind::initial_velocity)
      for (auto i : loads_[l].particles)
        before[l].push_back({k.ux[i], k.uy[i], k.vx[i], k.vy[i], k.fx[i], k.fy[i]});

  // Half kick, then the constrained velocities over the step, then drift.
  // Kick and drift run as one pass over the particles (one read of the
  // arrays instead of two); the loaded particles, whose velocities the
  // constraints set in between, then go back to u_n (kept in `before`) and
  // drift again with their constrained velocities: the same operations on
  // the same numbers as a separate kick, constraints and drift.
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    k.vx[i] += half * k.fx[i] * inv_density;
    k.vy[i] += half * k.fy[i] * inv_density;
    k.ux[i] += dt * k.vx[i];
    k.uy[i] += dt * k.vy[i];
  }
  for (std::size_t l = 0; l < loads_.size(); ++l)
    for (std::size_t m = 0; m < before[l].size(); ++m) {
      const auto i = loads_[l].particles[m];
      k.ux[i] = before[l][m].ux;
      k.uy[i] = before[l][m].uy;
    }
  apply_velocity_constraints(t0 + half, t1);
  for (std::size_t l = 0; l < loads_.size(); ++l)
    for (std::size_t m = 0; m < before[l].size(); ++m) {
      const auto i = loads_[l].particles[m];
      // An assignment from u_n, not +=: a particle in two loads drifts once.
      k.ux[i] = before[l][m].ux + dt * k.vx[i];
      k.uy[i] = before[l][m].uy + dt * k.vy[i];
    }
  // Prescribed displacements land exactly (no round-off from the drift).
  for (const auto& load : loads_) {
    const auto& s = load.spec;
    if (s.kind != LoadKind::displacement && s.kind != LoadKind::fixed) continue;
    const double f = s.kind == LoadKind::fixed ? 0.0 : s.time_function(t1);
    for (std::size_t m = 0; m < load.particles.size(); ++m) {
      if (s.has_x) k.ux[load.particles[m]] = load.value_x[m] * f;
      if (s.has_y) k.uy[load.particles[m]] = load.value_y[m] * f;
    }
  }

  time_ = t1;
  compute_forces(report_energy ? &energy_density_ : nullptr);

  // The second half kick; the same pass checks every value and sums
  // sum_i v_i^2 A_i for the kinetic energy (the per-step stability check of
  // the run: a blow-up shows as kinetic energy long before it is non-finite).
  // The damage arrival times of the step (they read the damage index only)
  // in the same parallel region: one wait at its end for both.
  bool bad = false;
  double velocity_squared_area = 0;
  const ForceField& forces = *forces_;
#pragma omp parallel
  {
#pragma omp for schedule(static) reduction(|| : bad) reduction(+ : velocity_squared_area) nowait
    for (std::int64_t i = 0; i < n; ++i) {
      k.vx[i] += half * k.fx[i] * inv_density;
      k.vy[i] += half * k.fy[i] * inv_density;
      bad = bad || !std::isfinite(k.vx[i]) || !std::isfinite(k.vy[i]) || !std::isfinite(k.ux[i]) ||
            !std::isfinite(k.uy[i]);
      velocity_squared_area += (k.vx[i] * k.vx[i] + k.vy[i] * k.vy[i]) * area[i];
    }
    forces.record_arrivals_in_team(state_, t1);
  }
  // End-of-step velocities: prescribed ones at t1; displaced particles keep
  // the step's average velocity; fixed ones rest. The kinetic energy's sum
  // takes the constrained components at these values: the half kick gave
  // them what the forces on a held particle would do (a traction on a fixed
  // edge: large, and no motion at all), which would read as a blow-up.
  double constrained_correction = 0;  // sum of (v_set^2 - v_kicked^2) A_i over the constrained components
  const auto set_velocity = [&](double& v, double value, std::uint32_t i) {
    constrained_correction += (value * value - v * v) * area[i];
    v = value;
  };
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const auto& load = loads_[l];
    const auto& s = load.spec;
    if (s.kind == LoadKind::velocity) {
      const double f = s.time_function(t1);
      for (std::size_t m = 0; m < load.particles.size(); ++m) {
        const auto i = load.particles[m];
        if (s.has_x) set_velocity(k.vx[i], load.value_x[m] * f, i);
        if (s.has_y) set_velocity(k.vy[i], load.value_y[m] * f, i);
      }
    } else if (s.kind == LoadKind::displacement || s.kind == LoadKind::fixed) {
      for (std::size_t m = 0; m < load.particles.size(); ++m) {
        const auto i = load.particles[m];
        if (s.has_x) set_velocity(k.vx[i], s.kind == LoadKind::fixed ? 0.0 : (k.ux[i] - before[l][m].ux) / dt, i);
        if (s.has_y) set_velocity(k.vy[i], s.kind == LoadKind::fixed ? 0.0 : (k.uy[i] - before[l][m].uy) / dt, i);
      }
    }
  }
  step_kinetic_energy_ =
      comm_.sum(0.5 * density_ * thickness_ * std::max(0.0, velocity_squared_area + constrained_correction));

  // External work of this step (trapezoidal rule). A constraint does the work
  // that changes the kinetic energy of its particles minus the work of the
  // internal forces on them; a traction does b . du.
  for (std::size_t l = 0; l < loads_.size(); ++l) {
    const auto& load = loads_[l];
    const auto& s = load.spec;
    if (s.kind == LoadKind::initial_velocity) continue;
    double work = 0;
    for (std::size_t m = 0; m < load.particles.size(); ++m) {
      const auto i = load.particles[m];
      const Before& b = before[l][m];
      const double dux = k.ux[i] - b.ux, duy = k.uy[i] - b.uy;
      double w = 0;
      if (s.kind == LoadKind::traction) {
        const double f0 = s.time_function(t0), f1 = s.time_function(t1);
        w = 0.5 * (f0 + f1) * (load.body_force_x * dux + load.body_force_y * duy);
      } else {
        if (s.has_x) w += 0.5 * density_ * (k.vx[i] * k.vx[i] - b.vx * b.vx) - 0.5 * (b.fx + k.fx[i]) * dux;
        if (s.has_y) w += 0.5 * density_ * (k.vy[i] * k.vy[i] - b.vy * b.vy) - 0.5 * (b.fy + k.fy[i]) * duy;
      }
      work += w * area[i] * thickness_;
    }
    external_work_ += comm_.sum(work);
  }

  ++step_;

  if (comm_.any(bad)) {
    for (std::int64_t i = 0; i < n; ++i) {
      const char* what = !std::isfinite(k.ux[i]) || !std::isfinite(k.uy[i]) ? "displacement"
                         : !std::isfinite(k.vx[i]) || !std::isfinite(k.vy[i]) ? "velocity" : nullptr;
      if (what) {
        non_finite_ = {true, static_cast<std::size_t>(i), what, true};
        break;
      }
    }
    // Every process stops together (the run writes its last good state
    // collectively); one whose own particles are all finite names its first.
    if (!non_finite_.found) non_finite_ = {true, 0, "value on another process, e.g. near the particle", false};
  }
}

double Simulation::traction_work_ahead() const {
  const Kinematics& k = state_.motion;
  const std::vector<double>& area = state_.area();
  double work = 0;
  for (const auto& load : loads_) {
    if (load.spec.kind != LoadKind::traction) continue;
    const double f = load.spec.time_function(time_);
    for (const auto i : load.particles)
      work += f * (load.body_force_x * k.vx[i] + load.body_force_y * k.vy[i]) * area[i];
  }
  return comm_.sum(0.5 * dt_ * work * thickness_);
}

std::uint64_t Simulation::broken_bond_count() const { return comm_.sum(forces_->broken_bond_count()); }

const std::vector<double>& Simulation::strain_energy_density() const {
  if (!energy_density_current_) {
    forces_->strain_energy_density(state_, energy_density_);
    discard_ghost_energy(energy_density_);
    energy_density_current_ = true;
  }
  return energy_density_;
}

EnergyTotals Simulation::energies() const { return energy_sums(&strain_energy_density()); }

EnergyTotals Simulation::energy_sums(const std::vector<double>* energy_density) const {
  EnergyTotals e;
  const Kinematics& k = state_.motion;
  const std::vector<double>& area = state_.area();
  // Serial sums: a fixed order, so restarted runs report identical numbers.
  for (std::size_t i = 0; i < particle_count(); ++i) {
    const double volume = area[i] * thickness_;
    const double v2 = k.vx[i] * k.vx[i] + k.vy[i] * k.vy[i];
    const double a2 = (k.fx[i] * k.fx[i] + k.fy[i] * k.fy[i]) / (density_ * density_);
    e.kinetic += 0.5 * density_ * v2 * volume;
    e.kinetic_half_step += 0.5 * density_ * (v2 - 0.25 * dt_ * dt_ * a2) * volume;
    if (energy_density) e.strain += (*energy_density)[i] * volume;
  }
  e.kinetic = comm_.sum(e.kinetic);
  e.kinetic_half_step = comm_.sum(e.kinetic_half_step);
  e.strain = comm_.sum(e.strain);
  e.external_work = external_work_;
  return e;
}

std::vector<double> Simulation::displacement_xyz() const {
  const Kinematics& k = state_.motion;
  std::vector<double> u(3 * particle_count(), 0.0);
  for (std::size_t i = 0; i < particle_count(); ++i) {
    u[3 * i] = k.ux[i];
    u[3 * i + 1] = k.uy[i];
  }
  return u;
}

std::vector<double> Simulation::velocity_xyz() const {
  const Kinematics& k = state_.motion;
  std::vector<double> v(3 * particle_count(), 0.0);
  for (std::size_t i = 0; i < particle_count(); ++i) {
    v[3 * i] = k.vx[i];
    v[3 * i + 1] = k.vy[i];
  }
  return v;
}

Simulation::State Simulation::save_state() const {
  State s;
  save_state(s);
  return s;
}

void Simulation::save_state(State& s) const {
  if (!distributed()) return save_own_state(s);
  State local;
  save_own_state(local);
  forces_->family_bond_states(local.bond_states);  // the gathered layout (docs/formats.md)
  gather_state(local, s);
  s.bond_states_by_family = true;
}

Simulation::StateView Simulation::state_view(State& scratch) const {
  if (distributed()) {
    save_state(scratch);
    return view_of(scratch);
  }
  forces_->bond_states(scratch.bond_states);
  return {step_, time_, external_work_, &state_.motion, &state_.damage, &scratch.bond_states, &state_.arrival};
}

void Simulation::gather_state(const State& local, State& whole) const {
  whole.step = local.step;
  whole.time = local.time;
  whole.external_work = local.external_work;
  const auto gather = [&](const std::vector<double>& values, std::vector<double>& into) {
    comm_.gather_owned(values.data(), owned_count_, 1, into);
  };
  gather(local.kinematics.ux, whole.kinematics.ux);
  gather(local.kinematics.uy, whole.kinematics.uy);
  gather(local.kinematics.vx, whole.kinematics.vx);
  gather(local.kinematics.vy, whole.kinematics.vy);
  gather(local.kinematics.fx, whole.kinematics.fx);
  gather(local.kinematics.fy, whole.kinematics.fy);
  gather(local.damage, whole.damage);
  whole.arrival.clear();
  std::vector<double> one_threshold;
  const std::size_t n = particle_count();
  for (std::size_t t = 0; t < scene_.output.damage_thresholds.size(); ++t) {
    comm_.gather_owned(local.arrival.data() + t * n, owned_count_, 1, one_threshold);
    whole.arrival.insert(whole.arrival.end(), one_threshold.begin(), one_threshold.end());
  }
  // The local bond states are the owned particles' rows in local order (ghosts have no bonds).
  comm_.gather_owned_rows(local.bond_states, owned_bond_state_count_, whole.bond_states);
}

Simulation::State Simulation::local_part(const State& whole) const {
  const std::size_t thresholds = scene_.output.damage_thresholds.size();
  if (whole.kinematics.ux.size() != whole_count_ || whole.damage.size() != whole_count_ ||
      whole.arrival.size() != thresholds * whole_count_ || whole.bond_states.size() != whole_bond_state_count_)
    throw Error("the saved state does not fit this particle set and scene");
  State l;
  l.step = whole.step;
  l.time = whole.time;
  l.external_work = whole.external_work;
  const std::size_t n = particle_count();
  const Kinematics& w = whole.kinematics;
  Kinematics& k = l.kinematics;
  for (auto* v : {&k.ux, &k.uy, &k.vx, &k.vy, &k.fx, &k.fy}) v->assign(n, 0.0);
  l.damage.assign(n, 0.0);
  l.arrival.assign(thresholds * n, -1.0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t g = global_id_[i];
    k.ux[i] = w.ux[g];
    k.uy[i] = w.uy[g];
    if (i >= owned_count_) continue;  // a ghost: displacement only (see the constructor)
    k.vx[i] = w.vx[g];
    k.vy[i] = w.vy[g];
    k.fx[i] = w.fx[g];
    k.fy[i] = w.fy[g];
    l.damage[i] = whole.damage[g];
    for (std::size_t t = 0; t < thresholds; ++t) l.arrival[t * n + i] = whole.arrival[t * whole_count_ + g];
  }
  // Variable-horizon rows read the whole plate's states (an owned particle's
  // dual entries are bonds of other processes' particles); other kernels the
  // owned particles' rows.
  if (forces_->reads_whole_family_bond_states()) {
    l.bond_states = whole.bond_states;
    return l;
  }
  for (std::size_t m = 0; m < owned_count_; ++m) {
    const auto from = whole.bond_states.begin() + static_cast<std::ptrdiff_t>(owned_bond_state_start_[m]);
    l.bond_states.insert(l.bond_states.end(), from, from + owned_bond_state_count_[m]);
  }
  return l;
}

void Simulation::save_own_state(State& s) const {
  const Kinematics& k = state_.motion;
  s.step = step_;
  s.time = time_;
  s.external_work = external_work_;
  s.kinematics.ux = k.ux;  // (copy assignments reuse the vectors' storage)
  s.kinematics.uy = k.uy;
  s.kinematics.vx = k.vx;
  s.kinematics.vy = k.vy;
  s.kinematics.fx = k.fx;
  s.kinematics.fy = k.fy;
  s.damage = state_.damage;
  forces_->bond_states(s.bond_states);
  s.arrival = state_.arrival;
}

void Simulation::restore_state(const State& s) {
  if (distributed()) {
    // (A one-process state is converted first: runs/checkpoint_layout.hpp.)
    if (!s.bond_states_by_family)
      throw Error("the saved state holds a one-process run's bond states, which several processes cannot place");
    restore_own_state(local_part(s), true);
  } else {
    restore_own_state(State(s), s.bond_states_by_family);
    // The families kept for that restore (SetupOptions::keep_families) are of no further use.
    if (s.bond_states_by_family) forces_->release_families_kept_for_restart();
  }
}

void Simulation::restore_state_in_place(const std::function<void(State&)>& read) {
  if (distributed()) throw Error("restore_state_in_place: a distributed run restores the whole plate's state");
  // The simulation's own arrays are lent to `read` (it overwrites them,
  // sizes unchanged), then taken back: no second copy of the state.
  State s;
  s.kinematics = std::move(state_.motion);
  s.damage = std::move(state_.damage);
  s.arrival = std::move(state_.arrival);
  forces_->bond_states(s.bond_states);
  const auto lend_back = [&] {  // (also when `read` throws: the simulation keeps its arrays)
    state_.motion = std::move(s.kinematics);
    state_.damage = std::move(s.damage);
    state_.arrival = std::move(s.arrival);
  };
  try {
    read(s);
  } catch (...) {
    lend_back();
    throw;
  }
  restore_own_state(std::move(s), false);
}

void Simulation::restore_own_state(State s, bool states_by_family) {
  const std::size_t arrival_count = scene_.output.damage_thresholds.size() * particle_count();
  if (s.kinematics.ux.size() != particle_count() || s.arrival.size() != arrival_count ||
      (!states_by_family && s.bond_states.size() != forces_->bond_state_count()) ||
      s.damage.size() != particle_count())
    throw Error("the saved state does not fit this particle set and scene");
  const auto set_bond_states = [&] {
    if (states_by_family)
      forces_->set_family_bond_states(s.bond_states);
    else
      forces_->set_bond_states(s.bond_states);
  };
  step_ = s.step;
  time_ = s.time;
  external_work_ = s.external_work;
  // The positions and velocities move in (the force evaluation does not
  // change them); forces, damage and bond states are copied, since the
  // evaluation rewrites them and the saved ones are kept bit for bit.
  Kinematics& k = state_.motion;
  k.ux = std::move(s.kinematics.ux);
  k.uy = std::move(s.kinematics.uy);
  k.vx = std::move(s.kinematics.vx);
  k.vy = std::move(s.kinematics.vy);
  k.fx = s.kinematics.fx;
  k.fy = s.kinematics.fy;
  state_.damage = s.damage;
  set_bond_states();
  state_.arrival = std::move(s.arrival);
  // Forces and resultants are functions of the positions and bond states;
  // recompute the load resultants (the kernel gives the same forces and
  // states, but the saved ones are kept bit for bit).
  compute_forces();
  k.fx = std::move(s.kinematics.fx);
  k.fy = std::move(s.kinematics.fy);
  state_.damage = std::move(s.damage);
  set_bond_states();
  non_finite_ = {};
}

void Simulation::save_rollback_state(State& s) const {
  const Kinematics& k = state_.motion;
  s.step = step_;
  s.time = time_;
  s.external_work = external_work_;
  s.kinematics.ux = k.ux;
  s.kinematics.uy = k.uy;
  s.kinematics.vx = k.vx;
  s.kinematics.vy = k.vy;
  forces_->bond_states(s.bond_states);
}

void Simulation::roll_back(const State& s) {
  if (s.kinematics.ux.size() != particle_count() || s.bond_states.size() != forces_->bond_state_count())
    throw Error("the saved state does not fit this particle set and scene");
  step_ = s.step;
  time_ = s.time;
  external_work_ = s.external_work;
  Kinematics& k = state_.motion;
  k.ux = s.kinematics.ux;
  k.uy = s.kinematics.uy;
  k.vx = s.kinematics.vx;
  k.vy = s.kinematics.vy;
  forces_->set_bond_states(s.bond_states);
  // An arrival time is the end of the step that first reached its threshold:
  // those after the saved time had not happened yet.
  for (double& t : state_.arrival)
    if (t > time_) t = -1;
  compute_forces();  // the forces and the damage index of these displacements and bond states
  non_finite_ = {};
}

std::uint64_t Simulation::continue_from(Continuation&& c) {
  const std::size_t n = particle_count();
  if (c.ux.size() != n || c.uy.size() != n || c.vx.size() != n || c.vy.size() != n ||
      c.arrival.size() != state_.arrival.size())
    throw Error("the carried state does not fit this particle set and scene");
  step_ = c.step;
  time_ = c.time;
  external_work_ = c.external_work;
  facts_.pieces = c.pieces;
  facts_.pieces_without_cuts = c.pieces_without_cuts;
  Kinematics& k = state_.motion;
  k.ux = std::move(c.ux);
  k.uy = std::move(c.uy);
  k.vx = std::move(c.vx);
  k.vy = std::move(c.vy);
  state_.arrival = std::move(c.arrival);
  forces_->break_pairs(c.broken_pairs);
  const std::uint64_t inherited = broken_bond_count();
  compute_forces_timed();  // forces at t_n of the new set, and the damage of its bonds
  non_finite_ = {};
  return broken_bond_count() - inherited;
}

void Simulation::set_velocities(const std::vector<double>& vx, const std::vector<double>& vy) {
  state_.motion.vx = vx;
  state_.motion.vy = vy;
}

void Simulation::set_displacements(const std::vector<double>& ux, const std::vector<double>& uy) {
  state_.motion.ux = ux;
  state_.motion.uy = uy;
  compute_forces();
}

}  // namespace pd::solver
