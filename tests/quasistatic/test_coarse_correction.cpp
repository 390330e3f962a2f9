// The coarse-space correction of the lattice path's preconditioner (theory.md
// Sec. 4.13, solver/statics/coarse_correction.*).
#include <catch2/catch.hpp>
#include <cmath>

#include "linear_cg.hpp"
#include "quasi_static_problem.hpp"
#include "support.hpp"

using namespace pd::solver;
using namespace pd::quasistatic::test;

namespace {

// The lattice scene of `scene` with the coarse correction (first) and without it.
std::pair<Scene, Scene> with_and_without_correction(const Scene& scene) {
  auto with = lattice_scene(scene);
  auto without = with;
  without.quasi_static.coarse_correction = false;
  return {with, without};
}

// The C1 plate held on its left edge and pulled on its right.
Scene pulled_plate() {
  auto scene = quasi_static_scene();
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  return scene;
}

// Linear CG to 1e-8 on H w = r at `state`, with the coarse correction and
// with the blocks alone; both must converge.
struct BothSolves {
  std::vector<double> w_coarse, w_blocks;
  long coarse_iterations = 0, blocks_iterations = 0;
};
BothSolves solve_both(const QuasiStaticProblem& coarse, const QuasiStaticProblem& blocks,
                      const std::vector<double>& state, const std::vector<double>& r) {
  NcgSettings settings;
  settings.tolerance = 1e-8;
  settings.max_iterations = 20000;
  BothSolves both;
  const auto a = solve_linear(coarse, state, r, both.w_coarse, settings);
  const auto b = solve_linear(blocks, state, r, both.w_blocks, settings);
  both.coarse_iterations = a.iterations;
  both.blocks_iterations = b.iterations;
  INFO("iterations: " << a.iterations << " with the coarse correction, " << b.iterations << " without");
  REQUIRE(a.converged);
  REQUIRE(b.converged);
  return both;
}

}  // namespace

// Reference: an identity of the coarse correction C = P A_c^-1 P^T itself.
// If A_c = P^T K0 P, then C K0 C = C (C is the K0-orthogonal projection onto
// the coarse motions, times K0^-1); a wrong or missing bond term in A_c, a
// wrong sign or scale, breaks it. K0: the problem's own small-strain
// product (the float sweep of tiny displacements, theory.md Sec. 4.12: an
// implementation independent of the bond-by-bond sum of A_c) on the C1
// plate with a hole (NB-NUG, the lattice kernels), its left edge held.
// C is the problem's preconditioner with the blocks' part taken out: M^-1 r
// minus the blocks' inverse. Tolerance 1e-5: the float products (1e-7
// relative per pair; measured 5e-7) and the shift of A_c by 1e-9 of its
// median diagonal.
TEST_CASE("the coarse correction is the projection A_c = P^T K0 P promises: C K0 C = C", "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  const std::size_t n = particles.size();
  const auto [with, without] = with_and_without_correction(pulled_plate());
  QuasiStaticProblem coarse(with, particles), blocks(without, particles);
  REQUIRE(coarse.coarse_unknown_count() > 3 * 9);
  coarse.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::small_strain);
  const std::vector<double> rest(2 * n, 0.0);
  // C r = M^-1 r - B^-1 r.
  const auto correction = [&](const std::vector<double>& r) {
    std::vector<double> full, local;
    coarse.precondition(r, full);
    blocks.precondition(r, local);
    for (std::size_t k = 0; k < full.size(); ++k) full[k] -= local[k];
    return full;
  };
  // r: a smooth load with noise, zero on the held components.
  std::vector<double> r = test_field(particles);
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = coarse.free_mask()[k] ? r[k] : 0.0;
  const std::vector<double> s = correction(r);
  std::vector<double> ks;
  coarse.hessian_times(rest, s, ks);
  const std::vector<double> t = correction(ks);
  double difference = 0, size = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    difference = std::max(difference, std::fabs(t[k] - s[k]));
    size = std::max(size, std::fabs(s[k]));
  }
  INFO("coarse unknowns " << coarse.coarse_unknown_count() << ", |C K0 C r - C r| / |C r| = " << difference / size);
  REQUIRE(size > 0);
  CHECK(difference < 1e-5 * size);
}

