#include "mixed_precision.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "linear_cg.hpp"

namespace pd::solver {
namespace {

double norm(const std::vector<double>& v) { return std::sqrt(dot(v, v)); }

}  // namespace

MixedPrecisionResult minimise_in_mixed_precision(QuasiStaticProblem& problem, std::vector<double>& u,
                                                 const NcgSettings& settings, double inner_tolerance,
                                                 const DampingSettings& damping) {
  MixedPrecisionResult result;
  if (!problem.lattice_kernels()) {
    result.ncg = minimise_energy(problem, u, settings);
    return result;
  }
  using Hessian = QuasiStaticProblem::LatticeHessian;
  const Hessian chosen = problem.lattice_hessian();  // the rounds' matrix (tangent unless a caller chose K0)
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  problem.set_double_residual(true);
  std::vector<double> r, trial, r_trial, w;
  NcgResult& total = result.ncg;
  problem.residual(u, r);  // double; also the reactions of this state
  ++result.rounds;
  bool reactions_of_u = true;  // false after a rejected trial state's residual
  // Progress lines at most every progress_interval seconds over the whole
  // minimisation, however short its rounds (each CG round reports every
  // iteration to this throttle, not on a clock of its own).
  double last_line = 0;  // [s] since start
  const auto report = [&](const NcgProgress& p) {
    if (p.seconds - last_line < settings.progress_interval) return;
    last_line = p.seconds;
    settings.progress(p);
  };
  // The round to try next: the chosen matrix; after a dropped round K0; after
  // that damped tangent rounds (Levenberg-Marquardt, theory.md Sec. 4.14)
  // for the rest of the minimisation.
  enum class Round { tangent, small_strain, damped };
  const Round first = chosen == Hessian::small_strain ? Round::small_strain : Round::tangent;
  Round round = first;
  double mu = 0;
  double last_taken_mu = -1;  // the mu of the last damped round taken (-1: none yet)
  // mu / divisor, and 0 below the smallest damping (an undamped round).
  const auto lower = [&](double divisor) { return mu / divisor < damping.smallest ? 0.0 : mu / divisor; };
  double energy_of_u = 0;  // Pi(u), kept while the damped rounds need it
  bool energy_known = false;
  bool fall_back = false;
  // The stall rule (NcgSettings::stall_iterations): the iteration of the last
  // new least relative residual, or new least energy of a damped round (near
  // separation such rounds lower the energy while the residual may not fall).
  total.least_relative_residual = std::numeric_limits<double>::quiet_NaN();
  double least_energy = std::numeric_limits<double>::infinity();
  long progress_at = 0;
  for (;;) {
    total.residual_norm = norm(r);
    total.reference_norm = std::max(problem.reaction_norm(), settings.force_floor);
    if (std::isfinite(total.residual_norm) && std::isfinite(total.reference_norm) &&
        total.residual_norm <= settings.tolerance * total.reference_norm) {
      total.converged = true;
      break;
    }
    if (total.relative_residual() < total.least_relative_residual || std::isnan(total.least_relative_residual)) {
      total.least_relative_residual = total.relative_residual();
      progress_at = total.iterations;
    }
    total.stalled_iterations = total.iterations - progress_at;
    if (settings.stall_iterations > 0 &&
        total.stalled_iterations >= std::max(settings.stall_iterations, progress_at)) {
      total.stalled = true;
      break;
    }
    if (total.iterations >= settings.max_iterations) break;
    // The correction w with H w = r, H the tangent at u (or K0; + mu B in a
    // damped round), by linear CG to inner_tolerance of |r| (no further than
    // the outer tolerance needs).
    problem.set_lattice_hessian(round == Round::small_strain ? Hessian::small_strain : Hessian::tangent);
    problem.set_lattice_damping(round == Round::damped ? mu : 0.0);
    NcgSettings inner = settings;
    inner.tolerance = std::max(inner_tolerance, settings.tolerance * total.reference_norm / total.residual_norm);
    inner.max_iterations = settings.max_iterations - total.iterations;
    if (settings.progress) {
      // Progress in the outer terms: iterations so far, and the residual the
      // correction has reached, as a fraction of the reference.
      const double scale = total.residual_norm / total.reference_norm;
      const long done = total.iterations;
      inner.progress_interval = 0;  // every iteration to `report`, which keeps the interval
      inner.progress = [&, scale, done](const NcgProgress& p) {
        report({done + p.iteration, p.relative_residual * scale, seconds()});
      };
      if (total.iterations > 0)  // between rounds
        report({total.iterations, total.residual_norm / total.reference_norm, seconds()});
    }
    const LinearSolveResult step = solve_linear(problem, u, r, w, inner);
    total.iterations += step.iterations;
    if (round == Round::damped) {
      ++result.damped_rounds;
      result.largest_damping = std::max(result.largest_damping, mu);
    }
    const bool indefinite = step.negative_curvature || step.diverged;
    if (indefinite) ++result.negative_curvature_stops;
    if (step.stagnated) ++result.stagnated_rounds;
    bool accepted = false;
    bool cut_residual = false;
    if (!(round == Round::damped && indefinite)) {  // a damped round that met negative curvature: more damping
      trial = u;
      for (std::size_t k = 0; k < u.size(); ++k) trial[k] += w[k];
      problem.residual(trial, r_trial);
      ++result.rounds;
      cut_residual = norm(r_trial) < 0.9 * norm(r);  // a round must cut the residual by 10 %
      accepted = cut_residual;
      if (!accepted && round == Round::damped) {
        // Or lower the energy enough (Armijo's condition, c = 1e-4, along w,
        // whose slope is -r.w): far from equilibrium a short damped step
        // descends while the residual of the pieces it moves can grow.
        const double slope = dot(r, w);
        if (!energy_known) energy_of_u = problem.energy(u);
        energy_known = true;
        const double energy_of_trial = problem.energy(trial);
        if (slope > 0 && energy_of_trial <= energy_of_u - 1e-4 * slope) {
          accepted = true;
          energy_of_u = energy_of_trial;
          if (energy_of_trial < least_energy) {
            least_energy = energy_of_trial;
            progress_at = total.iterations;
          }
        }
      } else {
        energy_known = false;
      }
    }
    if (accepted) {
      u.swap(trial);
      r.swap(r_trial);
      reactions_of_u = true;
      if (round == Round::damped) {
        // A round the model predicted well (the residual fell): less damping,
        // down to none (a piece held by a few bonds has modes far softer than
        // the blocks: any fixed mu would slow their convergence to mu / lambda
        // per round). A round taken on the energy alone: a little less, so
        // that mu settles just above what keeps H + mu B positive definite
        // instead of staying a factor 10 above it (theory.md Sec. 4.14).
        last_taken_mu = mu;
        mu = lower(cut_residual ? damping.factor : damping.fine_factor);
      } else {
        round = first;
      }
      continue;
    }
    if (!indefinite || round != Round::damped) reactions_of_u = false;
    ++result.rejected_rounds;
    if (round == Round::tangent) {
      // The tangent's correction overshot (a nearly singular or indefinite
      // tangent after bonds broke): one round with K0, which is positive
      // definite wherever the bonds hold the state at rest.
      round = Round::small_strain;
      continue;
    }
    if (round == Round::small_strain) {
      // K0 misses what holds the state too (a particle left with bonds in one
      // direction only, held sideways by the geometric stiffness alone; pieces
      // hanging by a few bonds): damped tangent rounds from here on.
      round = Round::damped;
      mu = damping.first;
      last_taken_mu = -1;
    } else if (last_taken_mu > mu) {
      mu = last_taken_mu;  // back to the damping that was last taken
    } else {
      mu = mu > 0 ? mu * damping.fine_factor : damping.smallest;
    }
    if (!damping.enabled || mu > damping.largest) {
      fall_back = true;
      break;
    }
  }
  if (fall_back) {
    // Damping up to its largest value found no acceptable step: NCG on the
    // double residual with central-difference Hessian products for the rest
    // of this minimisation (the last resort: slow, but as robust as the
    // energy table's path).
    problem.set_lattice_damping(0.0);
    problem.set_lattice_hessian(Hessian::central_difference);
    NcgSettings rest = settings;
    rest.max_iterations = settings.max_iterations - total.iterations;
    const long done = total.iterations;
    if (settings.progress)
      rest.progress = [&, done](const NcgProgress& p) {
        settings.progress({done + p.iteration, p.relative_residual, seconds()});
      };
    const NcgResult exact = minimise_energy(problem, u, rest);
    total.converged = exact.converged;
    total.no_descent = exact.no_descent;
    total.stalled = exact.stalled;
    total.least_relative_residual = std::min(total.least_relative_residual, exact.least_relative_residual);
    total.stalled_iterations = exact.stalled_iterations;
    total.residual_norm = exact.residual_norm;
    total.reference_norm = exact.reference_norm;
    total.iterations += exact.iterations;
    result.exact_iterations = exact.iterations;
    reactions_of_u = true;  // minimise_energy's last residual is at its final u
  }
  if (!reactions_of_u) problem.residual(u, r);  // the reactions of the state kept
  problem.set_lattice_damping(0.0);
  problem.set_lattice_hessian(chosen);
  problem.set_double_residual(false);
  return result;
}

}  // namespace pd::solver
