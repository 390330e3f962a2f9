// Loads on the particles (docs/scenes.md, "[[loads]]"): the regions, loads
// that contradict each other, the work a suddenly applied velocity does, and
// values that vary linearly with position.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "error.hpp"
#include "scene.hpp"
#include "lattice.hpp"
#include "load_steps.hpp"
#include "loads.hpp"
#include "quasi_static_problem.hpp"
#include "simulation.hpp"
#include "test_support.hpp"

using namespace pd::solver;

namespace {

LoadSpec load_on(const std::string& set, LoadKind kind, bool x, bool y) {
  LoadSpec l;
  l.name = set;
  l.kind = kind;
  l.region.set = set;
  l.has_x = x || kind == LoadKind::fixed;
  l.has_y = y || kind == LoadKind::fixed;
  return l;
}

std::string error_of(const Scene& scene, const pd::ParticleSet& p) {
  try {
    resolve_loads(scene, p);
  } catch (const pd::Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("two loads constraining the same component of the same particles are an error", "[loads]") {
  const double dx = 1e-4;
  // Sets one horizon (3 dx) deep: left and bottom share the 3 x 3 particles of the corner.
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.loads = {load_on("left", LoadKind::fixed, true, true), load_on("bottom", LoadKind::displacement, false, true)};
  const auto both = error_of(scene, p);
  CHECK_THAT(both, Catch::Contains("test-scene.toml: loads 'left' (fixed on set 'left') and 'bottom' (displacement on "
                                   "set 'bottom') both constrain the y component of 9 particles"));
  // Different components do not conflict, nor do the two parts of... one load with itself.
  scene.loads = {load_on("left", LoadKind::velocity, true, false), load_on("bottom", LoadKind::velocity, false, true)};
  CHECK(error_of(scene, p) == "no error");
  // A box that leaves out the corner resolves it.
  scene.loads = {load_on("left", LoadKind::fixed, true, true), load_on("bottom", LoadKind::displacement, false, true)};
  scene.loads[1].region = {};
  scene.loads[1].region.has_box = true;
  scene.loads[1].region.box = {3 * dx, 0, 10 * dx, 3 * dx};
  CHECK(error_of(scene, p) == "no error");
  // A pin on a particle of a constrained set.
  scene.loads = {load_on("left", LoadKind::velocity, true, false), load_on("pin", LoadKind::fixed, true, true)};
  scene.loads[1].region = {};
  scene.loads[1].region.has_nearest = true;
  scene.loads[1].region.nearest = {0, 5 * dx};
  CHECK_THAT(error_of(scene, p), Catch::Contains("both constrain the x component of 1 particle (e.g. the one at (5e-05, "));
}

TEST_CASE("messages name a load by its place in the scene file, also in a part of a switching scene", "[loads]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = parse_scene(R"(particles = "plate.pdp"
[material]
youngs_modulus = 3.24e9
density = 1190
fracture_energy = 200
[quasi_static]
load_factors = [1.0]
then = "dynamic"
[time]
step = "auto"
end = 1e-6
[[loads]]
phase = "quasi_static"
set = "top"
type = "displacement"
y = 1e-6
[[loads]]
phase = "dynamic"
set = "middle"
type = "velocity"
y = 0.3
)", "switch.toml");
  scene.loads = {scene.loads[1]};  // the dynamic part's loads
  CHECK_THAT(error_of(scene, p), Catch::Contains("switch.toml:19: key 'loads[1].set' = \"middle\""));
}

TEST_CASE("a traction or initial velocity on constrained particles is a warning", "[loads]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  auto pull = load_on("top", LoadKind::traction, false, true);
  pull.y = 1e6;
  auto hold = load_on("left", LoadKind::fixed, true, true);
  hold.name = "support";
  scene.loads = {pull, hold};
  const auto loads = resolve_loads(scene, p);
  const auto warnings = load_warnings(loads, false);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("load 'top' (traction on set 'top') acts on the y component of 9 particles "
                                          "that load 'support' (fixed on set 'left') constrains"));
  // The loads may name particles of a set larger than the particle file (a
  // restarted adaptive run's refined set): the check reads only the loads.
  auto renumbered = loads;
  for (auto& load : renumbered)
    for (auto& i : load.particles) i += 5'000'000;
  CHECK(load_warnings(renumbered, false) == warnings);
  // The traction's x component is not given: no warning for it; a traction elsewhere: none at all.
  scene.loads[0].region.set = "right";
  scene.loads[1].region.set = "bottom";
  scene.loads[1].kind = LoadKind::velocity;
  scene.loads[1].has_y = false;  // holds x only; the traction pulls in y
  CHECK(load_warnings(resolve_loads(scene, p), false).empty());
  // No load at all runs, with a warning.
  const auto none = load_warnings({}, false);
  REQUIRE(none.size() == 1);
  CHECK(none[0] == "no [[loads]] act in this run: the plate stays at rest (docs/scenes.md)");
  // A switching scene's dynamic part without loads is not at rest: it
  // springs back from the quasi-static equilibrium (before 7 December 2026
  // it was told the plate stays at rest).
  const auto released = load_warnings({}, true);
  REQUIRE(released.size() == 1);
  CHECK_THAT(released[0], Catch::StartsWith("no [[loads]] of phase = \"dynamic\": the dynamic part starts from the "
                                            "quasi-static part's equilibrium with nothing holding the plate"));
  CHECK_THAT(released[0], !Catch::Contains("stays at rest"));
}

// Reference: the material's own scales. PMMA (E = 3.24 GPa, rho = 1190
// kg/m^3): wave speed sqrt(E / rho) = 1650 m/s. A traction of 1 (meant as
// 1 MPa) is 3.1e-10 E; 5e9 Pa is above E; 300 m/s (300 mm/s read as m/s) is
// 0.18 of the wave speed. 1 MPa and 0.3 m/s, the values of the C3 scenes, say nothing.
// A displacement is held to the plate's size: above a tenth of it, a strain of 10 % or more.
TEST_CASE("load values far from the material's scales are a warning naming the likely unit", "[loads]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  auto pull = load_on("top", LoadKind::traction, false, true);
  auto move = load_on("bottom", LoadKind::velocity, false, true);
  const auto warnings_for = [&](double traction, double velocity) {
    pull.y = traction;
    move.y = velocity;
    scene.loads = {pull, move};
    return load_size_warnings(scene.material, resolve_loads(scene, p));
  };
  CHECK(warnings_for(1e6, 0.3).empty());
  const auto small = warnings_for(1, 0.3);
  REQUIRE(small.size() == 1);
  CHECK_THAT(small[0], Catch::Contains("load 'top': a traction of at most 1 Pa is 3.08642e-10 times Young's modulus: "
                                       "tractions are in Pa"));
  CHECK(warnings_for(5e9, 0.3).size() == 1);
  const auto fast = warnings_for(1e6, -300);
  REQUIRE(fast.size() == 1);
  CHECK_THAT(fast[0], Catch::Contains("load 'bottom': a velocity of up to 300 m/s is 0.18") &&
                          Catch::Contains("times the wave speed sqrt(E / rho) = 1650") &&
                          Catch::Contains("velocities are in m/s"));
  // A table's largest factor counts: 1e6 Pa held at 1e-5 of it is 10 Pa, 3.1e-9 E.
  pull.time_function.kind = TimeFunction::Kind::table;
  pull.time_function.table = {{0, 0}, {1e-6, 1e-5}};
  CHECK(warnings_for(1e6, 0.3).size() == 1);
  // A displacement against the plate's size (1 mm square): 0.02 mm is a
  // strain of about 2 %, 0.5 (0.5 mm read as m) 500 plates.
  auto shift = load_on("bottom", LoadKind::displacement, false, true);
  shift.y = -2e-5;
  scene.loads = {shift};
  CHECK(load_size_warnings(scene.material, resolve_loads(scene, p)).empty());
  shift.y = -0.5;
  scene.loads = {shift};
  const auto far = load_size_warnings(scene.material, resolve_loads(scene, p));
  REQUIRE(far.size() == 1);
  CHECK_THAT(far[0], Catch::Contains("load 'bottom': a displacement of up to 0.5 m is 500 times the plate's size "
                                     "(0.001 m): displacements are in m"));
  // A traction or an initial velocity of 0 does nothing (a careless scene,
  // or a component meant as the other); a velocity or a displacement of 0
  // holds its set, quietly.
  const auto zero = warnings_for(0, 0);
  REQUIRE(zero.size() == 1);
  CHECK(zero[0] == "load 'top': a traction of 0 everywhere has no effect (every component given is 0)");
  auto kick = load_on("left", LoadKind::initial_velocity, true, false);
  shift.y = 0;
  scene.loads = {kick, shift};
  const auto still = load_size_warnings(scene.material, resolve_loads(scene, p));
  REQUIRE(still.size() == 1);
  CHECK(still[0] == "load 'left': an initial velocity of 0 everywhere has no effect (every component given is 0)");
}

TEST_CASE("a pin takes the particle nearest to its point", "[loads]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 6 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  const auto pin_at = [&](double x, double y) {
    RegionSpec r;
    r.has_nearest = true;
    r.nearest = {x, y};
    const auto particles = resolve_region(r, p, "s.toml", "loads[0]");
    REQUIRE(particles.size() == 1);
    return pd::Vec2{p.x[particles[0]], p.y[particles[0]]};
  };
  const auto near = [&](pd::Vec2 a, double x, double y) { return std::hypot(a.x - x, a.y - y) < 1e-9 * dx; };
  CHECK(near(pin_at(3.4 * dx, 2.3 * dx), 3.5 * dx, 2.5 * dx));
  CHECK(near(pin_at(0, 0), 0.5 * dx, 0.5 * dx));          // the corner of the plate: the corner particle
  CHECK(near(pin_at(5 * dx, 3 * dx), 4.5 * dx, 2.5 * dx));  // a vertex: four at one distance, the lowest, leftmost
  CHECK(near(pin_at(10.2 * dx, 6.1 * dx), 9.5 * dx, 5.5 * dx));  // just outside: within a cell
  // Farther than a cell from every particle: e.g. written in mm.
  RegionSpec far;
  far.has_nearest = true;
  far.nearest = {0.5, 0.3};
  try {
    resolve_region(far, p, "s.toml", "loads[2]");
    FAIL("no error");
  } catch (const pd::Error& e) {
    CHECK_THAT(std::string(e.what()), Catch::Contains("s.toml: key 'loads[2].nearest' = [0.5, 0.3]") &&
                                          Catch::Contains("more than its cell size") &&
                                          Catch::Contains("x in [0, 0.001], y in [0, 0.0006] m"));
  }
}

// Energy balance of docs/formats.md: for an elastic plate, kinetic + strain =
// external work to within 1 %. A velocity applied suddenly gives its particles
// kinetic energy at t = 0: that is work the load does, and must be counted.
TEST_CASE("a suddenly applied velocity's kinetic energy is counted as external work", "[loads][dynamics]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(30 * dx, 20 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  auto top = load_on("top", LoadKind::velocity, false, true);
  top.y = 1.0;
  auto bottom = load_on("bottom", LoadKind::velocity, false, true);
  bottom.y = -1.0;
  scene.loads = {top, bottom};
  Simulation sim(scene, p);
  const auto start = sim.energies();
  // At t = 0 the work done is the kinetic energy of the two moving strips, 1/2 rho v^2 h A.
  double moving_area = 0;
  for (const char* set : {"top", "bottom"})
    for (auto i : p.find_set(set)->particles) moving_area += p.volume[i];
  const double given = 0.5 * scene.material.density * 1.0 * moving_area * scene.material.thickness;
  CHECK(start.kinetic == Approx(given).epsilon(1e-12));
  CHECK(start.external_work == Approx(given).epsilon(1e-12));
  // Early, when the strips' kinetic energy is much of the total, and later.
  for (const double until : {0.25e-6, 0.5e-6, 1e-6, 2e-6, 4e-6}) {
    while (sim.time() < until) sim.step();
    const auto e = sim.energies();
    INFO("t " << sim.time() << " s: work " << e.external_work << " J, kinetic " << e.kinetic << " J, strain "
              << e.strain << " J");
    CHECK(e.kinetic + e.strain == Approx(e.external_work).epsilon(0.01));
  }

  // The same for an initial velocity: the plate moving as a whole has all its energy from t = 0.
  auto kick = load_on("all", LoadKind::initial_velocity, true, false);
  kick.x = 2.0;
  scene.loads = {kick};
  Simulation moving(scene, p);
  for (int k = 0; k < 20; ++k) moving.step();
  const auto m = moving.energies();
  CHECK(m.external_work > 0);
  CHECK(m.kinetic + m.strain == Approx(m.external_work).epsilon(1e-9));
}

// Reference: a homogeneous deformation u = (ex (x - xc), ey (y - yc)) is an
// exact equilibrium of the PD plate when the boundary layers follow it: the
// bond forces of an affine field are odd in the bond vector, so they cancel
// over every family that is mirror-symmetric in the free component (all
// families away from the layers that hold that component). Left and right
// layers prescribe u_x, top and bottom u_y, linearly over the layer's depth;
// a pin holds the centre particle, where the field is zero. The quasi-static
// run must reproduce the field to the minimiser's tolerance. A layer moved
// uniformly (its edge value) instead cannot.
TEST_CASE("linear displacements and a pin reproduce an exact linear field in a quasi-static run", "[loads][quasistatic]") {
  const double dx = 1e-4, width = 21 * dx, height = 11 * dx;  // odd counts: a particle at the centre
  const double xc = width / 2, yc = height / 2, ex = 1e-4, ey = -3e-5;
  const auto p = pd::make_rectangle_lattice(width, height, dx, 3 * dx, pd::Quadrature::analytic);
  std::ostringstream centre, field_x, field_y;
  centre << "[" << xc << ", " << yc << "]";
  field_x << "{ value = 0, gradient = [" << ex << ", 0], at = " << centre.str() << " }";
  // The two-point form: ey (y - yc) at y = 0 and at y = height.
  field_y << "{ from = [0, 0], to = [0, " << height << "], values = [" << -ey * yc << ", " << ey * (height - yc) << "] }";
  const auto scene_with = [&](const std::string& x_value, const std::string& y_top, const std::string& y_bottom) {
    std::ostringstream text;
    text << "particles = \"plate.pdp\"\n[material]\nyoungs_modulus = 3.24e9\n[effects]\ndamage = false\n"
         << "[quasi_static]\nload_factors = [1.0]\ntolerance = 1e-10\n"
         << "[[loads]]\nset = \"left\"\ntype = \"displacement\"\nx = " << x_value << "\n"
         << "[[loads]]\nset = \"right\"\ntype = \"displacement\"\nx = " << x_value << "\n"
         << "[[loads]]\nset = \"top\"\ntype = \"displacement\"\ny = " << y_top << "\n"
         << "[[loads]]\nset = \"bottom\"\ntype = \"displacement\"\ny = " << y_bottom << "\n"
         << "[[loads]]\nname = \"pin\"\nnearest = " << centre.str() << "\ntype = \"fixed\"\n";
    return parse_scene(text.str(), "linear.toml");
  };
  // Largest distance of the solution from the field, over its largest value.
  const auto relative_error = [&](const Scene& scene) {
    QuasiStaticProblem problem(scene, p);
    std::ostringstream log;
    const auto result = solve_quasi_static(problem, scene, {}, log);
    const std::size_t n = p.size();
    double error = 0, largest = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double fx = ex * (p.x[i] - xc), fy = ey * (p.y[i] - yc);
      error = std::max({error, std::fabs(result.u[i] - fx), std::fabs(result.u[n + i] - fy)});
      largest = std::max({largest, std::fabs(fx), std::fabs(fy)});
    }
    return error / largest;
  };
  const double linear = relative_error(scene_with(field_x.str(), field_y.str(), field_y.str()));
  CHECK(linear < 1e-6);
  // Top and bottom layers moved rigidly by the field's value at the edges: the field is wrong in and near them.
  std::ostringstream rigid_top, rigid_bottom;
  rigid_top << ey * (height - yc);
  rigid_bottom << -ey * yc;
  INFO("linear loads: " << linear);
  CHECK(relative_error(scene_with(field_x.str(), rigid_top.str(), rigid_bottom.str())) > 100 * linear);
}

