// The quasi-static solver on the dynamic solver's kernels (quasi_static.kernels
// = "lattice", docs/solver.md "Fast kernels"): its residual against the energy
// table's (the double-precision reference, an independent implementation:
// energy_bonds.hpp and the neighbour-list kernel), its Hessian product, and
// the equilibria and cracks both reach.
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "lattice.hpp"
#include "linear_cg.hpp"
#include "load_steps.hpp"
#include "mixed_precision.hpp"
#include "ncg.hpp"
#include "plate_grid.hpp"
#include "quasi_static_problem.hpp"
#include "support.hpp"

using namespace pd::solver;
using namespace pd::quasistatic::test;

// Reference: the energy table's residual (double, exact gradient of the
// energy; tested against differences of the energy in test_energy_minimisation.cpp).
// The double pass differs from it only by the table's float reference bonds
// (1e-7 relative in a bond's extension); the float sweep also by the rounding
// of u to 24 bits, 6e-8 |u| in each bond's extension of ~1e-3 |xi|: a few
// 1e-5 of the residual at this field.
TEST_CASE("lattice kernels: the residual is the energy table's, to float round-off or in double",
          "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  auto scene = quasi_static_scene(true);
  scene.effects.surface_correction = GENERATE(false, true);
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem lists(scene, particles);
  QuasiStaticProblem fast(lattice_scene(scene), particles);
  REQUIRE(fast.lattice_kernels());
  REQUIRE(lists.stiffness_asymmetry() > 1e-3);  // the general particles' table must be symmetrised
  std::vector<double> u = test_field(particles);
  const ResidualsOfBothPaths r = residuals_of_both_paths(lists, fast, u);
  INFO("float " << difference(r.fast, r.lists) / r.scale << ", double " << difference(r.fast_double, r.lists) / r.scale);
  CHECK(difference(r.fast_double, r.lists) < 1e-6 * r.scale);
  CHECK(difference(r.fast, r.lists) < 1e-4 * r.scale);
  CHECK(fast.reaction_norm() == Approx(lists.reaction_norm()).epsilon(1e-6));
  // The energies agree too (the kernel's double energy pass against the table's).
  CHECK(fast.strain_energy(u) == Approx(lists.strain_energy(u)).epsilon(1e-6));
}

// Reference: the exact Hessian product of the energy table at u. The fast
// product is the small-strain Hessian, which differs from it by terms of the
// order of the strain (1e-3 here): d.Hd agrees to a few 1e-3.
TEST_CASE("lattice kernels: the Hessian product is the small-strain one", "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  auto scene = quasi_static_scene(true);
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem lists(scene, particles);
  QuasiStaticProblem fast(lattice_scene(scene), particles);
  fast.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::small_strain);
  std::vector<double> u = test_field(particles);
  lists.set_load_factor(1.0, u);
  fast.set_load_factor(1.0, u);
  std::vector<double> d(u.size()), h_lists, h_fast;
  for (std::size_t k = 0; k < d.size(); ++k) d[k] = lists.free_mask()[k] ? 1e-6 * std::cos(0.37 * k) : 0.0;
  lists.hessian_times(u, d, h_lists);
  fast.hessian_times(u, d, h_fast);
  double dhd_lists = 0, dhd_fast = 0;
  for (std::size_t k = 0; k < d.size(); ++k) dhd_lists += d[k] * h_lists[k], dhd_fast += d[k] * h_fast[k];
  CHECK(dhd_fast == Approx(dhd_lists).epsilon(5e-3));
  // At u = 0 both are the small-strain Hessian: equal to the sweep's float round-off.
  std::vector<double> rest(u.size(), 0.0);
  lists.hessian_times(rest, d, h_lists);
  CHECK(difference(h_fast, h_lists) < 1e-5 * norm(h_lists));
}

