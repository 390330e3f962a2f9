#include "load_steps.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <ostream>
#include <sstream>

#include "error.hpp"
#include "load_step_predictor.hpp"
#include "loads.hpp"
#include "mixed_precision.hpp"
#include "units.hpp"

namespace pd::solver {

double axial_reaction(const std::vector<LoadResultant>& reactions, const std::vector<ResolvedLoad>& loads) {
  double largest = 0;
  for (std::size_t l = 0; l < loads.size(); ++l)
    if (loads[l].spec.kind == LoadKind::displacement)
      largest = std::max({largest, std::fabs(reactions[l].reaction_x), std::fabs(reactions[l].reaction_y)});
  return largest;
}

namespace {

// Forces that are no numbers: the loads at this load factor overflowed the
// arithmetic, and neither iterations nor on_nonconvergence = "warn" can make
// a state of them (before 7 December 2026 the message read "relative
// residual -nan"). `minimisation`: the one that ended so (0: at the step's
// start, before any).
[[noreturn]] void refuse_non_finite_forces(const Scene& scene, long step, double factor, long minimisation) {
  std::ostringstream m;
  m << scene.path << ": load step " << step << " (load factor " << shortest_text(factor) << ")";
  if (minimisation > 0) m << ", minimisation " << minimisation;
  m << ": the forces are no finite numbers: the loads at this load factor are too large for the arithmetic (see "
    << "the plan's warnings on the loads' size); check the load values and key 'quasi_static."
    << scene.quasi_static.load_steps_key << "'";
  throw Error(m.str());
}

// A round tolerance a stalled minimisation can meet: the power of ten at
// least 10 times its least residual.
double tolerance_above(double least_relative_residual) {
  return std::pow(10.0, std::ceil(std::log10(10 * least_relative_residual)));
}

// Forces so small that their squares underflow to 0 (a load factor of
// 1e-300): the residual's norm reads 0, every minimisation "converges" at
// once, and the interior never moves (before 7 December 2026 the run ended
// as a success with that state).
[[noreturn]] void refuse_underflowing_forces(const Scene& scene, long step, double factor) {
  std::ostringstream m;
  m << scene.path << ": load step " << step << " (load factor " << shortest_text(factor)
    << "): the forces are too small for the arithmetic (their squares are below the smallest double): the "
    << "minimisation could not measure them; check the load values and key 'quasi_static."
    << scene.quasi_static.load_steps_key << "'";
  throw Error(m.str());
}

// A load that acts at `factor`: not a support, and with a value this
// factor keeps a normal double (a displacement of 0 only holds the plate).
bool acts_at_factor(const ResolvedLoad& load, double factor) {
  if (factor == 0 || load.spec.kind == LoadKind::fixed || value_lost_at_factor(load, factor) != 0) return false;
  for (const auto* values : {load.spec.has_x ? &load.value_x : nullptr, load.spec.has_y ? &load.value_y : nullptr})
    if (values && std::any_of(values->begin(), values->end(), [](double v) { return v != 0; })) return true;
  return false;
}

// "the load 'a'", "the loads 'a' and 'b'", "the loads 'a', 'b' and 'c'".
std::string load_names(const std::vector<std::string>& names) {
  std::string text = names.size() == 1 ? "the load " : "the loads ";
  for (std::size_t k = 0; k < names.size(); ++k)
    text += (k == 0 ? "" : k + 1 == names.size() ? " and " : ", ") + ("'" + names[k] + "'");
  return text;
}

// A nonzero load that the load factor scales to 0 or to a subnormal double
// (increments = [[2, 1e-320]]): the step would apply no load, converge at
// once with 0 iterations, and the run end as a success with the plate at
// rest (before 7 December 2026). The rule is value_lost_at_factor's: a small
// factor that leaves the loads normal doubles passes. `previous`: the load
// factor of the step before (0 before the first): a step after one that
// applied the load removes it, the plate relaxing towards its unloaded state
// (before 7 December 2026 said as at the first step, "run unloaded"). Where
// other loads still act, the step runs without the lost ones, not unloaded,
// and the plate relaxes towards the others' state (before 7 December 2026
// said as if no load were left).
void refuse_lost_loads(const Scene& scene, const std::vector<ResolvedLoad>& loads, long step, double factor,
                       double previous) {
  std::vector<std::string> lost, acting;
  for (const auto& load : loads) {
    if (value_lost_at_factor(load, factor) != 0) lost.push_back(load.spec.name);
    else if (acts_at_factor(load, factor)) acting.push_back(load.spec.name);
  }
  for (const auto& load : loads) {
    const double value = value_lost_at_factor(load, factor);
    if (value == 0) continue;
    const double scaled = value * factor;
    const std::string still = acting.empty() ? std::string()
                                             : " while " + load_names(acting) + (acting.size() == 1 ? " still acts"
                                                                                                    : " still act");
    std::ostringstream m;
    m << scene.path << ": load step " << step << " (load factor " << shortest_text(factor) << "): the load '"
      << load.spec.name << "' has the value " << shortest_text(value) << ", which this load factor scales to "
      << (scaled == 0 ? std::string("0") : shortest_text(scaled) + ", below the smallest normal double (" +
                                               format_number(std::numeric_limits<double>::min()) + ")")
      << ": the arithmetic loses the load, and ";
    if (previous == 0)
      m << (acting.empty() ? std::string("the step would run unloaded")
                           : "the step would run without " + load_names(lost) + still);
    else if (acting.empty())
      m << "the load would be removed at load step " << step
        << ", the plate relaxing towards its unloaded state from load step " << step - 1 << "'s load factor "
        << shortest_text(previous);
    else
      m << (lost.size() == 1 ? "the load" : load_names(lost)) << " would be removed at load step " << step
        << " (from load step " << step - 1 << "'s load factor " << shortest_text(previous) << ")" << still;
    m << "; check the load values and key 'quasi_static." << scene.quasi_static.load_steps_key << "'";
    throw Error(m.str());
  }
}

double norm_of(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x * x;
  return std::sqrt(sum);
}

}  // namespace

void check_resumable(const Scene& scene, std::size_t particle_count, const LoadStepState& resume) {
  const auto& q = scene.quasi_static;
  const std::size_t n = particle_count;
  const auto& done = resume.load_factors_done;
  if (resume.u.size() != 2 * n || resume.damage_load_factor.size() != n ||
      (!resume.last_increment.empty() && resume.last_increment.size() != 2 * n))
    throw Error(scene.path + ": the saved load-step state does not fit this particle set");
  if (done.size() > q.load_factors.size())
    throw Error(scene.path + ": the checkpoint holds " + std::to_string(done.size()) +
                " load steps done, and quasi_static.load_factors / increments now lists " +
                std::to_string(q.load_factors.size()) + ": a restart may only extend the list");
  // The first step whose factor differs, both values (before 7 December
  // 2026 the message named neither).
  const auto differs = std::mismatch(done.begin(), done.end(), q.load_factors.begin());
  if (differs.first != done.end()) {
    const std::size_t k = static_cast<std::size_t>(differs.first - done.begin());
    throw Error(scene.path + ": the saved load steps (" + std::to_string(done.size()) +
                ") are not the first load factors of quasi_static.load_factors / increments: load step " +
                std::to_string(k + 1) + " was done at load factor " + shortest_text(*differs.first) +
                ", and the scene now gives " + shortest_text(*differs.second) +
                " (they may only be extended; run without --restart to start over)");
  }
}

QuasiStaticResult solve_quasi_static(QuasiStaticProblem& problem, const Scene& scene,
                                     const std::vector<std::uint32_t>& stop_region, std::ostream& log,
                                     const LoadStepObserver& observer, const LoadStepState* resume,
                                     const LoadStepStateObserver& state_observer, std::ostream* progress,
                                     std::ostream* warning_echo, const std::function<bool()>& stop_requested) {
  const auto& q = scene.quasi_static;
  const std::size_t n = problem.particle_count();
  QuasiStaticResult result;
  result.stop_reason = "last load step";
  LoadStepState state;
  state.u.assign(2 * n, 0.0);
  state.damage_load_factor.assign(n, -1.0);
  if (resume) {
    check_resumable(scene, n, *resume);
    state = *resume;
  }
  std::vector<double>& u = state.u;
  auto& damage_load_factor = state.damage_load_factor;
  const auto& free = problem.free_mask();
  std::vector<double> step_start_u;  // the last equilibrium, during a step
  double& largest_reaction_norm = state.largest_reaction_norm;  // of converged states, for the residual floor
  double& largest_axial_reaction = state.largest_axial_reaction;
  // With stop_requested: the last completed step's bond states, for a step
  // abandoned after bonds broke in it.
  std::vector<std::uint8_t> step_start_bond_states;

  for (std::size_t k = state.load_factors_done.size(); state.stop_reason.empty() && k < q.load_factors.size(); ++k) {
    const double factor = q.load_factors[k];
    // The last equilibrium kept (as the increment's other end, below) while
    // the predictor moves u to its guess at the new load.
    step_start_u = u;
    const double step_start_reaction_norm = largest_reaction_norm;
    if (stop_requested && scene.effects.damage) step_start_bond_states = problem.bond_states();
    refuse_lost_loads(scene, problem.loads(), static_cast<long>(k) + 1, factor,
                      state.load_factors_done.empty() ? 0.0 : state.load_factors_done.back());
    predict_load_step(u, free, state.last_increment, state.load_factors_done, factor);
    problem.set_load_factor(factor, u);

    LoadStepRecord record;
    record.step = static_cast<long>(k) + 1;
    record.load_factor = factor;
    NcgSettings settings;
    settings.tolerance = q.tolerance;
    settings.max_iterations = q.max_iterations;
    // A minimisation whose least residual has not fallen for 100 iterations,
    // and for as many as it took to reach it, has stalled (ncg.hpp): a
    // tolerance the plate's round-off does not let it reach (before 7 December
    // 2026 each such minimisation ran to max_iterations, the message then
    // advising more).
    settings.stall_iterations = 100;
    settings.abandon = stop_requested;
    using Clock = std::chrono::steady_clock;
    const auto step_start = Clock::now();
    auto last_line = step_start;
    if (progress) {
      // A line at least every progress_interval seconds inside a long minimisation.
      settings.progress_interval = q.progress_interval;
      settings.progress = [&](const NcgProgress& p) {
        *progress << "load step " << record.step << " (load factor " << shortest_text(factor) << "), minimisation "
                  << record.minimisations + 1 << ": iteration " << p.iteration << ", relative residual "
                  << p.relative_residual << ", " << p.seconds << " s\n"
                  << std::flush;
      };
    }
    // The load cell's largest reading at this step's equilibria, and whether
    // one of them already showed the sample separated.
    double step_peak = largest_axial_reaction;
    bool separated_at_re_equilibration = false;
    // Forces at this step's start that are no numbers are refused here, not
    // after a minimisation has spent its iterations on them (before 7
    // December 2026; with the lattice kernels, dozens of rounds). In double,
    // as the minimisation judges them. (A sweep that least_sweeps_per_load_step counts.)
    std::vector<double> start_residual;
    if (problem.lattice_kernels()) problem.set_double_residual(true);
    problem.residual(u, start_residual);
    problem.set_double_residual(false);
    if (!std::isfinite(norm_of(start_residual)) || !std::isfinite(problem.reaction_norm()))
      refuse_non_finite_forces(scene, record.step, factor, 0);
    if (norm_of(start_residual) == 0 &&
        std::any_of(start_residual.begin(), start_residual.end(), [](double f) { return f != 0; }))
      refuse_underflowing_forces(scene, record.step, factor);
    // The floor of the residual's scale (theory.md Sec. 4.10): 1e-3 of the
    // largest |F| of the converged states; before the first, of the
    // out-of-balance forces at this step's start, so that a plate the
    // pre-cracks cut apart, whose solution carries nothing, can converge.
    double scale = largest_reaction_norm;
    if (!(scale > 0)) {
      if (problem.lattice_kernels()) problem.residual(u, start_residual);  // (the float forces, as ever)
      scale = norm_of(start_residual);
    }
    bool abandoned = false;  // on request (stop_requested), within the step
    for (;;) {
      settings.force_floor = 1e-3 * scale;
      DampingSettings damping;
      damping.enabled = q.damped_rounds;
      MixedPrecisionResult mixed;
      try {
        mixed = minimise_in_mixed_precision(problem, u, settings, 1e-2, damping);
      } catch (const MinimisationAbandoned&) {
        abandoned = true;
        break;
      }
      const NcgResult& r = mixed.ncg;
      ++record.minimisations;
      if (progress && (mixed.damped_rounds > 0 || mixed.exact_iterations > 0 || mixed.stagnated_rounds > 0))
        *progress << "load step " << record.step << " (load factor " << shortest_text(factor) << "), minimisation "
                  << record.minimisations << ": " << mixed.rejected_rounds << " rounds dropped, "
                  << mixed.stagnated_rounds << " stalled, "
                  << mixed.damped_rounds << " damped rounds (largest mu " << mixed.largest_damping << "), "
                  << mixed.exact_iterations << " central-difference NCG iterations\n"
                  << std::flush;
      record.iterations += r.iterations;
      record.relative_residual = r.relative_residual();
      // (Forces finite at the start that a minimisation made no numbers.)
      if (!std::isfinite(record.relative_residual))
        refuse_non_finite_forces(scene, record.step, factor, record.minimisations);
      if (!r.converged) {
        record.converged = false;
        std::ostringstream m;
        m << scene.path << ": load step " << record.step << " (load factor " << shortest_text(factor)
          << "), minimisation " << record.minimisations << ": not converged after " << r.iterations
          << " iterations; relative residual " << r.relative_residual() << " > quasi_static.tolerance = "
          << q.tolerance;
        // What would help: more iterations only if they ran out.
        if (r.stalled)
          m << ": the minimiser has stalled: the relative residual has gone no lower than "
            << r.least_relative_residual << " in its last " << r.stalled_iterations
            << " iterations (the round-off of this plate's forces; more iterations cannot help); raise "
               "quasi_static.tolerance = "
            << q.tolerance << " above the residual reached, e.g. to " << tolerance_above(r.least_relative_residual);
        else if (r.no_descent)
          m << ": no direction of descent with positive curvature was left (more iterations cannot help: a "
               "smaller load increment, or a tolerance the state can reach)";
        else
          m << " (raise quasi_static.max_iterations = " << q.max_iterations << ")";
        // Displacements beyond the plate's size at this load factor (the
        // plan warned of them): what ends the minimisation is the load, not
        // its settings (before 7 December 2026 the message named no cause).
        for (const auto& load : problem.loads()) {
          const double largest = largest_load_value(load) * std::fabs(factor);
          if (!beyond_plate(load, largest)) continue;
          m << "; at this load factor the displacement load '" << load.spec.name << "' prescribes up to " << largest
            << " m, " << largest / load.plate_size << " times the plate's size (" << load.plate_size
            << " m), a strain far past any solid's failure that the minimiser cannot resolve: check its values "
               "(in m) and key 'quasi_static."
            << q.load_steps_key << "'";
          break;
        }
        if (!q.warn_on_nonconvergence)
          m << "; or set quasi_static.on_nonconvergence = \"warn\" to go on with the residual reached";
        if (!q.warn_on_nonconvergence) throw Error(m.str());
        log << "warning: " << m.str() << std::endl;
        result.warnings.push_back(m.str());
        if (warning_echo) *warning_echo << "pd-solve: warning: " << m.str() << std::endl;
      } else {
        largest_reaction_norm = std::max(largest_reaction_norm, problem.reaction_norm());
      }
      if (!scene.effects.damage) break;
      if (q.stop_reaction_fraction > 0 && r.converged) {
        // An equilibrium after bonds broke in this step whose reaction is
        // below stop_reaction_fraction of the peak: the sample has separated
        // (theory.md Sec. 4.11, step 3). The bonds still over s0 are in
        // pieces that carry no load; breaking them one re-equilibration at a
        // time would cost the most iterations of the run (pieces held by a
        // few bonds) and change nothing the stop reports. A reading that
        // fell with the load factor alone (unloading) is no separation.
        const double axial_now = axial_reaction(problem.reactions(), problem.loads());
        step_peak = std::max(step_peak, axial_now);
        if (record.pairs_broken > 0 && axial_now < q.stop_reaction_fraction * step_peak) {
          separated_at_re_equilibration = true;
          break;
        }
      }
      const std::size_t broken = problem.break_overstretched_bonds(u);
      record.pairs_broken += broken;
      if (broken == 0) break;
      if (stop_requested && stop_requested()) {
        abandoned = true;
        break;
      }
      if (progress && std::chrono::duration<double>(Clock::now() - last_line).count() >= q.progress_interval) {
        last_line = Clock::now();
        *progress << "load step " << record.step << " (load factor " << shortest_text(factor) << "): "
                  << record.minimisations << (record.minimisations == 1 ? " minimisation, " : " minimisations, ")
                  << record.iterations << (record.iterations == 1 ? " iteration, " : " iterations, ")
                  << record.pairs_broken << " pairs broken so far, "
                  << std::chrono::duration<double>(last_line - step_start).count() << " s\n"
                  << std::flush;
      }
      if (record.minimisations > q.max_breaking_rounds) {
        std::ostringstream m;
        m << scene.path << ": load step " << record.step << " (load factor " << shortest_text(factor)
          << "): bonds still break after "
          << q.max_breaking_rounds << " re-equilibrations (quasi_static.max_breaking_rounds)";
        throw Error(m.str());
      }
    }
    if (abandoned) {
      // Abandoned within the step: what a restart goes on from is the last
      // completed step (its u, residual floor and bond states).
      u = step_start_u;
      largest_reaction_norm = step_start_reaction_norm;
      InterruptedLoadSteps stop;
      stop.step = record.step;
      stop.abandoned = true;
      stop.state = state;
      stop.bond_states = scene.effects.damage ? step_start_bond_states : problem.bond_states();
      result.interrupted = std::move(stop);
      break;
    }
    // The residual call of the last minimisation left the reactions of this state.
    record.reactions = problem.reactions();
    // (Two sweeps that least_sweeps_per_load_step counts.)
    record.strain_energy = problem.strain_energy(u);
    record.potential_energy = problem.energy(u);
    record.broken_bonds = problem.broken_bond_count();
    const auto damage = problem.damage();
    for (std::size_t i = 0; i < n; ++i) {
      record.max_damage = std::max(record.max_damage, damage[i]);
      if (damage[i] > 0 && damage_load_factor[i] < 0) damage_load_factor[i] = factor;
    }
    result.steps.push_back(record);
    if (observer) observer(problem, u, record);
    state.load_factors_done.push_back(factor);
    // The predictor's increment for the next step: only from a step that broke
    // no bond (load_step_predictor.hpp).
    if (record.pairs_broken == 0) {
      state.last_increment.resize(u.size());
      for (std::size_t c = 0; c < u.size(); ++c) state.last_increment[c] = u[c] - step_start_u[c];
    } else {
      state.last_increment.clear();
    }
    const double axial = axial_reaction(record, problem.loads());
    largest_axial_reaction = std::max(largest_axial_reaction, axial);

    if (!stop_region.empty()) {
      const RegionPeak peak = most_damaged(stop_region, damage, problem.reference_x(), problem.reference_y());
      if (peak.damage >= scene.stop.damage) state.stop_reason = stop_condition_reason(scene.stop, peak);
    }
    // (Separation needs bonds broken in the step: see above. Here also after
    // a last minimisation that did not converge, under on_nonconvergence = "warn".)
    if (state.stop_reason.empty() && q.stop_reaction_fraction > 0 && record.pairs_broken > 0 &&
        (axial < q.stop_reaction_fraction * largest_axial_reaction || separated_at_re_equilibration)) {
      std::ostringstream m;
      m << "separated: reaction " << axial << " N < " << q.stop_reaction_fraction << " x its peak "
        << std::max(largest_axial_reaction, step_peak) << " N";
      if (separated_at_re_equilibration)
        m << " after re-equilibration " << record.minimisations << " (bonds over s0 left unbroken)";
      state.stop_reason = m.str();
    }
    if (state_observer) state_observer(state);
    // Asked also after the last step or a stop: a switching scene's dynamic part is still to come.
    if (stop_requested && stop_requested()) {
      result.interrupted = InterruptedLoadSteps{record.step, false, state, problem.bond_states()};
      break;
    }
    if (!state.stop_reason.empty()) break;
  }
  if (!state.stop_reason.empty()) result.stop_reason = state.stop_reason;
  else if (result.interrupted && state.load_factors_done.size() < q.load_factors.size()) result.stop_reason = "interrupted";
  result.damage = problem.damage();
  result.damage_load_factor = std::move(damage_load_factor);
  result.u = std::move(u);
  return result;
}

}  // namespace pd::solver
