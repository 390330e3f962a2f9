#include "state_surface_correction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include "error.hpp"
#include "harmonic_moments.hpp"

namespace pd::solver {

namespace {

using moments::all_harmonics;
using moments::HarmonicSet;
using moments::K;
using moments::Matrix;

// The harmonics a listed particle's factors may carry, in the order tried.
constexpr HarmonicSet distortion_sets[] = {all_harmonics, 0x19 /* 1, cos 4t, sin 4t */, 0x01 /* 1 */};
constexpr HarmonicSet dilatation_sets[] = {0x06 /* cos 2t, sin 2t */, 0x00};

// Damping of the block Jacobi update of the dilatation factors. A particle's
// own factor carries half of each of its bonds' factors, its neighbours the
// other half, so the undamped update overshoots by about the residual; with
// 1/2 it is the fixed point lambda_i <- lambda_i T0 / W_i of Sec. 3 in the
// scalar case.
constexpr double damping = 0.5;
constexpr int max_iterations = 10000;

// Smallest dilatation factor D_ij accepted: non-negative weights, so that no
// bond's stretch counts against the dilatation. A corner's quarter-disk
// family cannot meet its equations so (cos 2t, sin 2t moments of a quarter
// disk need D < 0 along the diagonal), and drops its factor.
constexpr double lowest_dilatation_factor = 0.0;

// One bond as the solver of the moment equations reads it.
struct Bond {
  std::uint32_t neighbor;  // the neighbour's number in the MomentProblem when between_listed (else 0)
  bool between_listed;  // both ends listed: directional factors
  double energy_weight, volume;  // E_ij [m^3] (with kappa), V_ij = phi_ij A_j [m^2]
  Harmonics h;          // h(n_ij)
};

// The bonds of the particles with listed families, precomputed (a stencil
// particle has a scalar factor only: its family is whole). They are numbered
// 0 .. size() - 1 here, and the factors are kept for them alone: on a fine
// grid they are a few per cent of the particles.
class MomentProblem {
public:
  // `listed`: per particle, whether its family is a list (null: those not
  // on a stencil). On a process's local particles a ghost has no family and
  // is on no stencil locally: its set-up's rows say whether it is listed.
  MomentProblem(const ParticleSet& p, const Families& families, const PerBond<double>& weight,
                const std::vector<std::uint8_t>& listed_intact, const std::vector<std::uint8_t>* listed = nullptr)
      : particle_count_(families.particle_count) {
    const std::size_t n = families.particle_count;
    const auto is_listed = [&](std::uint32_t i) { return listed ? (*listed)[i] != 0 : !families.on_stencil[i]; };
    std::vector<std::uint32_t> number(n, 0);
    for (std::uint32_t i = 0; i < n; ++i)
      if (is_listed(i)) number[i] = static_cast<std::uint32_t>(particle_.size()), particle_.push_back(i);
    const std::size_t count = particle_.size();
    first_.assign(count + 1, 0);
    for (std::size_t l = 0; l < count; ++l) first_[l + 1] = first_[l] + families.family_size(particle_[l]);
    bonds_.resize(first_[count]);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t s = 0; s < static_cast<std::int64_t>(count); ++s) {
      const auto i = particle_[static_cast<std::size_t>(s)];
      auto out = first_[static_cast<std::size_t>(s)];
      families.for_each_bond(i, [&](const BondRef& b) {
        const auto j = b.neighbor;
        const bool intact = listed_intact[b.index] != 0;
        const bool between_listed = is_listed(j);
        bonds_[out++] = Bond{between_listed ? number[j] : 0u, between_listed, intact ? weight(b) : 0.0,
                             intact ? b.partial_volume * p.volume[j] : 0.0,
                             bond_harmonics(p.x[j] - p.x[i], p.y[j] - p.y[i])};
      });
    }
  }

  std::size_t size() const { return particle_.size(); }  // particles with listed families
  std::size_t particle_count() const { return particle_count_; }  // of the particle set
  std::uint32_t particle(std::size_t l) const { return particle_[l]; }  // the particle of number l
  bool listed(std::size_t l) const { return first_[l + 1] > first_[l]; }  // (a family of no bond is not)

