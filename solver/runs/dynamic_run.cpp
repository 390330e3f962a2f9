#include "dynamic_run.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>

#include "adaptive_refinement.hpp"
#include "checkpoint.hpp"
#include "checkpoint_layout.hpp"
#include "error.hpp"
#include "horizon_mode.hpp"
#include "interrupt.hpp"
#include "loads.hpp"
#include "material_scales.hpp"
#include "osb.hpp"
#include "output_cost.hpp"
#include "plan_limits.hpp"
#include "outputs.hpp"
#include "peak_memory.hpp"
#include "processes.hpp"
#include "progress.hpp"
#include "results_format.hpp"
#include "run_report.hpp"
#include "units.hpp"

namespace pd::solver {
namespace {

// The refinement's spread as the scene gives it (docs/scenes.md), for the
// plan line and summary.json.
std::string spread_name(const RefinementSpec& f) {
  switch (f.spread) {
    case RefinementSpread::family: return "family";
    case RefinementSpread::none: return "none";
    case RefinementSpread::within: break;
  }
  return format_number(f.spread_horizons) + " horizon";
}

// OSB with damage where the dilatation term outweighs a bond's
// (osb_break_energy_ratio above 1: plane strain near nu = 1/2), under
// model.osb_failure = force_and_dilatation, where a bond that breaks adds
// more dilatation energy than its bond term takes, or force_only, whose
// forces are not the gradient of an energy once bonds break (theory.md Sec.
// 5.8): the plate gains energy as it cracks, whatever the step, and may
// stop as unstable. Empty otherwise (bond_term_only keeps an energy).
// `spacing`, `horizon`: the particle file's dx and delta [m].
std::string osb_break_energy_warning(const Scene& scene, double spacing, double horizon) {
  if (scene.model != ModelType::osb || !scene.effects.damage || scene.osb_failure == OsbFailure::bond_term_only ||
      !(spacing > 0 && horizon > 0))
    return {};
  const OsbConstants k = Osb::constants(scene.material, horizon);
  const double ratio = osb_break_energy_ratio(k, spacing);
  if (!(ratio > 1)) return {};
  std::ostringstream w;
  w << "material.poisson_ratio = " << shortest_text(scene.material.poisson_ratio) << " in plane "
    << to_string(scene.material.plane) << " (kappa = " << k.bulk_modulus / k.shear_modulus
    << " mu) with model.osb_failure = \"" << to_string(scene.osb_failure) << "\": ";
  if (scene.osb_failure == OsbFailure::force_and_dilatation)
    w << "a bond that breaks leaves the dilatation theta_i, and where theta_i was about 0 the energy a theta_i^2 "
      << "this adds is " << ratio << " times the energy its bond term takes (theory.md Sec. 5.8, \"Energy at a break\")";
  else
    w << "a bond that breaks keeps its share of theta_i but loses its force, so the forces are not the gradient "
      << "of an energy, and the dilatation term outweighs a bond term's energy " << ratio
      << " times (theory.md Sec. 5.8, \"Energy at a break\"); model.osb_failure = \"bond_term_only\" keeps an energy";
  w << "; the plate gains energy as it cracks, at any time step, and may stop as unstable";
  return w.str();
}

// The largest ratio of the horizons across a bond from which ordinary PD is
// warned about. Measured (docs/solver.md, "Safety"): on graded free C1 grids
// graded nearly everywhere, pulled or kicked, kinetic + strain energy strayed
// from the energy supplied by about 6 (ratio - 1) of it (0.030 at 1.0048,
// 0.058 at 1.0096, 0.26 at 1.05), no more over 400 us than over 100 us:
// below 1.005 under a third of the energy-gain margin (0.1, below).
constexpr double ordinary_variable_ratio_warned = 1.005;

// Ordinary PD (model.dual_horizon = false) where bonded particles' horizons
// differ by more than ordinary_variable_ratio_warned: its pair forces are
// not the gradient of an energy (theory.md Sec. 6.3; docs/scenes.md,
// dual_horizon), and the plate's energy strays from what was supplied,
// whatever the step. Empty otherwise (one horizon everywhere is never this mode).
std::string ordinary_variable_horizon_warning(const Scene& scene, const SetupFacts& setup) {
  const double ratio = setup.largest_bonded_horizon_ratio;
  if (setup.horizon_mode != HorizonMode::ordinary_variable || !(ratio > ordinary_variable_ratio_warned)) return {};
  std::ostringstream w;
  w << scene.source_of("model.dual_horizon") << ": key 'model.dual_horizon' = false on " << scene.particle_file
    << ", whose bonded particles' horizons differ by up to " << ratio << " times: ordinary PD with a variable "
    << "horizon has pair forces that are not the gradient of an energy (theory.md Sec. 6.3), and the plate's "
    << "kinetic + strain energy strays from the energy supplied, at any time step: mostly below it (0.26 of it "
    << "lost at a ratio of 1.05 on a graded grid, a loss the run's energy check does not warn of), or above it "
    << "until the run stops as unstable; model.dual_horizon = true conserves it";
  return w.str();
}

// time.force = true lets a fixed step above the stable limit run; below the
// limit it does nothing, said in the plan as other keys that cannot act are
// (before 7 December 2026 no word: a user may believe the run unstable, or
// forced). Not with [refinement]: each halving of dx lowers the limit, and a
// step below the particle file's may lie above a refined set's, where the
// key acts (docs/refinement.md).
std::string needless_force_warning(const Scene& scene, const Simulation& sim) {
  if (!scene.time.force || scene.time.automatic || scene.refinement.enabled ||
      sim.time_step() > sim.stable_time_step())
    return {};
  std::ostringstream w;
  w << scene.source_of("time.force") << ": key 'time.force' = true has no effect: time.step = " << sim.time_step()
    << " s is below the stable limit " << sim.stable_time_step()
    << " s of this particle set: the run is stable without it (force only lets a step above the limit run); "
       "leave time.force out";
  return w.str();
}

// [refinement] without a particle_budget that may grow the particle file's
// count more than tenfold: each halving splits a cell into 4, so that levels
// = 6 on the whole plate allows 4096 times the particles, and a crack that
// branches or a criterion met widely makes the run far larger and longer
// than its plan says (before 7 December 2026 no word).
std::string refinement_growth_warning(const Scene& scene, const AdaptiveRefinement& refinement) {
  const RefinementSpec& f = scene.refinement;
  const std::uint64_t start = refinement.initial_particle_count(), worst = refinement.worst_case_particle_count();
  if (f.particle_budget > 0 || !(worst > 10 * start)) return {};
  std::ostringstream w;
  w << scene.source_of("refinement.levels") << ": key 'refinement.levels' = " << f.levels
    << " without refinement.particle_budget lets the particles grow from " << start << " to up to " << worst << " ("
    << format_number(static_cast<double>(worst) / static_cast<double>(start))
    << " times: each halving splits a cell into 4; " << refinement.splittable_at_start() << " of the " << start
    << " may split" << (f.has_region ? " in refinement.region" : "")
    << "), the run's steps and memory with them; set refinement.particle_budget (e.g. " << 10 * start
    << "), fewer levels or a smaller refinement.region";
  return w.str();
}

// The number of steps to reach the end time: the last step reaches or
// passes it (the 1e-9 guards against 2e-4/2e-8 = 10000.000000001). pd::Error
// when it cannot be counted exactly or its bond evaluations would take more
// than a year even at 1e10 per second; `long_run_warning` when it would run
// for more than a day at the rate of the force evaluation measured at set-up
// (one evaluation, so only an estimate; check_run_length).
// After a refinement event (from_step, from_time), whose set has its own
// time step, the count goes on from there; a restart computes it from the
// same recorded event, so that it ends at the same step.
long step_count(const Scene& scene, const Simulation& sim, std::string& long_run_warning, long from_step = 0,
                double from_time = 0) {
  const double dt = sim.time_step();
  RunLength length;
  // (At least one step from the start; none more after an event at or past the end.)
  length.steps =
      from_step + std::max(from_step > 0 ? 0.0 : 1.0, std::ceil((scene.time.end - from_time) / dt - 1e-9));
  // Each step evaluates the forces once; the rest of a step costs a small fraction of that.
  length.seconds = length.steps * sim.force_evaluation_seconds();
  length.bond_evaluations = length.steps * static_cast<double>(sim.bond_count());
  // An automatic step from a material outside what solids have (a density
  // of 1e-300 kg/m^3: a stable step near 1e-158 s) is the likely cause of a
  // huge count, not time.end: the message names the material key.
  const std::string material =
      scene.time.automatic ? implausible_material_described(scene, {"density", "youngs_modulus"}) : std::string();
  std::ostringstream m;
  m << "time.end = " << scene.time.end << " s with a time step of " << dt << " s (stable limit "
    << sim.stable_time_step() << " s" << (material.empty() ? "" : ", from the material") << ") is " << length.steps
    << " steps; at the " << sim.force_evaluation_seconds() << " s per step measured at set-up that is about "
    << length.seconds / 86400.0 << " days";
  length.description = m.str();
  length.advice =
      material.empty()
          ? "shorten time.end, raise time.step, or check the particle file for a tiny cell that collapses the stable "
            "step"
          : "the stable step sqrt(2 rho / (a particle's sum of bond stiffnesses)) (theory.md Sec. 4.5) follows from "
            "the density and Young's modulus: check the material value and its unit; a shorter time.end would not "
            "make the run meaningful";
  long_run_warning = check_run_length(length, material.empty() ? scene.path : material);
  return static_cast<long>(length.steps);
}

// The energy supplied to the plate [J]: the size of the external work and
// what the plate held at the start beyond the work counted then (theory.md
// Sec. 4.3: a kick, initial velocities or a sudden velocity load, is
// external work at t = 0, and counts once).
double energy_supplied(double external_work, double energy_beyond_work) {
  return std::fabs(external_work) + energy_beyond_work;
}

// The energy check of a run: the plate must not hold far more energy than
// it was ever given. Returns the reason if it does, else an empty string.
std::string energy_blow_up(double energy, const char* what, double external_work, double energy_beyond_work) {
  const double supplied = energy_supplied(external_work, energy_beyond_work);
  if (energy <= 100.0 * supplied + 1e-15) return {};
  std::ostringstream m;
  m << what << " " << energy << " J exceeds 100 x the energy supplied (" << supplied << " J)";
  return m.str();
}

// The gain over the energy supplied beyond which a run is warned that it
// does not conserve energy, as a fraction of the largest energy supplied so
// far. Measured (docs/solver.md, "Safety"): the shipped scenes stay below
// 0.01, a kicked plate's first steps below 0.04 (velocity-Verlet's K + U
// oscillates, theory.md Sec. 4.4); runs that gain pass 0.3 as they crack.
constexpr double energy_gain_margin = 0.1;

// What a run that gains energy is told (once, at the energy row where the
// gain first passes the margin). `split_energy`: what refinement splits
// added [J], which their own warning names and the gain leaves out.
// `known_cause`: the cause the set-up knows of (empty if none).
struct EnergyGain {
  long step = 0;
  double time = 0;          // [s]
  double energy = 0;        // kinetic + strain [J]
  double supplied = 0;      // energy_supplied, with the traction work ahead [J]
  double split_energy = 0;  // [J]
  std::string known_cause;
};

std::string energy_gain_warning(const EnergyGain& g) {
  std::ostringstream w;
  w.precision(4);
  const double kept = g.energy - g.split_energy;
  w << "energy not conserved: at step " << g.step << " (t = " << g.time << " s) the plate holds " << g.energy
    << " J (kinetic + strain)";
  if (g.split_energy > 0) w << ", " << kept << " J without the " << g.split_energy << " J refinement splits added";
  w << ", " << kept / g.supplied << " times the " << g.supplied
    << " J supplied (|external work| and the start's energy beyond it; warned past " << energy_gain_margin
    << " of the largest supplied so far, theory.md Sec. 4.3): the run makes energy"
    << (g.known_cause.empty() ? std::string() : " (" + g.known_cause + ")")
    << "; the usual causes: a time step near the stable limit, a model that gains energy at breaks, ordinary PD "
       "on variable horizons, a refinement split after the crack passed; the gain is the rise of energy.csv's "
       "total_minus_work_J; the run goes on (it stops as unstable at 100 times)";
  return w.str();
}

// The particles of `region` (global ids) this process owns, in its local numbering.
std::vector<std::uint32_t> owned_part(const std::vector<std::uint32_t>& region, const Simulation& sim) {
  if (!sim.distributed()) return region;
  const auto owned_begin = sim.global_ids().begin();
  const auto owned_end = owned_begin + static_cast<std::ptrdiff_t>(sim.owned_count());  // ascending global ids
  std::vector<std::uint32_t> mine;
  for (auto id : region) {
    const auto at = std::lower_bound(owned_begin, owned_end, id);
    if (at != owned_end && *at == id) mine.push_back(static_cast<std::uint32_t>(at - owned_begin));
  }
  return mine;
}

// Largest damage among the stop region's particles, over all ranks.
double region_damage(const Simulation& sim, const std::vector<std::uint32_t>& region) {
  const auto& d = sim.damage();
  double largest = 0;
  for (auto i : region) largest = std::max(largest, d[i]);
  return sim.communicator().max(largest);
}

// The region's most damaged particle over all processes (the same one
// whatever the partition: largest damage, then smallest x, then y).
RegionPeak most_damaged_on_processes(const Simulation& sim, const std::vector<std::uint32_t>& region) {
  const RegionPeak local = most_damaged(region, sim.damage(), sim.reference_x(), sim.reference_y());
  const Communicator& comm = sim.communicator();
  RegionPeak peak;
  peak.damage = comm.max(local.damage);
  const double inf = std::numeric_limits<double>::infinity();
  peak.x = comm.min(local.damage == peak.damage ? local.x : inf);
  peak.y = comm.min(local.damage == peak.damage && local.x == peak.x ? local.y : inf);
  return peak;
}

// What the snapshots this run writes would take on disk, with its
// checkpoint (for check_snapshot_volume; snapshots on). The snapshots: step 0
// (a fresh run), every interval after `first_step` up to `last_step`, and the
// last step when off the interval. A checkpoint (with checkpoints on) at its
// state arrays, 8 bytes each per particle, and a byte per bond.
SnapshotVolume snapshot_volume(const RunContext& run, const Simulation& sim, long first_step, long last_step) {
  const OutputSpec& o = run.scene.output;
  const long interval = o.snapshot_interval;
  SnapshotVolume volume;
  volume.snapshots = std::floor(static_cast<double>(last_step) / interval) -
                     std::floor(static_cast<double>(first_step) / interval) + (run.options.restart ? 0 : 1) +
                     (last_step % interval != 0 ? 1 : 0);
  volume.particles = static_cast<double>(sim.whole_particle_count());
  // ux, uy, vx, vy, fx, fy, damage and an arrival time per threshold.
  volume.checkpoint_bytes = o.checkpoint_interval > 0
                                ? 8.0 * (7 + static_cast<double>(o.damage_thresholds.size())) * volume.particles +
                                      static_cast<double>(sim.bond_count())
                                : 0.0;
  volume.span = "from step " + std::to_string(run.options.restart ? first_step + 1 : first_step) + " to " +
                std::to_string(last_step);
  volume.advice = "shorten time.end (in s)";
  return volume;
}

// A restart from step `first_step`: the folder must hold the snapshots the
// checkpoint's run wrote up to there (step 0 and every interval), which
// snapshots.pvd will list. One missing means the folder's series is not that
// run's (removed by hand, or by a run of an earlier version that kept the
// checkpoint); pd::Error naming it rather than a collection of absent files.
void check_snapshots_before(const RunContext& run, long first_step) {
  const long interval = run.scene.output.snapshot_interval;
  if (interval <= 0) return;
  for (long step = 0; step <= first_step; step += interval) {
    const std::string name = snapshot_name(step);
    std::error_code error;
    if (std::filesystem::is_regular_file(run.path(name), error)) continue;
    std::ostringstream m;
    m << run.path(name) << ": missing, though the run of " << run.path(checkpoint_file)
      << " wrote it (a snapshot every " << interval << " steps up to its step " << first_step
      << "): the folder does not hold that run's snapshots, and snapshots.pvd would list an absent file; "
         "run without --restart to start over";
    throw Error(m.str());
  }
}

void print_plan(const RunContext& run, const Simulation& sim, long first_step, long last_step,
                const std::vector<std::string>& run_warnings, const AdaptiveRefinement* refinement) {
  const Scene& scene = run.scene;
  std::ostream& log = run.log();
  print_plan_header(log, run, {sim.model(), sim.setup_facts(), sim.whole_loads(), 0, run_warnings}, "dynamic");
  // Owned particles, summed over the processes (collective). With dual
  // horizons the general particles' bonds among themselves are dual-horizon
  // rows (each bond with its owner's constants and its reaction); the
  // lattice's pairs are constant-horizon PD (theory.md Sec. 6.7).
  const Communicator& comm = sim.communicator();
  const std::uint64_t lattice = comm.sum(static_cast<std::uint64_t>(sim.lattice_particle_count()));
  const std::uint64_t moved = comm.sum(static_cast<std::uint64_t>(sim.moved_off_lattice_count()));
  const HorizonMode horizons = sim.setup_facts().horizon_mode;
  const bool dual = horizons == HorizonMode::dual_horizon;
  if (horizons == HorizonMode::ordinary_variable)
    log << "  kernel:    neighbour lists for all " << sim.whole_particle_count()
        << " particles (ordinary PD with variable horizons has no lattice sweep)";
  else if (dual && lattice == 0)
    log << "  kernel:    dual-horizon rows for all " << sim.whole_particle_count()
        << " particles (no square on the lattice sweep in this run)";
  else if (lattice == 0)
    log << "  kernel:    " << (dual ? "dual-horizon rows" : "neighbour lists") << " for all "
        << sim.whole_particle_count() << " particles (no particle on the lattice sweep"
        << (moved == 0 ? std::string()
                       : ": its " + std::to_string(moved) + " squares taken off it (" +
                             (dual ? "one-way bonds or other horizons" : "one-way bonds") + ")")
        << ")";
  else
    log << "  kernel:    lattice sweep for " << lattice << " particles"
        << (dual ? " (squares at the stencil's horizon)" : "") << ", "
        << (dual ? "dual-horizon rows" : "neighbour lists") << " for " << sim.whole_particle_count() - lattice
        << (moved == 0 ? std::string()
                       : " (" + std::to_string(moved) + " of them squares taken off the lattice: " +
                             (dual ? "one-way bonds or other horizons)" : "one-way bonds)"));
  if (sim.distributed()) log << ", on " << run.processes << " processes (slabs of balanced bonds)";
  log << (sim.model().kernel_note.empty() ? std::string() : " (" + sim.model().kernel_note + ")") << "\n";
  if (run.processes > 1) {
    // (Collective: every process takes part.)
    const auto largest_read = static_cast<std::uint64_t>(comm.max(static_cast<double>(run.particles_read)));
    if (run.band_setup)
      log << "  set-up:    on each process's slab's band of the particle file (at most " << largest_read << " of "
          << run.particle_count << " particles read by a process)\n";
    else
      log << "  set-up:    on the whole plate on every process (" << run.whole_plate_reason << ")\n";
  }
  log << "  time step: " << sim.time_step() << " s (stable limit " << sim.stable_time_step() << " s"
      << (scene.time.automatic ? ", safety " + format_number(scene.time.safety) : std::string(", fixed"))
      << (sim.time_step_capped_at_end()
              ? ", capped at time.end: the stable step " + format_number(scene.time.safety * sim.stable_time_step()) +
                    " s is longer than the whole run, which takes one step"
              : std::string())
      << (sim.time_step() > sim.stable_time_step() ? ", ABOVE THE LIMIT (forced)" : "") << ")\n"
      << "  steps:     " << first_step << " -> " << last_step << " (end time " << scene.time.end << " s"
      // An end shorter than a fixed step (a time in another unit) still
      // takes one, of the step the scene gives (an automatic step is capped
      // at the end instead).
      << (first_step == 0 && scene.time.end < sim.time_step()
              ? ", shorter than one time step: the run takes one step, to " + format_number(sim.time_step()) +
                    " s (time.step = " + format_number(sim.time_step()) +
                    " s is longer than time.end; step = \"auto\" would end at time.end)"
              : std::string())
      << "), about " << duration_text(static_cast<double>(last_step - first_step) * sim.force_evaluation_seconds())
      << " at the set-up's force evaluation"
      // A refined set's stable step is about half its parent's per level: the count grows at each event.
      << (scene.refinement.enabled
              ? "; more after refinement events (each level about halves the step: up to about " +
                    std::to_string((last_step - first_step) << scene.refinement.levels) + " steps)"
              : std::string())
      << "\n";
  if (scene.refinement.enabled) {
    // What decides a split (theory.md Sec. 8.1), as the scene's keys say it.
    const RefinementSpec& f = scene.refinement;
    const bool lead = f.event_split_fraction() < f.strain_fraction;
    // --set made the section (the documented way to try refinement on a
    // scene without it): said, so that the run's refinement is no surprise.
    log << "  refinement: "
        << (f.made_by_set.empty() ? std::string()
                                  : "on by --set " + f.made_by_set + " (the scene has no [refinement]); ")
        << "every " << f.check_interval << " steps, split where damage > "
        << format_number(f.damage_threshold) << " or "
        << (f.strain == RefinementStrain::bond ? "a bond's stretch" : "the normal strain") << " > "
        << format_number(f.strain_fraction) << " s0"
        << (lead ? " (then also > " + format_number(f.event_split_fraction()) + " s0: the lead)" : std::string())
        << ", spread " << spread_name(f)
        << ", up to " << f.levels << (f.levels == 1 ? " halving" : " halvings")
        << (f.has_region ? ", in [" + format_mm(f.region[0]) + ", " + format_mm(f.region[2]) + "] x [" +
                               format_mm(f.region[1]) + ", " + format_mm(f.region[3]) + "]"
                         : std::string(", anywhere"))
        << (f.particle_budget > 0 ? ", budget " + std::to_string(f.particle_budget) + " particles" : std::string());
    // The worst case the settings allow: every particle that may split, at every level.
    if (refinement)
      log << "; at most " << refinement->worst_case_particle_count() << " particles (from "
          << refinement->initial_particle_count()
          << (f.particle_budget > 0 ? "; " + std::to_string(refinement->worst_case_particle_count(false)) +
                                          " without the budget"
                                    : std::string())
          << ")";
    log << "\n";
  }
  const auto& o = scene.output;
  print_plan_footer(log, run,
                    "energy every " + std::to_string(o.energy_interval) + " steps, snapshots " +
                        (o.snapshot_interval ? "every " + std::to_string(o.snapshot_interval) + " steps"
                                             : std::string("off")) +
                        ", checkpoints " +
                        (o.checkpoint_interval ? "every " + std::to_string(o.checkpoint_interval) + " steps"
                                               : std::string("off")));
}

void write_summary_of(const RunContext& run, const Simulation& sim, const RunReport& report, long steps_this_run,
                      const OutputCost& output_cost, const AdaptiveRefinement* refinement,
                      const std::vector<std::string>& run_warnings) {
  const auto e = sim.energies();
  const auto& d = sim.damage();
  std::uint64_t damaged = 0;
  double max_damage = 0;
  for (std::size_t i = 0; i < sim.owned_count(); ++i) {
    damaged += d[i] > 0 ? 1 : 0;
    max_damage = std::max(max_damage, d[i]);
  }
  const Communicator& comm = sim.communicator();
  damaged = comm.sum(damaged);
  max_damage = comm.max(max_damage);
  const std::uint64_t broken = sim.broken_bond_count();
  // Per step: the displacements, and a state-based model's theta / m.
  const int exchanges = 1 + sim.ghost_value_exchanges_per_step();
  const std::uint64_t ghost_bytes =
      comm.sum(comm.ghost_bytes_sent_per_update() +
               static_cast<std::uint64_t>(exchanges - 1) * comm.ghost_value_bytes_sent_per_update());
  const double ghost_seconds = comm.max(comm.ghost_update_seconds());
  const double ghost_wait_seconds = comm.max(comm.ghost_wait_seconds());
  const std::uint64_t lattice = comm.sum(static_cast<std::uint64_t>(sim.lattice_particle_count()));
  const auto particles_read = static_cast<std::uint64_t>(comm.max(static_cast<double>(run.particles_read)));
  const auto grid_cells = static_cast<std::uint64_t>(comm.max(static_cast<double>(sim.lattice_grid_cell_count())));
  if (!comm.is_root()) return;
  JsonObject final_state;
  final_state.number("kinetic_energy_J", e.kinetic)
      .number("strain_energy_J", e.strain)
      .number("external_work_J", e.external_work)
      .integer("broken_bonds", static_cast<std::int64_t>(broken))
      .integer("damaged_particles", static_cast<std::int64_t>(damaged))
      .number("max_damage", max_damage);
  JsonObject j = summary_fields(
      run,
      {sim.model(), sim.setup_facts(), sim.whole_loads(), refinement ? sim.particle_count() : 0,
       run_warnings},
      "dynamic",
      report.stop_reason, report.wall_seconds);
  j.number("time_step_s", sim.time_step())
      .number("stable_time_step_s", sim.stable_time_step())
      .number("requested_end_time_s", run.scene.time.end)
      .integer("steps", report.steps)
      .integer("steps_this_run", steps_this_run)
      .number("end_time_s", report.time)
      .integer("lattice_particles", static_cast<std::int64_t>(lattice))  // on the lattice sweep, all processes
      .integer("lattice_grid_cells_max", static_cast<std::int64_t>(grid_cells))  // the largest process's sweep grid
      .number("directed_bond_evaluations_per_second", report.bond_evaluations_per_second)
      .number("directed_bond_evaluations_per_second_per_thread",
              report.bond_evaluations_per_second / std::max(1, run.threads * run.processes))
      .object("final", final_state)
      .number("output_seconds", output_cost.seconds())  // the root process's (docs/formats.md)
      .number("output_share_of_time_loop", output_cost.share());
  if (run.processes > 1) {
    JsonObject exchange;
    exchange.integer("ghost_bytes_per_step", static_cast<std::int64_t>(ghost_bytes))  // all processes together
        .integer("ghost_exchanges_per_step", exchanges)
        .number("ghost_update_seconds_max", ghost_seconds)  // the slowest process, waiting included
        .number("ghost_wait_seconds_max", ghost_wait_seconds)  // of that, in the finishing halves (waiting, unpacking)
        .text("setup", run.band_setup ? "slab band" : "whole plate")
        .text("setup_whole_plate_reason", run.whole_plate_reason)
        .integer("setup_particles_read_max", static_cast<std::int64_t>(particles_read));
    j.object("mpi", exchange);
  }
  if (refinement) {
    // The criteria the run used, the scene's keys with their defaults filled in.
    const RefinementSpec& f = run.scene.refinement;
    JsonObject settings;
    settings.integer("check_interval", f.check_interval)
        .number("damage_threshold", f.damage_threshold)
        .text("strain", f.strain == RefinementStrain::bond ? "bond" : "normal")
        .number("strain_fraction", f.strain_fraction)
        .number("lead_fraction", f.event_split_fraction())
        .text("spread", spread_name(f))
        .integer("levels", f.levels)
        .integer("particle_budget", f.particle_budget);
    if (f.has_region) {
      JsonObject region;
      region.number("xmin", f.region[0]).number("ymin", f.region[1]);
      region.number("xmax", f.region[2]).number("ymax", f.region[3]);
      settings.object("region_m", region);
    }
    JsonObject r;
    r.integer("events", static_cast<std::int64_t>(refinement->events().size()))
        .integer("particles_start", static_cast<std::int64_t>(refinement->initial_particle_count()))
        .integer("particles_end", static_cast<std::int64_t>(sim.particle_count()))
        .number("seconds", refinement->seconds())
        .integer("bonds_broken_by_splits", static_cast<std::int64_t>(refinement->bonds_broken_by_splits()))
        .number("energy_added_by_splits_J", refinement->energy_added_by_splits())
        .object("settings", settings);
    j.object("refinement", r);
  }
  write_summary(run, j, sim.bond_count());
}

}  // namespace

std::shared_ptr<DeferredCacheWrite> check_dynamic_plan(RunContext run) {
  // (The Simulation refuses a step above the stable limit as it is set up.)
  const Simulation sim(run.scene, std::move(run.particles), std::move(run.families), run.setup_options());
  std::string long_run_warning;  // (the run's own plan says it)
  const long last_step = step_count(run.scene, sim, long_run_warning);
  if (run.scene.output.snapshot_interval > 0) check_snapshot_volume(run, snapshot_volume(run, sim, 0, last_step));
  return run.deferred_cache;
}

RunReport run_dynamic(RunContext run, const InitialState& initial_state) {
  const Scene& scene = run.scene;
  const std::string& out = run.output_dir();
  // Adaptive refinement keeps the particle set with its cells and families
  // (the problem drops them): the particle file is read once more, whole.
  // It runs on one process (run.cpp refuses it on more).
  std::unique_ptr<AdaptiveRefinement> refinement;
  if (scene.refinement.enabled) {
    keep_freed_blocks_for_reuse();  // each event frees and builds a simulation
    refinement = std::make_unique<AdaptiveRefinement>(scene, read_particle_file(scene.particle_file), run.log());
    refinement->show_details(run.options.refinement_details);
    refinement->echo_warnings_to(warning_echo(run));
  }
  // Every process reads the same checkpoint and particles: their errors are
  // printed once (on_every_process, before the exchanges of the partition).
  // A restart on one process without refinement checks its checkpoint here
  // and reads the state straight into the simulation once it is set up (no
  // copy of the state held through the set-up, docs/performance.md); the
  // others read it whole here (a refined set is rebuilt from its events, and
  // every process picks its part out of the whole plate's state), and so
  // does one process a checkpoint of several, whose bond states go family by
  // family (the simulation keeps its families to place them).
  std::optional<Checkpoint> checkpoint;
  bool restart_in_place = run.options.restart && run.processes == 1 && !scene.refinement.enabled;
  HorizonMode horizons = HorizonMode::uniform;
  on_every_process([&] {
    if (restart_in_place) restart_in_place = !check_checkpoint(run.path(checkpoint_file), run.checkpoint_key);
    if (run.options.restart && !restart_in_place)
      checkpoint = read_checkpoint(run.path(checkpoint_file), run.checkpoint_key);
    if (run.processes > 1) horizons = horizon_mode(scene, run.particles);
  });
  const bool refined_checkpoint = checkpoint && !checkpoint->refinements.empty();
  if (refined_checkpoint && !refinement)
    throw Error(run.path(checkpoint_file) + ": the checkpoint holds a refined particle set, but " + scene.path +
                " has no [refinement]");
  // On several processes: this one's slab, and the communicator of its ghosts.
  std::optional<Partition> partition;
  std::unique_ptr<Communicator> distributed;
  // `sim` is replaced by each refinement event: everything below reaches it through this pointer.
  std::unique_ptr<Simulation> sim;
  if (refined_checkpoint) {
    // The checkpoint's refined set, split again from the particle file as the run split it.
    try {
      refinement->replay(checkpoint->refinements);
    } catch (const Error& e) {
      throw Error(run.path(checkpoint_file) + ": its refinement events do not fit " + scene.particle_file + " (" +
                  e.what() + ")");
    }
    sim = refinement->simulation();
  } else {
    if (run.band_setup) {
      partition = std::move(run.band_partition);  // made from the band (read_slab_band)
    } else if (run.processes > 1) {
      // Dual horizons: a particle's row also holds the bonds others own towards it.
      const GhostReach reach =
          horizons == HorizonMode::dual_horizon ? GhostReach::bonds_both_ways : GhostReach::own_bonds;
      partition =
          slab_partition(run.particles, run.families, process_rank(), run.processes, scene.particle_file, reach);
    }
    if (partition) distributed = distributed_communicator(*partition);
    // A one-process run's checkpoint on several processes: its bond states
    // family by family, turned so by the root (before this process's set-up,
    // so that the root's one-process set-up does not come on top of it).
    if (checkpoint && distributed)
      take_bond_states_by_family(run, run.path(checkpoint_file), checkpoint->state, *distributed);
    // An adaptive run keeps the first set's bond weights for its first event's set-up.
    SetupOptions setup = refinement ? refinement->first_setup(run.setup_options()) : run.setup_options();
    if (checkpoint && !distributed && checkpoint->state.bond_states_by_family) setup.keep_families = true;
    sim = std::make_unique<Simulation>(scene, std::move(run.particles), std::move(run.families), setup,
                                       distributed ? *distributed : serial_communicator(),
                                       partition ? &*partition : nullptr, run.band_setup ? &run.whole_plate : nullptr);
    run.whole_plate = WholePlateFacts{};
    partition.reset();
  }
  // Files are written by the root process only (outputs gather onto it).
  const bool root = sim->communicator().is_root();
  // The stop region (this process's part of it) and the step count follow
  // the particle set and its time step.
  std::vector<std::uint32_t> stop_region = owned_part(run.stop_region, *sim);
  const auto refined_set_changed = [&] {
    if (scene.stop.enabled)
      run.stop_region = resolve_region(scene.stop.region, refinement->particles(), scene.path, "stop");
    stop_region = owned_part(run.stop_region, *sim);
  };
  // The run's own warnings, in the plan and summary.json's "warnings".
  std::string long_run_warning, snapshot_warning;
  std::string break_energy_warning = osb_break_energy_warning(scene, run.spacing, sim->model().horizon);
  std::string horizons_warning = ordinary_variable_horizon_warning(scene, sim->setup_facts());
  std::string force_warning = needless_force_warning(scene, *sim);
  std::string growth_warning = refinement ? refinement_growth_warning(scene, *refinement) : std::string();
  const auto run_warnings = [&] {
    std::vector<std::string> list;
    for (const std::string* w : {&break_energy_warning, &horizons_warning, &force_warning, &growth_warning,
                                 &long_run_warning, &snapshot_warning})
      if (!w->empty()) list.push_back(*w);
    return list;
  };
  const auto last_step_of = [&] {
    if (!refinement || refinement->events().empty()) return step_count(scene, *sim, long_run_warning);
    const SplitEvent& last = refinement->events().back();
    return step_count(scene, *sim, long_run_warning, last.step, last.time);
  };
  if (refined_checkpoint) refined_set_changed();

  EnergyLog energy(*sim);
  // The energy checks' state from the run's start (check_energy_gain), the
  // checkpoint's on a restart: a restarted run checks and warns as the run
  // that never stopped. Before the end's extra energy row it is kept for
  // the last step's checkpoint, which leaves that row out.
  EnergyCheckState energy_check, energy_check_before_end_row;
  // The run's files, written by the root (on several processes the others
  // take part in their gathers, which come first): a write that fails there
  // (a full disk, the snapshot folder replaced by a file during the run)
  // ends every process with the root's message, said once, which names the
  // file, its cause, the step and what is left (written_by_the_root, one
  // agreement per file at output steps only; before 7 December 2026 the
  // root said it with its rank and MPI_Abort's banner followed). `write`
  // makes at most one write that gathers, and after it the root's own.
  const auto written = [&](const std::function<void()>& write) {
    written_by_the_root([&] {
      try {
        write();
      } catch (const Error& e) {
        // A place taken since the start (a folder where a result goes, a
        // file where the snapshots go) is named as at the start, with what
        // to do (the atomic write alone would say "name a file"), where it
        // is the failed write's.
        std::string what = e.what();
        // The start's words end in its advice, "move it, or give -o a new or
        // empty folder", which here would stand beside the one below (before
        // 7 December 2026 both were said, and the second contradicted the
        // first where a restart goes on): taken off, one instruction follows.
        const std::string start_advice = std::string("; ") + taken_place_advice;
        bool taken_place = false;
        try {
          check_result_paths(scene, out, false);
        } catch (const Error& taken) {
          const std::string place = std::string(taken.what()).substr(0, std::string(taken.what()).find(": "));
          if (what.compare(0, place.size(), place) == 0) {
            what = taken.what();
            if (what.size() >= start_advice.size() &&
                what.compare(what.size() - start_advice.size(), start_advice.size(), start_advice) == 0)
              what.erase(what.size() - start_advice.size()), taken_place = true;
          }
        }
        const bool restartable = scene.output.checkpoint_interval > 0 || run.options.restart;
        std::ostringstream m;
        m << what << "; the run stopped at step " << sim->step_index() << " (t = " << sim->time()
          << " s), its files written before it left whole; "
          << (restartable ? std::string(taken_place ? "move it away"
                                                    : "mend the cause (free disk space, put the folder back)") +
                                ", then the same command with --restart goes on from the last checkpoint"
                          : taken_place ? std::string("run it again with -o a new folder")
                                        : std::string("mend the cause (free disk space, put the folder back), then "
                                                      "run it again"));
        throw Error(m.str());
      }
    });
  };
  // The snapshot folder removed during the run (by hand, to free disk space,
  // or by mistake): the next snapshot makes it again, and snapshots.pvd
  // lists the steps before, whose files are gone. Warned once, by the root,
  // when it makes the folder again, and in summary.json (before 7 December
  // 2026 without a word). A restart's folder holds the earlier snapshots
  // (check_snapshots_before).
  std::string snapshots_removed_warning;
  bool snapshots_written = run.options.restart;
  const auto before_snapshot = [&] {
    const std::filesystem::path folder = std::filesystem::path(out) / results::snapshot_folder;
    std::error_code error;
    if (root && snapshots_written && snapshots_removed_warning.empty() &&
        std::filesystem::symlink_status(folder, error).type() == std::filesystem::file_type::not_found) {
      std::ostringstream w;
      w << folder.string() << ": removed during the run, made again for the snapshot of step " << sim->step_index()
        << "; snapshots.pvd lists the snapshots of the steps before, whose files went with it (ParaView and pd-post "
           "will not find them); run again to have the whole series";
      snapshots_removed_warning = w.str();
      run.log() << "warning: " << snapshots_removed_warning << std::endl;
      if (std::ostream* echo = warning_echo(run)) *echo << "pd-solve: warning: " << snapshots_removed_warning << std::endl;
    }
    snapshots_written = true;
  };
  // state_view gathers the whole plate's state onto the root (collective);
  // on one process the file is written from the state itself, not a copy.
  // `without_last_row`: the energy rows as a run that goes on past this step
  // has them (the end's extra row left out).
  const auto save_checkpoint = [&](bool without_last_row = false) {
    written([&] {
      Simulation::State scratch;
      const Simulation::StateView state = sim->state_view(scratch);
      if (!root) return;
      EnergyRecords records{energy.rows(), without_last_row ? energy_check_before_end_row : energy_check};
      if (without_last_row) records.rows.pop_back();
      write_checkpoint(run.path(checkpoint_file), run.checkpoint_key, state, records,
                       refinement ? refinement->events() : std::vector<SplitEvent>{});
    });
  };
  const auto restore_records = [&](EnergyRecords&& records) {
    energy.set_rows(std::move(records.rows));
    energy_check = std::move(records.check);
  };
  if (checkpoint) {
    sim->restore_state(checkpoint->state);
    restore_records(std::move(checkpoint->energy));
    checkpoint.reset();
  } else if (restart_in_place) {
    sim->restore_state_in_place([&](Simulation::State& state) {
      restore_records(read_checkpoint_in_place(run.path(checkpoint_file), run.checkpoint_key, state));
    });
  } else {
    if (initial_state) initial_state(*sim);
    // A stop condition that already holds would end the run after its first
    // step, with nothing simulated (e.g. a stop set the pre-crack reaches).
    if (scene.stop.enabled) {
      const double start_damage = region_damage(*sim, stop_region);
      on_every_process([&] {
        if (start_damage >= scene.stop.damage)
          throw Error(stop_holds_at_start(scene, start_damage, "step",
                                          initial_state ? "the pre-cracks or the quasi-static part" : "the pre-cracks"));
      });
    }
  }
  const long first_step = sim->step_index();
  // An automatic step capped at time.end (a stable step longer than the
  // run) changes with time.end, which a restart may change: the
  // checkpoint's steps would not be this run's. (Without refinement the
  // time of step n is n dt, up to the round-off of the sum.)
  if (run.options.restart && !refinement && first_step > 0) {
    const double checkpoint_step = sim->time() / static_cast<double>(first_step);
    on_every_process([&] {
      if (std::fabs(checkpoint_step - sim->time_step()) > 1e-6 * sim->time_step()) {
        std::ostringstream m;
        m << run.path(checkpoint_file) << ": its run took steps of " << checkpoint_step << " s (step "
          << first_step << ", t = " << sim->time() << " s), this run's is " << sim->time_step() << " s"
          << (sim->time_step_capped_at_end() ? " (the automatic step capped at time.end, which changed)" : "")
          << ": a restart goes on with the checkpoint's step; run without --restart to start over";
        throw Error(m.str());
      }
    });
  }
  // Every process counts the same steps: a run too long to count is refused
  // once (before 7 December 2026 each process said so, with its rank).
  long last_step = 0;
  on_every_process([&] { last_step = last_step_of(); });
  // A restart of a run that ended on its [stop] condition would take one
  // step and stop again, rewriting the results with that step.
  const double stop_damage_now =
      run.options.restart && scene.stop.enabled ? region_damage(*sim, stop_region) : 0.0;
  on_every_process([&] {
    if (run.options.restart && scene.stop.enabled && stop_damage_now >= scene.stop.damage) {
      std::ostringstream m;
      m << run.path(checkpoint_file) << ": the run stopped on its stop condition at step " << first_step
        << " (damage >= " << scene.stop.damage << " in " << scene.stop.region.describe()
        << "): a restart would stop again at once (a run that ended so cannot be extended; run again without --restart "
           "for another [stop])";
      throw Error(m.str());
    }
  });
  // A restart continues a run to a later end: an end at or before the
  // checkpoint's step would run nothing and rewrite the results as of that step.
  // The one exception: a run stopped after the checkpoint of its last step and
  // before its end files (no summary.json) is finished, taking no step.
  const bool finishes_only = run.options.restart && last_step == first_step &&
                             !std::filesystem::exists(run.path(results::summary_file));
  on_every_process([&] {
    if (run.options.restart && last_step <= first_step && !finishes_only) {
      std::ostringstream m;
      m << scene.source_of("time.end") << ": key 'time.end' = " << scene.time.end << " s is not after the time of "
        << run.path(checkpoint_file) << " (step " << first_step << ", t = " << sim->time()
        << " s): a restart continues a run to a later end time; raise time.end, or run without --restart to "
           "start over";
      throw Error(m.str());
    }
  });
  // Refinement that never checks: the run would go on coarse as if it had
  // been asked for. The default interval, not given, is said to be one, and
  // a later time.end is the other way out (before 7 December 2026 quoted as
  // if given, "give fewer steps (default 10)", a run shortened to try a
  // scene told nothing of time.end).
  if (refinement && scene.refinement.check_interval > last_step) {
    const long interval = scene.refinement.check_interval;
    std::ostringstream m;
    if (scene.refinement.check_interval_defaulted)
      m << scene.path << ": refinement.check_interval is not given, and its default, " << interval
        << " steps, is more than the run's " << last_step;
    else
      m << scene.source_of("refinement.check_interval") << ": key 'refinement.check_interval' = " << interval
        << " steps is more than the run's " << last_step;
    m << " steps (time.end = " << shortest_text(scene.time.end) << " s"
      << scene.from_set("time.end") << ", at a time step of "
      << format_number(sim->time_step()) << " s): the criteria would never be checked; give "
      << "refinement.check_interval = " << last_step << " or fewer, or a later time.end";
    throw Error(m.str());
  }
  if (scene.output.snapshot_interval > 0)
    on_every_process(
        [&] { snapshot_warning = check_snapshot_volume(run, snapshot_volume(run, *sim, first_step, last_step)); });
  if (run.options.restart) on_every_process([&] { check_snapshots_before(run, first_step); });
  // The checkpoint is taken: until this run ends, the folder holds an unfinished run (no summary.json).
  if (run.options.restart && process_rank() == 0) {
    std::error_code ignored;
    std::filesystem::remove(run.path(results::summary_file), ignored);
    // Snapshots the continued run will not write as they are: those of a
    // killed run after its last checkpoint (the continued run writes its own,
    // or none: a shorter end), an earlier end's off the interval (the
    // continued run passes that step without one, as an uninterrupted run
    // does), and any other off the interval (not the checkpoint's run's).
    const long interval = scene.output.snapshot_interval;
    const std::filesystem::path snapshots = run.path(results::snapshot_folder);
    std::vector<std::filesystem::path> foreign;
    if (std::filesystem::is_directory(snapshots, ignored))
      for (const auto& entry : std::filesystem::directory_iterator(snapshots, ignored)) {
        const long step = snapshot_step_of(entry.path().filename().string());
        if (step >= 0 && (step > first_step || interval <= 0 || step % interval != 0)) foreign.push_back(entry.path());
      }
    for (const auto& file : foreign) std::filesystem::remove(file, ignored);
    // pd-post's pictures of the run so far would look like the continued run's.
    remove_post_outputs(run.output_dir());
  }
  if (!run.options.restart) {
    // Every check of the set-up has passed: from here on the folder holds this run's results.
    // (On the root, which may refuse a folder of a user's files; all agree on it.)
    on_the_root([&] { run.clear_earlier_results(); });
    // (Before the outputs' arrays, and the double-precision energy's: the
    // evaluation's scratch goes first.)
    sim->release_evaluation_scratch();
    const EnergyTotals start = sim->energies();
    energy.record(*sim, start);
    // What the plate held at the start beyond the work counted by then: a
    // kick (initial velocities, a sudden velocity load) is external work at
    // t = 0 (theory.md Sec. 4.3), which the start's energy holds too.
    energy_check.energy_beyond_work =
        std::max(0.0, start.kinetic + start.strain - std::fabs(start.external_work));  // [J]
    energy_check.largest_supplied = energy_check.energy_beyond_work;
    // (Counted only for the messages of a run the plan warned gains energy as it cracks.)
    energy_check.broken_at_start = break_energy_warning.empty() ? 0 : sim->broken_bond_count();
    if (scene.output.snapshot_interval > 0) {
      before_snapshot();
      written([&] { write_snapshot(out, *sim, refinement != nullptr); });
    }
    // arrival.vtp from the start: a run stopped before its first checkpoint
    // still leaves the particles, the material and the arrivals so far.
    written([&] { write_arrival(out, *sim); });
    // A start state that took work to reach (a quasi-static equilibrium) is
    // saved at once, so that a restart never has to reach it again.
    if (initial_state && scene.output.checkpoint_interval > 0)
      save_checkpoint();
  }
  // (Every check has passed: the folder's cache may now take this set-up's factors.)
  run.write_deferred_cache();
  print_plan(run, *sim, first_step, last_step, run_warnings(), refinement.get());
  require_plan_written(run.log());
  // The energy gain's warning, once (given at an energy row, or carried by a
  // restart's checkpoint: said again, as the run's summary.json holds it).
  const auto say_energy_gain = [&] {
    run.log() << "warning: " << energy_check.gain_warning << std::endl;
    if (std::ostream* echo = warning_echo(run)) *echo << "pd-solve: warning: " << energy_check.gain_warning << std::endl;
  };
  if (!energy_check.gain_warning.empty()) say_energy_gain();

  const auto& o = scene.output;
  // The time of a step [s]: steps times the time step, piecewise between
  // refinement events (each refined set has its own step), from the recorded
  // events only, so that a restarted run lists the same times.
  const auto time_of_step = [&](long s) {
    const std::vector<SplitEvent> none;
    const auto& events = refinement ? refinement->events() : none;
    std::size_t e = 0;
    while (e < events.size() && events[e].step <= s) ++e;
    if (e == 0) return events.empty() ? s * sim->time_step() : s * (events[0].time / events[0].step);
    const SplitEvent& from = events[e - 1];
    const double dt = e < events.size() ? (events[e].time - from.time) / (events[e].step - from.step) : sim->time_step();
    return from.time + (s - from.step) * dt;
  };
  bool ended = false;  // the end's snapshot is listed even when off the interval
  const auto write_progress_files = [&] {
    sim->release_evaluation_scratch();
    written([&] {
      write_arrival(out, *sim);
      if (root) {
        energy.write(out);
        write_snapshot_collection(out, sim->scene().run_id, o.snapshot_interval, sim->step_index(), time_of_step,
                                  ended);
      }
    });
  };

  RunReport report;
  report.stop_reason = "end time";
  // Set-up of the loop (not timed): the first safe state. Both energy
  // checks count the supply from the run's start, a restart's too
  // (energy_check: the checkpoint's).
  const double energy_beyond_work = energy_check.energy_beyond_work;  // [J]
  // Bonds broken before the run's first step (pre-cracks), for the message
  // of a run that the plan warned gains energy as it cracks.
  const std::uint64_t broken_at_start = energy_check.broken_at_start;
  Simulation::State last_good;
  sim->save_rollback_state(last_good);
  Progress progress(first_step, last_step, sim->bond_count(), run.options.show_progress && sim->communicator().is_root());

  // Stops the run as unstable: the last good state is written out, then the
  // error. `seen_here`: whether this process saw the reason (every process
  // sees a sum over the plate; a non-finite value, the processes whose
  // particles have it): those report it (on_every_process: once if all did).
  const auto unstable = [&](const std::string& reason, bool seen_here) {
    const long step = sim->step_index();
    std::ostringstream m;
    m << "the run became unstable at step " << step << " (t = " << sim->time() << " s): " << reason
      << "; time step " << sim->time_step() << " s, stable limit " << sim->stable_time_step() << " s";
    if (!break_energy_warning.empty()) {
      const std::uint64_t broken = sim->broken_bond_count() - broken_at_start;
      if (broken > 0)
        m << "; " << broken << " directed bonds broke, and at this Poisson ratio "
          << (scene.osb_failure == OsbFailure::force_only ? "the forces left after breaks are not the gradient of "
                                                            "an energy and make energy"
                                                          : "each break adds energy")
          << " (the plan's warning, theory.md Sec. 5.8): a smaller step would not help";
    }
    // Ordinary PD on horizons that differ (the plan's warning) makes energy
    // at any step, as the energy gain's warning says too.
    if (!horizons_warning.empty())
      m << "; ordinary PD on variable horizons (model.dual_horizon = false; bonded particles' horizons differ by up "
        << "to " << sim->setup_facts().largest_bonded_horizon_ratio << " times: the plan's warning, theory.md Sec. "
        << "6.3) has pair forces that are not the gradient of an energy and may gain energy at any time step; "
        << "model.dual_horizon = true conserves it";
    sim->roll_back(last_good);
    sim->release_evaluation_scratch();
    if (o.snapshot_interval > 0) {
      before_snapshot();
      written([&] { write_snapshot(out, *sim, refinement != nullptr); });
    }
    written([&] {
      write_arrival(out, *sim);
      if (root) energy.write(out);
    });
    m << "; the last good state (step " << sim->step_index() << ") is in " << out;
    progress.stopped(step, sim->time());
    on_every_process([&] {
      if (seen_here) throw Error(m.str());
    });
    throw Error(m.str());  // (one process: on_every_process threw already)
  };
  // The energy check. The trapezoidal external work lags the last half kick:
  // a traction ramped from 0 has done no counted work at step 1 though its
  // kick moves the particles. That work is added (a pass over the loaded
  // particles) only when the check would fail without it.
  const auto check_energy = [&](double energy, const char* what, double external_work) {
    std::string reason = energy_blow_up(energy, what, external_work, energy_beyond_work);
    if (!reason.empty())
      reason = energy_blow_up(energy, what, std::fabs(external_work) + std::fabs(sim->traction_work_ahead()),
                              energy_beyond_work);
    if (!reason.empty()) unstable(reason, true);
  };
  const auto check_every_step = [&] {
    const NonFinite& bad = sim->non_finite();
    if (bad.found) {
      std::ostringstream m;
      const std::size_t id = sim->distributed() ? sim->global_ids()[bad.particle] : bad.particle;
      m << "non-finite " << bad.quantity << " of particle " << id << " at ("
        << sim->reference_x()[bad.particle] << ", " << sim->reference_y()[bad.particle] << ") m";
      unstable(m.str(), bad.on_this_process);
    }
    // Every step, at the cost of one sum in a pass the step makes anyway
    // (the kinetic energy; the strain energy needs a bond sweep).
    check_energy(sim->step_kinetic_energy(), "kinetic energy", sim->external_work());
  };
  // A gain below the blow-up: warned once, and the run goes on. Splits'
  // energy has its own warning (AdaptiveRefinement) and is left out here.
  // The traction work ahead is added, as in check_energy, only when the
  // gain would be warned without it. The supply counts the start's energy
  // beyond the work, as the blow-up check's (energy_supplied). A restart
  // goes on with the checkpoint's energy_check: the largest supplied and
  // the warning so far.
  const auto check_energy_gain = [&](const EnergyTotals& e) {
    if (!energy_check.gain_warning.empty()) return;
    const double split_energy = refinement ? std::max(0.0, refinement->energy_added_by_splits()) : 0.0;
    const double kept = e.kinetic + e.strain - split_energy;
    double supplied = energy_supplied(e.external_work, energy_beyond_work);
    energy_check.largest_supplied = std::max(energy_check.largest_supplied, supplied);
    const auto gains = [&] { return kept - supplied > energy_gain_margin * energy_check.largest_supplied + 1e-15; };
    if (!gains()) return;
    supplied =
        energy_supplied(std::fabs(e.external_work) + std::fabs(sim->traction_work_ahead()), energy_beyond_work);
    if (!gains()) return;
    std::string cause;
    if (!break_energy_warning.empty() && sim->broken_bond_count() > broken_at_start)
      cause = std::to_string(sim->broken_bond_count() - broken_at_start) + " directed bonds broke, " +
              (scene.osb_failure == OsbFailure::force_only
                   ? "and the forces left after breaks are not the gradient of an energy"
                   : "each adding energy") +
              " at this Poisson ratio: the plan's warning, theory.md Sec. 5.8";
    else if (sim->setup_facts().horizon_mode == HorizonMode::ordinary_variable)
      cause = "ordinary PD on variable horizons, model.dual_horizon = false (theory.md Sec. 6.3)";
    else if (sim->time_step() > sim->stable_time_step())
      cause = "a time step above the stable limit (time.force = true)";
    energy_check.gain_warning =
        energy_gain_warning({sim->step_index(), sim->time(), e.kinetic + e.strain, supplied, split_energy, cause});
    say_energy_gain();
  };
  // At energy rows and at the end: the whole energy.
  const auto check_energies = [&](const EnergyTotals& e) {
    check_energy(e.kinetic + e.strain, "kinetic + strain energy", e.external_work);
    check_energy_gain(e);
  };

  // Steps whose files need the strain energy: its sums ride on the step's force evaluation.
  const auto reports_energy = [&](long step) {
    return step % o.energy_interval == 0 || (o.snapshot_interval > 0 && step % o.snapshot_interval == 0) ||
           (o.checkpoint_interval > 0 && step % o.checkpoint_interval == 0);
  };
  OutputCost output_cost;
  const CatchInterrupts interrupts;  // Ctrl-C or SIGTERM ends the loop after its step
  int interrupted_by = 0;            // the signal that did
  while (sim->step_index() < last_step) {
    const bool with_energy = reports_energy(sim->step_index() + 1);
    output_cost.time_step(with_energy, [&] { sim->step(with_energy); });
    const long step = sim->step_index();
    check_every_step();
    // Refinement before this step's files, so that they show the set the run goes on with.
    // (Also at the last step: a restart with a later end goes on as the run
    // that never stopped, which split there. The split adds no step past the end.)
    if (refinement && step % scene.refinement.check_interval == 0) {
      // At an event the rollback copy goes before the refined set's set-up
      // (the event's peak memory): the refined set's state replaces it
      // below, and no step runs in between.
      if (auto refined = refinement->check(*sim, [&] { last_good = Simulation::State{}; })) {
        sim = std::move(refined);
        refined_set_changed();
        last_step = last_step_of();
        progress.replan(step, last_step, sim->bond_count());
        sim->save_rollback_state(last_good);
      }
    }
    if (step % o.energy_interval == 0) {
      output_cost.time_output([&] {
        const auto e = sim->energies();
        energy.record(*sim, e);
        check_energies(e);
        sim->save_rollback_state(last_good);
      });
    }
    if (o.snapshot_interval > 0 && step % o.snapshot_interval == 0) {
      output_cost.time_output([&] {
        sim->release_evaluation_scratch();
        before_snapshot();
        written([&] {
          write_snapshot(out, *sim, refinement != nullptr);
          if (root) {
            write_snapshot_collection(out, sim->scene().run_id, o.snapshot_interval, step, time_of_step);
            energy.write(out);
          }
        });
      });
    }
    if (o.checkpoint_interval > 0 && step % o.checkpoint_interval == 0) {
      output_cost.time_output([&] {
        sim->release_evaluation_scratch();
        save_checkpoint();
        write_progress_files();
      });
    }
    if (scene.stop.enabled && region_damage(*sim, stop_region) >= scene.stop.damage) {
      report.stop_reason = stop_condition_reason(scene.stop, most_damaged_on_processes(*sim, stop_region));
      break;
    }
    progress.update(step, sim->time());
    // (One read per step; set by Ctrl-C or SIGTERM. Several processes agree
    // on it, one max per step: each may have seen it at another step. In the
    // last step the run just ends: its end files take a moment and leave it finished.)
    const int signal = sim->distributed() ? static_cast<int>(sim->communicator().max(interrupt_signal()))
                                          : interrupt_signal();
    if (signal != 0 && sim->step_index() < last_step) {
      interrupted_by = signal;
      break;
    }
  }
  // Interrupted: the step is done; its checkpoint and progress files make the
  // run continue with --restart as if never stopped.
  if (interrupted_by != 0) {
    output_cost.time_output([&] {
      sim->release_evaluation_scratch();
      save_checkpoint();
    });
    last_good = Simulation::State{};
    progress.stopped(sim->step_index(), sim->time());
    write_progress_files();
    std::ostringstream m;
    m << "interrupted by " << interrupt_name(interrupted_by) << " at step " << sim->step_index() << " of " << last_step
      << " (t = " << sim->time() << " s): " << run.path(checkpoint_file)
      << " and arrival.vtp hold that step, energy.csv its rows so far; the same command with --restart continues "
         "the run";
    on_every_process([&] { throw Error(m.str()); });  // said once on several processes
    throw Error(m.str());
  }
  // The end (end time or stop condition) passes the whole energy check too.
  const bool end_row = energy.rows().empty() || sim->step_index() % o.energy_interval != 0;
  energy_check_before_end_row = energy_check;
  if (end_row) {
    sim->release_evaluation_scratch();
    const auto e = sim->energies();
    energy.record(*sim, e);
    check_energies(e);
  }
  // A run with checkpoints ends with one of its last step: --restart with a
  // later time.end goes on from there, not from the last interval's. (A run
  // that only finishes has that checkpoint already, without the end's row.)
  if (o.checkpoint_interval > 0 && sim->step_index() % o.checkpoint_interval != 0 && !finishes_only)
    output_cost.time_output([&] {
      sim->release_evaluation_scratch();
      save_checkpoint(end_row && sim->step_index() > first_step);
    });
  // Past the last check nothing rolls back: its copy goes before the last
  // files, whose temporary arrays would come on top of it.
  last_good = Simulation::State{};
  progress.finish(sim->step_index(), sim->time());
  // The last step has a snapshot also off the interval (an end time that is
  // no multiple of it, a stop condition): the series ends with the final state.
  ended = true;
  if (o.snapshot_interval > 0 && sim->step_index() % o.snapshot_interval != 0)
    output_cost.time_output([&] {
      sim->release_evaluation_scratch();
      before_snapshot();
      written([&] { write_snapshot(out, *sim, refinement != nullptr); });
    });
  output_cost.time_output(write_progress_files);
  report.steps = sim->step_index();
  report.time = sim->time();
  report.wall_seconds = progress.elapsed_seconds();
  const long steps_this_run = sim->step_index() - first_step;
  report.bond_evaluations_per_second =
      report.wall_seconds > 0 ? steps_this_run * static_cast<double>(sim->bond_count()) / report.wall_seconds : 0;
  // The plan's run warnings, those of this run's refinement events and its energy gain.
  std::vector<std::string> warnings = run_warnings();
  if (refinement) warnings.insert(warnings.end(), refinement->warnings().begin(), refinement->warnings().end());
  if (!energy_check.gain_warning.empty()) warnings.push_back(energy_check.gain_warning);
  if (!snapshots_removed_warning.empty()) warnings.push_back(snapshots_removed_warning);
  written([&] { write_summary_of(run, *sim, report, steps_this_run, output_cost, refinement.get(), warnings); });
  run.log() << "done: " << report.steps << (report.steps == 1 ? " step, t = " : " steps, t = ") << report.time
            << " s (" << report.stop_reason << "), "
            << report.wall_seconds << " s wall, " << report.bond_evaluations_per_second
            << " directed bond evaluations/s (" << report.bond_evaluations_per_second / (run.threads * run.processes)
            << " per thread), outputs " << output_cost.seconds() << " s ("
            // (A short run's outputs can take many times its steps: "25526.6 %" read as an error.)
            << (output_cost.share() <= 1 ? format_number(100.0 * output_cost.share()) + " % of"
                                         : format_number(output_cost.share()) + " times")
            << " the rest of the time loop), peak memory "
            << peak_memory_text(sim->bond_count()) << "\n";
  return report;
}

}  // namespace pd::solver