// Reference: central differences of the double residual (the kernel's double
// pass, lattice_double.hpp) at a deformed state with broken bonds: the test
// field, a rigid rotation of 0.01 rad, and a jump of 0.02 mm in u_x across
// the plate's middle that breaks the bonds across it (the steeper ones hold:
// particles hang on a few bonds there). The tangent product (float sweep of
// Model::force_change) agrees to float round-off: the pair terms carry ~1e-7,
// their sums a few times that, against 1e-10 of the differences (step 1e-6
// horizon: truncation of order step^2). The small-strain K0 misses the
// rotation and the geometric terms by ~1e-2: a factor above 100 apart.
TEST_CASE("lattice kernels: the tangent product is the Hessian at a deformed state with broken bonds",
          "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  auto scene = quasi_static_scene(true);
  scene.effects.surface_correction = GENERATE(false, true);
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem fast(lattice_scene(scene), particles);
  const std::size_t n = particles.size();
  double middle = 0;
  for (double x : particles.x) middle += x / static_cast<double>(n);
  std::vector<double> u = test_field(particles);
  for (std::size_t i = 0; i < n; ++i) {
    const double angle = 1e-2;
    u[i] += -angle * (particles.y[i] - middle) + (particles.x[i] > middle ? 2e-5 : 0.0);
    u[n + i] += angle * (particles.x[i] - middle);
  }
  fast.set_load_factor(1.0, u);
  REQUIRE(fast.break_overstretched_bonds(u) > 0);
  std::vector<double> d(u.size()), h_tangent, h_difference, h_small_strain;
  for (std::size_t k = 0; k < d.size(); ++k) d[k] = fast.free_mask()[k] ? 1e-6 * std::cos(0.37 * k) : 0.0;
  fast.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::tangent);
  fast.hessian_times(u, d, h_tangent);
  fast.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::central_difference);
  fast.hessian_times(u, d, h_difference);
  fast.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::small_strain);
  fast.hessian_times(u, d, h_small_strain);
  const double scale = norm(h_difference);
  INFO("tangent " << difference(h_tangent, h_difference) / scale << ", K0 "
                  << difference(h_small_strain, h_difference) / scale);
  CHECK(difference(h_tangent, h_difference) < 1e-5 * scale);
  CHECK(difference(h_small_strain, h_difference) > 1e-3 * scale);
}

// Reference: analytic. At a uniform compression u = eps x (every bond
// shortened by eps |xi|, directions unchanged) an infinitesimal rotation
// d = (-y, x) moves each bond's end across it (delta perpendicular to n, |delta| = |xi|):
// only the geometric term acts, and d.H d = eps / (1 + eps) x the small-strain
// curvature of the dilation x, 1/2 sum h A_i k |xi|^2 (theory.md Sec. 4.8), which
// is negative: CG on the tangent must stop at such a direction (linear_cg.hpp).
TEST_CASE("lattice kernels: the tangent's geometric term, and CG stops at negative curvature",
          "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  auto scene = quasi_static_scene(true);  // no loads: every component free
  QuasiStaticProblem fast(lattice_scene(scene), particles);
  const std::size_t n = particles.size();
  const double eps = -1e-3;
  std::vector<double> u(2 * n), rotation(2 * n), dilation(2 * n), h;
  for (std::size_t i = 0; i < n; ++i) {
    u[i] = eps * particles.x[i];
    u[n + i] = eps * particles.y[i];
    rotation[i] = -particles.y[i];
    rotation[n + i] = particles.x[i];
    dilation[i] = particles.x[i];
    dilation[n + i] = particles.y[i];
  }
  fast.set_load_factor(1.0, u);
  const auto dot = [](const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t k = 0; k < a.size(); ++k) s += a[k] * b[k];
    return s;
  };
  fast.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::small_strain);
  fast.hessian_times(u, dilation, h);
  const double dilation_curvature = dot(dilation, h);
  fast.set_lattice_hessian(QuasiStaticProblem::LatticeHessian::tangent);
  fast.hessian_times(u, rotation, h);
  const double rotation_curvature = dot(rotation, h);
  REQUIRE(dilation_curvature > 0);
  // Float sweep: n to 1e-7 (its part (n.delta)^2 ~ 1e-14 |delta|^2), sums to ~1e-6.
  CHECK(rotation_curvature == Approx(eps / (1 + eps) * dilation_curvature).epsilon(1e-4));

  // CG from the right-hand side M d_rot (M the 2 x 2 blocks): its first direction is the rotation.
  const auto& diagonal = fast.preconditioner();
  const auto& coupling = fast.preconditioner_coupling();
  std::vector<double> r(2 * n), w;
  for (std::size_t i = 0; i < n; ++i) {
    r[i] = diagonal[i] * rotation[i] + coupling[i] * rotation[n + i];
    r[n + i] = coupling[i] * rotation[i] + diagonal[n + i] * rotation[n + i];
  }
  NcgSettings settings;
  settings.tolerance = 1e-2;
  const auto solved = solve_linear(fast, u, r, w, settings);
  CHECK(solved.negative_curvature);
  CHECK(solved.iterations == 0);
  CHECK(norm(w) == 0);
}

