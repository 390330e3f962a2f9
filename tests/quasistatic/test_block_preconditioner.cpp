// The lattice path's preconditioner (theory.md Sec. 4.12): per particle the
// 2 x 2 block h A_i sum_j k_ij n n^T of the bonds that hold, plus 1 % of its
// trace on the diagonal.
#include <catch2/catch.hpp>
#include <cmath>

#include "quasi_static_problem.hpp"
#include "support.hpp"

using namespace pd::solver;
using namespace pd::quasistatic::test;

namespace {

// Groups of particles more than two horizons apart (greedy): probing all of
// a group at once, each probed particle's own entries of H d are its diagonal
// block alone, since no other probed particle is its neighbour (families
// reach a little beyond the horizon: partial volumes of the cells it cuts).
std::vector<std::vector<std::size_t>> far_apart_groups(const pd::ParticleSet& p, double horizon) {
  std::vector<std::vector<std::size_t>> groups;
  std::vector<bool> done(p.size(), false);
  for (std::size_t left = p.size(); left > 0;) {
    std::vector<std::size_t> group;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (done[i]) continue;
      bool far = true;
      for (auto j : group) far = far && std::hypot(p.x[i] - p.x[j], p.y[i] - p.y[j]) > 2 * horizon;
      if (!far) continue;
      group.push_back(i);
      done[i] = true;
      --left;
    }
    groups.push_back(std::move(group));
  }
  return groups;
}

}  // namespace

// Reference: the tangent Hessian product at rest (the lattice sweep of
// Model::force_change, lattice_tangent.hpp: an implementation of its own),
// which at u = 0 is the small-strain stiffness K0 exactly (e = 0: no geometric
// term, reference directions). Probing particle i along x and y gives its
// diagonal block of K0; the preconditioner must be that block plus 1 % of its
// trace on the diagonal, so that M^-1 (K0_ii + 0.01 tr I) e = e. Tolerance
// 1e-5: the sweep's float products (1e-7 relative per pair, summed).
// Checked on the intact plate (blocks coupled at the hole and the edges) and
// after bonds broke under a stretch of 1 % along x (blocks soft along x).
TEST_CASE("the block preconditioner inverts the small-strain stiffness' diagonal blocks",
          "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  const std::size_t n = particles.size();
  auto scene = quasi_static_scene(true);  // no loads: every component free
  // The blocks alone: without the coarse correction of Sec. 4.13, which
  // precondition() adds by default.
  auto blocks_only = lattice_scene(scene);
  blocks_only.quasi_static.coarse_correction = false;
  QuasiStaticProblem fast(blocks_only, particles);
  const bool broken = GENERATE(false, true);
  if (broken) {
    // 1 % along x (s0 is about 0.8 % here): the bonds near the x axis break, those near y hold.
    std::vector<double> stretched(2 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) stretched[i] = 1e-2 * particles.x[i];
    REQUIRE(fast.break_overstretched_bonds(stretched) > 0);
  }
  const std::vector<double> rest(2 * n, 0.0);
  const auto& diagonal = fast.preconditioner();
  std::vector<double> d(2 * n), hd_x, hd_y, r(2 * n), s;
  double largest_coupling = 0, smallest_ratio = 1e300, largest_ratio = 0;
  std::size_t checked = 0;
  for (const auto& group : far_apart_groups(particles, fast.model().horizon)) {
    std::fill(d.begin(), d.end(), 0.0);
    for (auto i : group) d[i] = 1;
    fast.hessian_times(rest, d, hd_x);
    std::fill(d.begin(), d.end(), 0.0);
    for (auto i : group) d[n + i] = 1;
    fast.hessian_times(rest, d, hd_y);
    for (auto i : group) {
      const double kxx = hd_x[i], kxy = hd_x[n + i], kyy = hd_y[n + i];
      REQUIRE(hd_y[i] == Approx(kxy).margin(1e-6 * (kxx + kyy)));  // K0 symmetric
      const double trace = kxx + kyy;
      if (!(trace > 0)) continue;
      const double floor = 1e-2 * trace;
      CHECK(diagonal[i] == Approx(kxx + floor).epsilon(1e-5));
      CHECK(diagonal[n + i] == Approx(kyy + floor).epsilon(1e-5));
      // M^-1 applied to the block's columns gives the unit vectors.
      for (int axis = 0; axis < 2; ++axis) {
        std::fill(r.begin(), r.end(), 0.0);
        r[i] = axis == 0 ? kxx + floor : kxy;
        r[n + i] = axis == 0 ? kxy : kyy + floor;
        fast.precondition(r, s);
        CHECK(s[i] == Approx(axis == 0 ? 1.0 : 0.0).margin(1e-5));
        CHECK(s[n + i] == Approx(axis == 0 ? 0.0 : 1.0).margin(1e-5));
      }
      largest_coupling = std::max(largest_coupling, std::fabs(kxy) / trace);
      smallest_ratio = std::min(smallest_ratio, kxx / kyy);
      largest_ratio = std::max(largest_ratio, kxx / kyy);
      ++checked;
    }
  }
  CHECK(checked > n / 2);
  // The blocks are not scalar: coupled x-y where a family is cut by the hole
  // or an edge, and anisotropic there; after breaking along x every particle
  // is softer along x than along y, some by far.
  CHECK(largest_coupling > 0.05);
  if (broken) {
    CHECK(smallest_ratio < 0.5);
    CHECK(largest_ratio < 1.0);
  } else {
    CHECK(smallest_ratio < 0.8);
    CHECK(largest_ratio > 1.2);
  }
}