TEST_CASE("velocities that vary linearly with position move each particle at its own velocity", "[loads][dynamics]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(20 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  auto shear = load_on("left", LoadKind::velocity, true, false);  // v_x = 2000/s * y: a shear of the left layer
  shear.x = 0;
  shear.x_variation.gradient = {0, 2000};
  auto spin = load_on("right", LoadKind::initial_velocity, false, true);  // v_y = 1 m/s + 500/s (x - 1.5 mm)
  spin.y = 1;
  spin.y_variation.gradient = {500, 0};
  spin.y_variation.origin = {1.5e-3, 0};
  scene.loads = {shear, spin};
  Simulation sim(scene, p);
  for (auto i : p.find_set("right")->particles)
    CHECK(sim.kinematics().vy[i] == Approx(1 + 500 * (p.x[i] - 1.5e-3)));
  for (int k = 0; k < 50; ++k) sim.step();
  for (auto i : p.find_set("left")->particles)
    CHECK(sim.kinematics().ux[i] == Approx(2000 * p.y[i] * sim.time()).epsilon(1e-9));
}

// Constraints that hold both components of every particle (one load, or one
// per component) leave nothing to move by the equations of motion: warned,
// naming them (since 7 December 2026; before, no word). A free component
// anywhere, or no count given (the loads of another set), gets no warning.
TEST_CASE("constraints that hold both components of every particle are a warning", "[loads]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  auto slide = load_on("all", LoadKind::velocity, true, false);
  slide.name = "slide";
  auto level = load_on("all", LoadKind::displacement, false, true);
  level.name = "level";
  scene.loads = {slide, level};
  const auto both = resolve_loads(scene, p);
  const auto warnings = load_warnings(both, false, p.size());
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0] == "the constraints 'slide' (velocity on set 'all'), 'level' (displacement on set 'all') hold "
                       "both components of every one of the 100 particles: no particle is left to move, and the run "
                       "computes only the motion the loads prescribe; give them sets or boxes that leave the plate "
                       "free between the loaded edges (docs/scenes.md, [[loads]])");
  CHECK(load_warnings(both, false).empty());
  CHECK(load_warnings(both, false, p.size() - 1).empty());  // a particle beyond the count: another set's loads
  CHECK(load_warnings(both, false, p.size() + 1).empty());  // one particle free
  scene.loads = {slide};
  CHECK(load_warnings(resolve_loads(scene, p), false, p.size()).empty());
}