// Reference: the same linear CG without the correction (the 2 x 2 blocks
// alone, theory.md Sec. 4.12) on the same system, to the same tolerance. The
// C1 plate is 17 horizons (50 particles) long; a correction acting particle by
// particle needs of the order of that many iterations to carry the load from
// the pulled edge to the held one, the coarse space carries it in one. Both must reach the
// same solution; the coarse correction must need at most half the
// iterations (measured: see the INFO line; C2 at 0.2 mm needs 5 times fewer,
// docs/performance.md).
TEST_CASE("the coarse correction cuts the linear CG iterations on a plate with a hole, same solution",
          "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  const auto [with, without] = with_and_without_correction(pulled_plate());
  QuasiStaticProblem coarse(with, particles), blocks(without, particles);
  REQUIRE(coarse.coarse_unknown_count() > 0);
  REQUIRE(blocks.coarse_unknown_count() == 0);
  std::vector<double> u;
  coarse.set_load_factor(1.0, u);
  coarse.set_double_residual(true);
  blocks.set_double_residual(true);
  std::vector<double> r;
  coarse.residual(u, r);
  const auto [w_coarse, w_blocks, coarse_iterations, blocks_iterations] = solve_both(coarse, blocks, u, r);
  CHECK(2 * coarse_iterations <= blocks_iterations);
  double largest = 0, off = 0;
  for (std::size_t k = 0; k < w_blocks.size(); ++k) {
    largest = std::max(largest, std::fabs(w_blocks[k]));
    off = std::max(off, std::fabs(w_coarse[k] - w_blocks[k]));
  }
  CHECK(off < 1e-5 * largest);
}

// A fragment cut loose: every bond across x = 10 mm of the C1 plate broken,
// the left half held at its left edge, the right half free (its rigid
// motions have no energy, and it must take no part in the coarse space:
// the aggregates of squares the cut runs through split, and a body held by
// no support is left out). The load acts on the left half only, so the
// right half has no reason to move.
// Reference: the solution of the left half alone, i.e. the same CG without
// the correction; with it, CG must converge too, to the same left half, and
// leave the right half at rest to 1e-6 of the largest displacement.
TEST_CASE("the coarse correction leaves a fragment that cracks cut loose at rest", "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  const std::size_t n = particles.size();
  auto scene = quasi_static_scene(true);
  scene.loads = {fixed("left")};
  const auto [with, without] = with_and_without_correction(scene);
  QuasiStaticProblem coarse(with, particles), blocks(without, particles);
  const double cut = 10e-3;  // [m]
  std::vector<double> apart(2 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) apart[i] = particles.x[i] > cut ? 1e-2 : 0.0;
  REQUIRE(coarse.break_overstretched_bonds(apart) > 0);
  REQUIRE(blocks.break_overstretched_bonds(apart) == coarse.broken_bond_count() / 2);
  const std::vector<double> rest(2 * n, 0.0);
  std::vector<double> r = test_field(particles);
  for (std::size_t i = 0; i < n; ++i)
    if (particles.x[i] > cut || !coarse.free_mask()[i]) r[i] = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (particles.x[i] > cut || !coarse.free_mask()[n + i]) r[n + i] = 0;
  const auto [w_coarse, w_blocks, coarse_iterations, blocks_iterations] = solve_both(coarse, blocks, rest, r);
  double largest = 0, left_off = 0, right_moved = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k : {i, n + i}) {
      largest = std::max(largest, std::fabs(w_blocks[k]));
      if (particles.x[i] > cut) right_moved = std::max(right_moved, std::fabs(w_coarse[k]));
      else left_off = std::max(left_off, std::fabs(w_coarse[k] - w_blocks[k]));
    }
  CHECK(left_off < 1e-5 * largest);
  CHECK(right_moved < 1e-6 * largest);
}
