// Griffith: a central crack in a plate under slowly increasing tension starts
// to grow at the stress linear elastic fracture mechanics gives, for PMB and
// for OSB (quasi-static load steps, bonds breaking between minimisations,
// theory.md Secs. 4.11, 5.6).
//
// Reference: Griffith's energy balance for a crack of length 2a in an
// infinite plate under remote tension sigma, plane stress: K_I = sigma sqrt(pi a)
// and G = K_I^2 / E, so growth starts at G = G0,
//   sigma_c = sqrt(E G0 / (pi a)).
// For a plate of finite width W the stress intensity is K_I = F sigma sqrt(pi a)
// with Tada's finite-width factor for the centre-cracked plate (Tada, Paris &
// Irwin, The Stress Analysis of Cracks Handbook, centre crack in a strip under
// uniform tension, Feddersen's secant form with Tada's correction, accurate to
// 0.1 % for any a / b, b = W / 2):
//   F = (1 - 0.025 (a/b)^2 + 0.06 (a/b)^4) sqrt(sec(pi a / (2 b))),
// so sigma_c = sqrt(E G0 / (pi a)) / F with sigma the gross stress, the
// reaction of the grips divided by the section W h. The plate is 1.5 W high
// with grips one horizon deep at top and bottom (u_y prescribed, u_x free):
// 0.75 W between the crack and each grip, where the stress is uniform again
// (a centre crack disturbs the stress over a distance of the order of a).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>

#include "error.hpp"
#include "lattice.hpp"
#include "load_steps.hpp"
#include "quasi_static_problem.hpp"
#include "support.hpp"

using namespace pd::solver;