  // f(const Bond&) for each bond of listed particle number l.
  template <class F>
  void for_each_bond(std::size_t l, F&& f) const {
    for (auto b = first_[l]; b < first_[l + 1]; ++b) f(bonds_[b]);
  }

  // Whether the bonds of listed particle number i to listed particles can carry the
  // harmonics of `set` independently (weights: E for the distortion, V for
  // the dilatation): the test of surface_correction.cpp's directional shapes.
  bool spans(std::size_t i, HarmonicSet set, bool distortion) const {
    Matrix gram{};
    for_each_bond(i, [&](const Bond& b) {
      if (b.between_listed) moments::add_outer(gram, distortion ? b.energy_weight : b.volume, b.h);
    });
    return moments::cholesky(gram, set);
  }

private:
  std::size_t particle_count_ = 0;
  std::vector<std::uint32_t> particle_;
  std::vector<std::uint64_t> first_;
  std::vector<Bond> bonds_;
};

// G_i(n) on a bond: c_i . h between listed particles, else c_i0.
double distortion_end(const Harmonics& c, const Bond& b) { return b.between_listed ? harmonic_sum(c, b.h) : c[0]; }

// The distortion factor c_i of listed particle number i on the harmonics `set`, from
// its own family: sum_j G_i(n_ij) E_ij h(n_ij) = T (the full disk's moments)
// on the rows of `set`. False if singular or if G_i falls below lowest_shape
// at one of its bonds.
bool own_distortion_factor(const MomentProblem& problem, std::size_t i, HarmonicSet set, double horizon,
                           Harmonics& c) {
  const Harmonics unit{1, 0, 0, 0, 0};
  Matrix a{};
  problem.for_each_bond(i, [&](const Bond& b) { moments::add_outer(a, b.energy_weight, b.h, b.between_listed ? b.h : unit); });
  if (!moments::solve(a, moments::full_disk(horizon), set, c)) return false;
  bool acceptable = c[0] > 0;
  problem.for_each_bond(i, [&](const Bond& b) {
    if (b.energy_weight > 0 && distortion_end(c, b) < lowest_shape) acceptable = false;
  });
  return acceptable;
}

// D_ij - 1 on a bond: (d_i + d_j) . h / 2 between listed particles, else 0.
double dilatation_excess(const Harmonics& di, const Harmonics& dj, const Bond& b) {
  return b.between_listed ? 0.5 * (harmonic_sum(di, b.h) + harmonic_sum(dj, b.h)) : 0.0;
}

// With `exchange` (a process's local particles): every ghost takes its
// owner's factor, one component of dilatation_sets[0] at a time (the others
// stay 0), as one value per local particle.
void update_ghost_factors(const MomentProblem& problem, std::vector<Harmonics>& factor,
                          const ScalarFactorExchange* exchange) {
  if (!exchange) return;
  std::vector<double> values(problem.particle_count(), 0.0);
  for (std::size_t k = 0; k < K; ++k) {
    if (!((dilatation_sets[0] >> k) & 1)) continue;
    for (std::size_t l = 0; l < problem.size(); ++l) values[problem.particle(l)] = factor[l][k];
    exchange->update_ghosts(values);
    for (std::size_t l = 0; l < problem.size(); ++l) factor[l][k] = values[problem.particle(l)];
  }
}

// Solves the dilatation equations of every listed particle together, for
// the factors d with the harmonics `set` (per listed particle), by damped block
// Jacobi: sum_j D_ij V_ij (cos 2t, sin 2t) = 0. With `exchange` on a
// process's local particles (a ghost's set is empty: its owner updates it)
// the iteration is iterate_scalar_factors' on the slabs: after each sweep
// the ghosts take their owners' factors and the largest change is the
// processes', so every process stops at the same iteration.
int solve_dilatation(const MomentProblem& problem, const std::vector<HarmonicSet>& set, double tolerance,
                     std::vector<Harmonics>& factor, const ScalarFactorExchange* exchange) {
  const std::size_t n = problem.size();
  std::vector<Harmonics> next(factor);
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    double largest_change = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : largest_change)
    for (std::int64_t s = 0; s < static_cast<std::int64_t>(n); ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (set[i] == 0) continue;
      Harmonics residual{};
      Matrix jacobian{};  // d(moments of i) / d(d_i)
      problem.for_each_bond(i, [&](const Bond& b) {
        const double d = 1.0 + dilatation_excess(factor[i], factor[b.neighbor], b);
        for (std::size_t k = 1; k < 3; ++k) residual[k] -= d * b.volume * b.h[k];
        if (b.between_listed) moments::add_outer(jacobian, 0.5 * b.volume, b.h);
      });
      Harmonics step;
      if (!moments::solve(jacobian, residual, set[i], step)) continue;  // every bond cut: nothing to correct
      for (std::size_t k = 0; k < K; ++k) {
        next[i][k] = factor[i][k] + damping * step[k];
        largest_change = std::max(largest_change, damping * std::fabs(step[k]));
      }
    }
    factor.swap(next);
    if (exchange) {
      update_ghost_factors(problem, factor, exchange);
      largest_change = exchange->largest(largest_change);
    }
    if (largest_change < tolerance) return iteration;
    next = factor;
  }
  std::ostringstream m;
  m << "surface correction (state-based): the dilatation factors did not converge to " << tolerance << " in "
    << max_iterations << " iterations";
  throw Error(m.str());
}