// Reference: the Hessian product itself, applied afresh to the result. Linear
// CG updates its residual by the recurrence r - alpha H d; at the tangent of
// the test field (positive definite: strains of 1e-3, the plate held on its
// left edge) the true residual r - H w must meet the tolerance too, up to the
// float products' round-off (1e-6 of |r| over a few hundred iterations).
TEST_CASE("linear CG on the tangent reaches its tolerance on the true residual", "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  auto scene = quasi_static_scene(true);
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem fast(lattice_scene(scene), particles);
  std::vector<double> u = test_field(particles);
  fast.set_load_factor(1.0, u);
  fast.set_double_residual(true);
  std::vector<double> r, w, hw;
  fast.residual(u, r);
  NcgSettings settings;
  settings.tolerance = 1e-4;
  const auto solved = solve_linear(fast, u, r, w, settings);
  REQUIRE(solved.converged);
  CHECK_FALSE(solved.negative_curvature);
  fast.hessian_times(u, w, hw);
  for (std::size_t k = 0; k < r.size(); ++k) hw[k] = r[k] - hw[k];
  INFO(solved.iterations << " iterations, true residual " << norm(hw) / norm(r));
  CHECK(norm(hw) < 2e-4 * norm(r));
}

// Reference: the energy table's equilibrium (the double-precision path, NCG to
// 1e-9). Both minimise the same energy; the lattice path converges to 1e-6
// (float sweep, then the double pass), so the displacements agree to about
// the tolerance times the conditioning: 1e-5 of the largest displacement.
TEST_CASE("lattice kernels and the energy table reach the same equilibrium on a plate with a hole",
          "[quasistatic][lattice]") {
  const auto particles = coarse_c1_nbnug();
  auto scene = quasi_static_scene();
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem lists(scene, particles);
  std::vector<double> u_lists;
  lists.set_load_factor(1.0, u_lists);
  NcgSettings settings;
  settings.tolerance = 1e-9;
  settings.max_iterations = 20000;
  REQUIRE(minimise_energy(lists, u_lists, settings).converged);

  QuasiStaticProblem fast(lattice_scene(scene), particles);
  std::vector<double> u_fast;
  fast.set_load_factor(1.0, u_fast);
  settings.tolerance = 1e-6;
  const auto result = minimise_in_mixed_precision(fast, u_fast, settings);
  REQUIRE(result.ncg.converged);
  INFO("iterations " << result.ncg.iterations << ", rounds " << result.rounds);
  CHECK(result.rounds >= 2);  // at least one correction, and the check of its result
  CHECK(result.ncg.relative_residual() <= 1e-6);
  double largest = 0;
  for (double v : u_lists) largest = std::max(largest, std::fabs(v));
  double off = 0;
  for (std::size_t k = 0; k < u_lists.size(); ++k) off = std::max(off, std::fabs(u_fast[k] - u_lists[k]));
  CHECK(off < 1e-5 * largest);
  REQUIRE(fast.reactions().size() == lists.reactions().size());
  for (std::size_t l = 0; l < lists.reactions().size(); ++l)
    CHECK(fast.reactions()[l].reaction_x == Approx(lists.reactions()[l].reaction_x).epsilon(1e-5));
}