namespace {

struct GriffithSetup {
  ModelType model = ModelType::pmb;
  double poisson_ratio = 1.0 / 3.0;  // OSB only (PMB: 1/3)
  double spacing = 1e-4;             // dx [m]
  int horizon_factor = 4;            // m = delta / dx
  int crack_half_length_cells = 20;  // a / dx
  int width_cells = 100;             // W / dx
  double first_load_factor = 0.9;    // load factor 1: the uncracked plate at the Griffith stress
  double load_step = 0.025;          // between load steps
};

struct GriffithOnset {
  double griffith = 0;            // sigma_c with the finite-width factor [Pa]
  double finite_width_factor = 0; // F
  double last_intact = 0;         // gross stress of the last step without growth [Pa]
  double onset = 0;               // the same, scaled to the first step with growth [Pa]
  std::size_t tip_pairs_before = 0;  // pairs broken before growth (at the tips)
  long most_rounds_before = 0;       // the most minimisations of a step before growth
  std::size_t particles = 0;
  double seconds = 0;
  std::string log;
};

// Runs the load steps until the crack has grown one horizon beyond either
// pre-crack tip and returns the gross stress bracket of the onset.
GriffithOnset griffith_onset(const GriffithSetup& g, std::ostream* progress = nullptr) {
  const double dx = g.spacing, delta = g.horizon_factor * dx, a = g.crack_half_length_cells * dx;
  const double width = g.width_cells * dx, height = 2 * std::lround(0.75 * g.width_cells) * dx;
  const auto p = pd::make_rectangle_lattice(width, height, dx, delta, pd::Quadrature::analytic);
  const double xc = 0.5 * width, yc = 0.5 * height;  // both on cell boundaries (even counts)

  auto scene = pd::quasistatic::test::quasi_static_scene(/*damage=*/true);
  scene.model = g.model;
  if (g.model == ModelType::osb) scene.material.poisson_ratio = g.poisson_ratio;
  scene.material.plane = PlaneKind::stress;
  scene.quasi_static.tolerance = 1e-7;
  scene.quasi_static.max_iterations = 200000;
  scene.quasi_static.lattice_kernels = g.model == ModelType::pmb;
  const double E = scene.material.youngs_modulus, G0 = scene.material.fracture_energy;
  const double ab = 2 * a / width;
  GriffithOnset r;
  r.finite_width_factor = (1 - 0.025 * ab * ab + 0.06 * std::pow(ab, 4)) * std::sqrt(1 / std::cos(M_PI * ab / 2));
  r.griffith = std::sqrt(E * G0 / (M_PI * a)) / r.finite_width_factor;
  // Load factor 1: the grips apart by the strain sigma_c / E over the height
  // (the uncracked plate's stress sigma_c; the cracked one is more compliant
  // and carries less: the stress is read from the reactions).
  const double U = 0.5 * r.griffith / E * height;
  for (const auto& [set, sign] : {std::pair{"bottom", -1.0}, std::pair{"top", 1.0}}) {
    LoadSpec l;
    l.name = set;
    l.kind = LoadKind::displacement;
    l.region.set = set;
    l.has_y = true;
    l.y = sign * U;
    scene.loads.push_back(l);
  }
  // Two halves from the centre out, so that both tips cut their bonds alike
  // (theory.md Sec. 1.5: the half-open rule).
  scene.precracks.push_back({{xc, yc}, {xc - a, yc}});
  scene.precracks.push_back({{xc, yc}, {xc + a, yc}});
  scene.quasi_static.load_factors.clear();
  for (int k = 0; g.first_load_factor + k * g.load_step < 1.8; ++k)
    scene.quasi_static.load_factors.push_back(g.first_load_factor + k * g.load_step);
  // Growth: damage on the two rows along the crack line more than half a
  // horizon beyond a tip. The pre-crack cuts no bond of those particles (a
  // bond from x_i = a + d to the other row crosses the line at x < a only if
  // it spans 2 d > delta in x), so their damage is that of new cracking.
  std::vector<std::uint32_t> beyond;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    if (std::fabs(p.y[i] - yc) < dx && std::fabs(p.x[i] - xc) > a + 0.5 * delta) beyond.push_back(i);
  scene.stop.enabled = true;
  scene.stop.damage = 0.2;

  // Under fixed grips the centre crack runs once it starts (its energy release
  // rate grows with its length): the load step where it starts would
  // re-equilibrate round after round until the plate separates. Growth is
  // therefore detected either by the stop condition (damage beyond a tip at
  // the end of a step) or by the step needing more re-equilibrations than
  // the tips ever need before growth (at most 12 in these runs), with the
  // damage beyond a tip checked in the state reached.
  scene.quasi_static.max_breaking_rounds = 20;

  const auto start = std::chrono::steady_clock::now();
  QuasiStaticProblem problem(scene, p);
  std::vector<LoadStepRecord> steps;
  const LoadStepObserver keep = [&](const QuasiStaticProblem&, const std::vector<double>&, const LoadStepRecord& r) {
    steps.push_back(r);
  };
  std::ostringstream log;
  std::ostream& out = progress ? *progress : log;
  std::string stop_reason;
  double running_at = 0;  // load factor of a step that did not settle
  try {
    stop_reason = solve_quasi_static(problem, scene, beyond, out, keep, nullptr, {}, progress).stop_reason;
  } catch (const pd::Error& e) {
    const std::string message = e.what();
    REQUIRE(message.find("quasi_static.max_breaking_rounds") != std::string::npos);
    running_at = scene.quasi_static.load_factors.at(steps.size());
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.particles = p.size();
  r.log = log.str();
  double damage_beyond = 0;
  const auto damage = problem.damage();
  for (const auto i : beyond) damage_beyond = std::max(damage_beyond, damage[i]);
  INFO(r.log);
  REQUIRE(damage_beyond >= scene.stop.damage);  // the crack grew beyond a tip
  // The last step without growth and the load factor of the first with it.
  const bool stopped = running_at == 0;
  REQUIRE(steps.size() >= (stopped ? 2u : 1u));
  const auto& before = steps[steps.size() - (stopped ? 2 : 1)];
  const double onset_factor = stopped ? steps.back().load_factor : running_at;
  std::size_t top = 0;
  for (std::size_t l = 0; l < problem.loads().size(); ++l)
    if (problem.loads()[l].spec.name == "top") top = l;
  r.last_intact = std::fabs(before.reactions[top].reaction_y) / (width * scene.material.thickness);
  r.onset = r.last_intact * onset_factor / before.load_factor;
  r.tip_pairs_before = 0;
  for (const auto& step : steps)
    if (step.load_factor <= before.load_factor) r.tip_pairs_before += step.pairs_broken;
  r.most_rounds_before = 0;
  for (const auto& step : steps)
    if (step.load_factor <= before.load_factor) r.most_rounds_before = std::max(r.most_rounds_before, step.minimisations);
  return r;
}

std::string describe(const GriffithSetup& g, const GriffithOnset& r) {
  std::ostringstream s;
  s << (g.model == ModelType::pmb ? "PMB" : "OSB") << " nu = " << g.poisson_ratio << ", m = " << g.horizon_factor
    << ", a = " << g.crack_half_length_cells << " dx, W = " << g.width_cells << " dx (" << r.particles
    << " particles): onset between " << r.last_intact / 1e6 << " and " << r.onset / 1e6 << " MPa, Griffith "
    << r.griffith / 1e6 << " MPa (F = " << r.finite_width_factor << "), ratio " << r.last_intact / r.griffith
    << " .. " << r.onset / r.griffith << "; " << r.tip_pairs_before << " pairs broke before (at most " << r.most_rounds_before << " minimisations in a step); " << r.seconds << " s";
  return s.str();
}

}  // namespace

// Bound 10 % on both ends of the onset bracket (the last load step without
// growth and the first with it, 2.5 % apart), PMB at a = 5 delta, m = 4
// (a = 20 dx, W = 100 dx, H = 150 dx, 15,000 particles). What PD adds to
// LEFM here: a tip zone of the size of the horizon, and the lattice's own
// quadrature of the energy of the bonds across a crack line, which makes
// the onset late at m = 3. Measured: 1.008 .. 1.029 times sigma_c at m = 4;
// at m = 3, 1.072 .. 1.093 (a = 15 dx) and 1.094 .. 1.115 (a = 20 dx): the
// study in docs/validation.md, "Griffith" (OSB: the next test). A critical stretch
// from a wrong fracture energy moves the onset with sqrt(G0): a factor 2 in
// G0 is 41 % in stress.
TEST_CASE("Griffith: a centre crack starts to grow at sqrt(E G0 / (pi a)) within 10 % with PMB",
          "[quasistatic][griffith]") {
  GriffithSetup g;  // PMB, m = 4, a = 20 dx, W = 100 dx
  // Measured: the tips break a few dozen pairs at load factor 1.1 and the
  // crack runs at 1.225; the steps start at 1.1, so that the tips' own
  // breaking before growth happens within the run.
  g.first_load_factor = 1.1;
  const auto r = griffith_onset(g);
  INFO(describe(g, r));
  CHECK(r.tip_pairs_before > 0);  // the tips broke bonds first, and then the crack ran
  CHECK(r.last_intact == Approx(r.griffith).epsilon(0.10));
  CHECK(r.onset == Approx(r.griffith).epsilon(0.10));
}

// The same with OSB at nu = 0.25 (a = (kappa - 2 mu) / 2 < 0: the dilatation
// term matters, theory.md Sec. 5.1; its critical stretch is that of
// Sec. 5.3), at m = 3, a = 15 dx, W = 75 dx (8,400 particles): OSB's
// quasi-static problem runs on neighbour lists with Hessian products by
// differences (theory.md Sec. 5.6), several times PMB's cost per particle,
// so the coarser of the study's settings. Bound 10 %; measured 1.056 ..
// 1.078 times sigma_c (PMB at the same setting: 1.072 .. 1.093, late by the
// m = 3 excess of the study in docs/validation.md, "Griffith").
TEST_CASE("Griffith: a centre crack starts to grow at sqrt(E G0 / (pi a)) within 10 % with OSB",
          "[quasistatic][osb][griffith]") {
  GriffithSetup g;
  g.model = ModelType::osb;
  g.poisson_ratio = 0.25;
  g.horizon_factor = 3;
  g.crack_half_length_cells = 15;
  g.width_cells = 75;
  g.first_load_factor = 1.2;  // measured: the tips break 42 pairs at 1.2 and 1.225, the crack runs at 1.275
  const auto r = griffith_onset(g);
  INFO(describe(g, r));
  CHECK(r.tip_pairs_before > 0);
  CHECK(r.last_intact == Approx(r.griffith).epsilon(0.10));
  CHECK(r.onset == Approx(r.griffith).epsilon(0.10));
}

// The convergence study behind the bound (docs/validation.md, "Griffith"):
// GRIFFITH_MODEL=pmb|osb GRIFFITH_NU GRIFFITH_M GRIFFITH_A GRIFFITH_W
// (a and W in cells) GRIFFITH_STEP GRIFFITH_FIRST; not part of the suite.
TEST_CASE("Griffith study", "[.griffith-study]") {
  GriffithSetup g;
  if (const char* v = std::getenv("GRIFFITH_MODEL")) g.model = std::string(v) == "osb" ? ModelType::osb : ModelType::pmb;
  if (const char* v = std::getenv("GRIFFITH_NU")) g.poisson_ratio = std::stod(v);
  if (const char* v = std::getenv("GRIFFITH_M")) g.horizon_factor = std::stoi(v);
  if (const char* v = std::getenv("GRIFFITH_A")) g.crack_half_length_cells = std::stoi(v);
  if (const char* v = std::getenv("GRIFFITH_W")) g.width_cells = std::stoi(v);
  if (const char* v = std::getenv("GRIFFITH_STEP")) g.load_step = std::stod(v);
  if (const char* v = std::getenv("GRIFFITH_FIRST")) g.first_load_factor = std::stod(v);
  const auto r = griffith_onset(g, &std::cerr);
  WARN(describe(g, r));
}