// The listed particles whose D_ij falls below lowest_dilatation_factor at one of their
// bonds lose their dilatation factor; true if any did.
bool drop_low_dilatation_factors(const MomentProblem& problem, const std::vector<Harmonics>& factor,
                                 std::vector<HarmonicSet>& set) {
  const std::size_t n = problem.size();
  std::vector<std::uint8_t> low(n, 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(n); ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (set[i] == 0) continue;
    problem.for_each_bond(i, [&](const Bond& b) {
      if (1.0 + dilatation_excess(factor[i], factor[b.neighbor], b) < lowest_dilatation_factor) low[i] = 1;
    });
  }
  bool dropped = false;
  for (std::size_t i = 0; i < n; ++i)
    if (low[i]) set[i] = 0, dropped = true;
  return dropped;
}

// The dilatation factors, all together, from `factor` (0 at first);
// particles with low factors drop theirs and the rest are solved again.
// Returns the iterations of all rounds.
int solve_dilatation_rounds(const MomentProblem& problem, std::vector<HarmonicSet>& set, double tolerance,
                            std::vector<Harmonics>& factor, const ScalarFactorExchange* exchange) {
  int iterations = 0;
  for (int round = 0; round < 4; ++round) {
    iterations += solve_dilatation(problem, set, tolerance, factor, exchange);
    bool dropped = drop_low_dilatation_factors(problem, factor, set);
    if (exchange) dropped = exchange->largest(dropped ? 1.0 : 0.0) > 0;  // on any process
    if (!dropped) break;
    for (std::size_t i = 0; i < problem.size(); ++i)
      if (set[i] == 0) factor[i] = Harmonics{};
    update_ghost_factors(problem, factor, exchange);  // (a ghost's set is empty: its owner's factor back)
  }
  return iterations;
}

// The harmonics of listed particle number i's dilatation factor: those its
// bonds to listed particles span.
HarmonicSet dilatation_set_of(const MomentProblem& problem, std::size_t i) {
  return problem.spans(i, dilatation_sets[0], false) ? dilatation_sets[0] : HarmonicSet{0};
}

}  // namespace

int iterate_dilatation_factors(const ParticleSet& p, const Families& families, const PerBond<double>& weight,
                               const std::vector<std::uint8_t>& listed_intact, double tolerance,
                               DirectionalShapes& dilatation, const ScalarFactorExchange* exchange) {
  const std::size_t n = families.particle_count;
  std::vector<std::uint8_t> listed(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) listed[i] = dilatation.has(i) ? 1 : 0;
  const MomentProblem problem(p, families, weight, listed_intact, &listed);
  const std::size_t count = problem.size();
  std::vector<HarmonicSet> set(count, 0);
  std::vector<Harmonics> factor(count);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(count); ++s) {
    const auto l = static_cast<std::size_t>(s);
    if (problem.listed(l)) set[l] = dilatation_set_of(problem, l);
  }
  for (std::size_t l = 0; l < count; ++l) factor[l] = dilatation.coefficients[dilatation.row[problem.particle(l)]];
  const int iterations = solve_dilatation_rounds(problem, set, tolerance, factor, exchange);
  for (std::size_t l = 0; l < count; ++l) dilatation.coefficients[dilatation.row[problem.particle(l)]] = factor[l];
  return iterations;
}

