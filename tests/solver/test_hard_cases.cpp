// Hard numerical cases that must end in a clear error, not in a success:
// a forced step above the stable limit whose blow-up never meets an energy
// row, and step counts too large to count or to run.
#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>

#include "error.hpp"
#include "run.hpp"
#include "simulation.hpp"
#include "test_support.hpp"

using namespace pd::solver;

namespace {

struct Outcome {
  bool failed = false;
  std::string message;  // the error, or the stop reason of a run that finished
};

Outcome run(const Scene& scene, const std::string& folder) {
  RunOptions options;
  options.output_dir = folder + "/out";
  options.show_progress = false;
  std::ostringstream log;
  options.log = &log;
  try {
    return {false, run_scene(scene, options).stop_reason};
  } catch (const pd::Error& e) {
    return {true, e.what()};
  }
}

// A plate kicked at its left edge, damage on, stopping when the right edge is damaged.
Scene kicked_plate(const std::string& folder, double step_factor) {
  const double dx = 1e-4;
  const auto plate = test::write_plate(folder, "plate.pdp", 40 * dx, 10 * dx, dx, 3 * dx);
  const auto probe = pd::make_rectangle_lattice(40 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  auto scene = test::basic_scene();
  scene.particle_file = plate;
  scene.effects.damage = true;
  const double stable = Simulation(scene, probe).stable_time_step();
  scene.time.automatic = false;
  scene.time.step = step_factor * stable;
  scene.time.force = true;
  scene.time.end = 2000 * scene.time.step;
  LoadSpec kick;
  kick.kind = LoadKind::initial_velocity;
  kick.region.set = "left";
  kick.has_x = true;
  kick.x = 1.0;
  scene.loads = {kick};
  scene.stop.enabled = true;
  scene.stop.region.set = "right";
  scene.stop.damage = 0.35;
  return scene;
}

}  // namespace

TEST_CASE("a blow-up between energy rows is caught in the step it happens", "[hard]") {
  const auto folder = test::fresh_folder("blow_up_between_rows");
  // 3 x the stable limit: the unstable modes tear the plate until the stop set
  // is damaged. With one energy row at the end only, the run used to end with
  // the stop condition and exit 0.
  auto scene = kicked_plate(folder, 3.0);
  scene.output.energy_interval = 100000;
  const auto outcome = run(scene, folder);
  INFO(outcome.message);
  CHECK(outcome.failed);
  CHECK_THAT(outcome.message, Catch::Contains("unstable at step") && Catch::Contains("kinetic energy") &&
                                  Catch::Contains("stable limit"));
}

TEST_CASE("a stable run with the same plate still ends with its stop condition or end time", "[hard]") {
  // The check must not fire on a legitimate run: the same kick at 0.8 x the limit.
  const auto folder = test::fresh_folder("stable_kick");
  auto scene = kicked_plate(folder, 0.8);
  scene.output.energy_interval = 100000;
  const auto outcome = run(scene, folder);
  INFO(outcome.message);
  CHECK_FALSE(outcome.failed);
}

TEST_CASE("a step count that cannot be counted or run is refused with its size", "[hard]") {
  const auto folder = test::fresh_folder("step_count");
  const double dx = 1e-4;
  auto scene = test::basic_scene();
  scene.particle_file = test::write_plate(folder, "plate.pdp", 12 * dx, 10 * dx, dx, 3 * dx);
  // 2e12 s at about 1e-8 s per step: 2e20 steps, beyond 2^63 (it used to run one step and exit 0).
  scene.time.end = 2e12;
  auto outcome = run(scene, folder);
  CHECK(outcome.failed);
  CHECK_THAT(outcome.message, Catch::Contains("steps") && Catch::Contains("days") && Catch::Contains("time.end"));
  // A fixed step of 1e-300 s: 1e294 steps.
  scene.time.end = 1e-6;
  scene.time.automatic = false;
  scene.time.step = 1e-300;
  outcome = run(scene, folder);
  CHECK(outcome.failed);
  CHECK_THAT(outcome.message, Catch::Contains("refused"));
  // Countable (1e15 < 2^53) but over a year even at 1e10 directed bond
  // evaluations per second (about 2,600 bonds: 8 years). The refusal counts
  // the work, not the set-up's one timed evaluation: before 5 December 2026
  // a run near the bound was refused or warned about by the machine's load.
  scene.time.step = 1e-21;
  outcome = run(scene, folder);
  CHECK(outcome.failed);
  CHECK_THAT(outcome.message, Catch::Contains("days even at 1e10 directed bond evaluations per second"));

}

TEST_CASE("a state that overflows to a non-finite value stops the run naming the quantity and particle", "[hard]") {
  // A kick of 1e300 m/s at a stable step: the stretch times the micromodulus
  // overflows within the first steps, long before any energy row.
  const auto folder = test::fresh_folder("non_finite_state");
  auto scene = kicked_plate(folder, 0.8);
  scene.loads.front().x = 1e300;
  scene.output.energy_interval = 100000;
  const auto outcome = run(scene, folder);
  INFO(outcome.message);
  CHECK(outcome.failed);
  CHECK_THAT(outcome.message, Catch::Contains("unstable at step") && Catch::Contains("non-finite") &&
                                  Catch::Contains("of particle") && Catch::Contains("last good state"));
}