// Reference: the energy table's run of the same scene (double precision).
// A bar pulled apart in load steps: bonds break (float extension in the
// sweep against double in the table: only bonds within 1e-7 of s0 could
// differ), the same steps break bonds, the reactions agree to 1e-4 and both
// separate at the same step.
TEST_CASE("lattice kernels and the energy table break the same bonds and separate together",
          "[quasistatic][lattice][damage]") {
  const auto plate = pd::make_rectangle_lattice(2e-3, 1e-3, 1e-4, 3e-4, pd::Quadrature::analytic);
  auto scene = quasi_static_scene(true);
  scene.loads = {x_displacement("left", -1.0), x_displacement("right", 1.0)};  // load factor = u per edge [m]
  scene.quasi_static.load_factors.clear();
  for (int k = 1; k <= 40; ++k) scene.quasi_static.load_factors.push_back(k * 5e-7);
  scene.quasi_static.tolerance = 1e-7;
  scene.quasi_static.stop_reaction_fraction = 0.05;
  std::ostringstream log;
  QuasiStaticProblem lists(scene, plate);
  const auto a = solve_quasi_static(lists, scene, {}, log);
  const Scene fast_scene = lattice_scene(scene);
  QuasiStaticProblem fast(fast_scene, plate);
  const auto b = solve_quasi_static(fast, fast_scene, {}, log);
  REQUIRE(a.steps.size() == b.steps.size());
  CHECK(b.stop_reason == a.stop_reason);
  bool broke = false;
  for (std::size_t s = 0; s < a.steps.size(); ++s) {
    INFO("step " << a.steps[s].step);
    CHECK(b.steps[s].broken_bonds == a.steps[s].broken_bonds);
    broke = broke || a.steps[s].pairs_broken > 0;
    const double ra = axial_reaction(a.steps[s], lists.loads()), rb = axial_reaction(b.steps[s], fast.loads());
    CHECK(rb == Approx(ra).epsilon(1e-4).margin(1e-4 * axial_reaction(a.steps[0], lists.loads())));
  }
  CHECK(broke);
  const auto da = a.damage, db = b.damage;
  REQUIRE(da.size() == db.size());
  for (std::size_t i = 0; i < da.size(); ++i) CHECK(db[i] == Approx(da[i]).margin(1e-6));
}

// Progress inside a minimisation: with an interval of 0 s a line after every
// iteration that did not converge, numbered in order.
TEST_CASE("a running minimisation reports its iterations at the progress interval", "[quasistatic][ncg]") {
  const auto particles = coarse_c1_nbnug();
  auto scene = quasi_static_scene();
  scene.loads = {fixed("left"), x_displacement("right", 1e-5)};
  QuasiStaticProblem problem(scene, particles);
  std::vector<double> u;
  problem.set_load_factor(1.0, u);
  NcgSettings settings;
  settings.tolerance = 1e-6;
  std::vector<NcgProgress> lines;
  settings.progress = [&](const NcgProgress& p) { lines.push_back(p); };
  settings.progress_interval = 0;
  const auto result = minimise_energy(problem, u, settings);
  REQUIRE(result.converged);
  REQUIRE(result.iterations > 10);
  REQUIRE(static_cast<long>(lines.size()) == result.iterations - 1);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    CHECK(lines[k].iteration == static_cast<long>(k) + 1);
    CHECK(lines[k].relative_residual > 1e-6);
    CHECK(lines[k].seconds >= (k ? lines[k - 1].seconds : 0.0));
  }
  // A long interval: no line in a run this short.
  lines.clear();
  settings.progress_interval = 3600;
  std::vector<double> again;
  problem.set_load_factor(1.0, again);
  minimise_energy(problem, again, settings);
  CHECK(lines.empty());

  // Through the load steps on the lattice kernels: the lines name the step and
  // count the iterations on across the correction rounds (mixed_precision.hpp).
  Scene fast_scene = lattice_scene(scene);
  fast_scene.quasi_static.tolerance = 1e-6;
  fast_scene.quasi_static.progress_interval = 0;
  QuasiStaticProblem fast(fast_scene, particles);
  std::ostringstream log, progress;
  const auto run = solve_quasi_static(fast, fast_scene, {}, log, {}, nullptr, {}, &progress);
  REQUIRE(run.steps.size() == 1);
  const std::string text = progress.str();
  CHECK_THAT(text, Catch::Contains("load step 1 (load factor 1), minimisation 1: iteration 1, relative residual"));
  // One line per iteration but the last of each round (3 to 5 rounds), numbered on.
  std::istringstream lines_in(text);
  std::string line;
  long count = 0, last = 0;
  while (std::getline(lines_in, line)) {
    const auto at = line.find(": iteration ");
    REQUIRE(at != std::string::npos);
    const long iteration = std::stol(line.substr(at + 12));
    CHECK(iteration > last);
    last = iteration;
    ++count;
  }
  CHECK(count >= run.steps[0].iterations - 6);
  CHECK(last < run.steps[0].iterations);
}