SurfaceCorrectionResult compute_state_surface_correction(const ParticleSet& p, const Families& families,
                                                         const PerBond<double>& weight,
                                                         const std::vector<std::uint8_t>& listed_intact,
                                                         double horizon, double tolerance,
                                                         bool dilatation_factors) {
  SurfaceCorrectionResult result;
  const MomentProblem problem(p, families, weight, listed_intact);
  const std::size_t n = families.particle_count, listed = problem.size();
  // The distortion factors, particle by particle (listed ones, by their
  // number in `problem`): the richest set of harmonics whose factor is acceptable.
  std::vector<Harmonics> distortion(listed, Harmonics{1, 0, 0, 0, 0});
  std::vector<std::uint8_t> distortion_reduced(listed, 0);
  // The dilatation factors' harmonics: those the listed bonds span.
  std::vector<HarmonicSet> dilatation_set(listed, 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(listed); ++s) {
    const auto i = static_cast<std::size_t>(s);
    if (!problem.listed(i)) continue;
    bool found = false;
    for (const HarmonicSet set : distortion_sets) {
      Harmonics c;
      if (problem.spans(i, set, true) && own_distortion_factor(problem, i, set, horizon, c)) {
        distortion[i] = c;
        distortion_reduced[i] = set != distortion_sets[0];
        found = true;
        break;
      }
    }
    if (!found) distortion_reduced[i] = 2;  // not even a scalar: reported below (no throw inside OpenMP)
    dilatation_set[i] = dilatation_set_of(problem, i);
  }
  for (std::size_t i = 0; i < listed; ++i)
    if (distortion_reduced[i] == 2)
      throw Error("surface correction (state-based): particle " + std::to_string(problem.particle(i)) +
                  " has no positive distortion factor (its family has too few intact bonds)");
  std::vector<Harmonics> dilatation(listed, Harmonics{});
  if (dilatation_factors) result.iterations = solve_dilatation_rounds(problem, dilatation_set, tolerance, dilatation, nullptr);
  SurfaceCorrection& c = result.correction;
  c.lambda.assign(n, 1.0);
  // A stencil particle's scalar factor: its family's zeroth moment (1 to
  // round-off on the level whose stencil set kappa).
  const double full_disk = moments::full_disk(horizon)[0];
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < static_cast<std::int64_t>(n); ++s) {
    const auto i = static_cast<std::uint32_t>(s);
    if (!families.on_stencil[i]) continue;
    double sum = 0;
    families.for_each_bond(i, [&](const BondRef& b) { sum += weight(b); });
    if (sum > 0) c.lambda[i] = full_disk / sum;
  }
  c.shapes.row.assign(n, DirectionalShapes::none);
  c.dilatation.row.assign(n, DirectionalShapes::none);
  for (std::size_t l = 0; l < listed; ++l) {
    if (!problem.listed(l)) continue;
    const auto i = problem.particle(l);
    if (distortion_reduced[l]) ++result.fallbacks;
    if (dilatation_set[l] == 0) ++result.fallbacks;
    c.lambda[i] = distortion[l][0];
    Harmonics d = distortion[l];
    for (std::size_t k = 1; k < K; ++k) d[k] /= c.lambda[i];
    d[0] = 0;
    c.shapes.row[i] = static_cast<std::uint32_t>(c.shapes.coefficients.size());
    c.shapes.coefficients.push_back(d);
    c.dilatation.row[i] = static_cast<std::uint32_t>(c.dilatation.coefficients.size());
    c.dilatation.coefficients.push_back(dilatation[l]);
  }
  return result;
}

}  // namespace pd::solver
