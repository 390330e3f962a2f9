// Scene parsing: a complete scene is read with its values and defaults, and
// every kind of mistake gives a message naming the file, the key and the value.
#include <catch2/catch.hpp>

#include "error.hpp"
#include "lattice.hpp"
#include "scene.hpp"
#include "simulation.hpp"

using pd::solver::parse_scene;

namespace {
const char* valid_scene = R"(
particles = "plate.pdp"
[material]
youngs_modulus = 3.24e9
density = 1190
fracture_energy = 200
poisson_ratio = 0.35
[effects]
damage = true
surface_correction = true
[time]
step = 2e-8
end = 1e-5
[[loads]]
set = "top"
type = "velocity"
y = 0.3
ramp_time = 2e-4
[[loads]]
box = [0, 0, 0.01, 0.001]
type = "traction"
y = -6e6
table = [[0, 0], [1e-6, 1], [2e-6, 1]]
[[precracks]]
from = [0, 0.0125]
to = [0.002, 0.0125]
[output]
snapshot_interval = 100
damage_thresholds = [0.3]
)";

std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_scene(text, "dir/scene.toml", overrides);
  } catch (const pd::Error& e) {
    return e.what();
  }
  return "no error";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}
}  // namespace

TEST_CASE("a valid scene is read with values and defaults", "[scene]") {
  const auto s = parse_scene(valid_scene, "dir/scene.toml");
  CHECK(s.particle_file == "dir/plate.pdp");  // relative to the scene file
  CHECK(s.material.youngs_modulus == 3.24e9);
  CHECK(s.material.thickness == 1.0);  // default
  CHECK(s.material.plane == pd::solver::PlaneKind::stress);
  CHECK(s.effects.surface_correction);
  CHECK_FALSE(s.time.automatic);
  CHECK(s.time.step == 2e-8);
  REQUIRE(s.loads.size() == 2);
  CHECK(s.loads[0].name == "top");
  CHECK(s.loads[0].has_y);
  CHECK_FALSE(s.loads[0].has_x);
  CHECK(s.loads[0].time_function(1e-4) == Approx(0.5));
  CHECK(s.loads[0].time_function(3e-4) == 1.0);
  CHECK(s.loads[1].region.has_box);
  CHECK(s.loads[1].time_function(0.5e-6) == Approx(0.5));
  CHECK(s.loads[1].time_function(5e-6) == 1.0);
  REQUIRE(s.precracks.size() == 1);
  CHECK(s.precracks[0].to.x == 0.002);
  CHECK(s.output.energy_interval == 100);  // default
  CHECK(s.output.damage_thresholds == std::vector<double>{0.3});
}

TEST_CASE("scene overrides (--set) replace and add keys", "[scene]") {
  const auto s = parse_scene(valid_scene, "dir/scene.toml",
                             {"time.step=auto", "time.safety=0.5", "material.plane=strain", "effects.damage=false"});
  CHECK(s.time.automatic);
  CHECK(s.time.safety == 0.5);
  CHECK(s.material.plane == pd::solver::PlaneKind::strain);
  CHECK_FALSE(s.effects.damage);
  CHECK_THAT(error_of(valid_scene, {"time.stepp=1"}), Catch::Contains("unknown key 'time.stepp'"));
  CHECK_THAT(error_of(valid_scene, {"nonsense"}), Catch::Contains("expected section.key=value"));
}

TEST_CASE("scene errors name the file, the key and the value", "[scene]") {
  SECTION("unknown key") {
    const auto m = error_of(replaced(valid_scene, "density = 1190", "density = 1190\ndensty = 1"));
    CHECK_THAT(m, Catch::Contains("dir/scene.toml"));
    CHECK_THAT(m, Catch::Contains("unknown key 'material.densty'"));
  }
  SECTION("unknown key in a load") {
    CHECK_THAT(error_of(replaced(valid_scene, "y = 0.3", "y = 0.3\nramp = 1")),
               Catch::Contains("unknown key 'loads[0].ramp'"));
  }
  SECTION("unknown top-level table") {
    CHECK_THAT(error_of(std::string(valid_scene) + "[outputs]\nx = 1\n"), Catch::Contains("unknown key 'outputs'"));
  }
  SECTION("wrong type") {
    const auto m = error_of(replaced(valid_scene, "density = 1190", "density = \"heavy\""));
    CHECK_THAT(m, Catch::Contains("'material.density'"));
    CHECK_THAT(m, Catch::Contains("heavy"));
    CHECK_THAT(m, Catch::Contains("expected a number"));
    CHECK_THAT(error_of(replaced(valid_scene, "damage = true", "damage = 1")),
               Catch::Contains("'effects.damage' = 1: expected true or false"));
  }
  SECTION("missing key") {
    CHECK_THAT(error_of(replaced(valid_scene, "fracture_energy = 200", "")),
               Catch::Contains("missing required key 'material.fracture_energy'"));
    CHECK_THAT(error_of(replaced(valid_scene, "end = 1e-5", "")), Catch::Contains("missing required key 'time.end'"));
  }
  SECTION("bad values") {
    CHECK_THAT(error_of(replaced(valid_scene, "youngs_modulus = 3.24e9", "youngs_modulus = -3.24e9")),
               Catch::Contains("'material.youngs_modulus' = -3240000000.0: expected a positive number"));
    CHECK_THAT(error_of(replaced(valid_scene, "youngs_modulus = 3.24e9", "youngs_modulus = nan")),
               Catch::Contains("'material.youngs_modulus' = nan: expected a finite number"));
    CHECK_THAT(error_of(replaced(valid_scene, "step = 2e-8", "step = \"fast\"")),
               Catch::Contains("'time.step' = 'fast'"));
    CHECK_THAT(error_of(replaced(valid_scene, "type = \"velocity\"", "type = \"pull\"")),
               Catch::Contains("'loads[0].type' = 'pull'"));
    CHECK_THAT(error_of(replaced(valid_scene, "to = [0.002, 0.0125]", "to = [0.002]")),
               Catch::Contains("'precracks[0].to'"));
    CHECK_THAT(error_of(replaced(valid_scene, "damage_thresholds = [0.3]", "damage_thresholds = [1.5]")),
               Catch::Contains("'output.damage_thresholds'"));
  }
  SECTION("models not implemented yet are rejected clearly") {
    const auto m = error_of(std::string(valid_scene) + "[model]\ntype = \"osb\"\n");
    CHECK_THAT(m, Catch::Contains("'model.type' = 'osb': not implemented yet"));
  }
  SECTION("syntax error gives the line") {
    CHECK_THAT(error_of("particles = \"a.pdp\"\n[material\n"), Catch::Contains("dir/scene.toml:2"));
  }
}

TEST_CASE("regions must exist in the particle file", "[scene]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  const auto error_with_load = [&](const std::string& load) {
    const std::string text = std::string(valid_scene).substr(0, std::string(valid_scene).find("[[loads]]")) + load;
    try {
      pd::solver::Simulation(parse_scene(text, "dir/scene.toml"), p);
    } catch (const pd::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto unknown = error_with_load("[[loads]]\nset = \"middle\"\ntype = \"fixed\"\n");
  CHECK_THAT(unknown, Catch::Contains("dir/scene.toml") && Catch::Contains("'loads[0].set' = \"middle\"") &&
                          Catch::Contains("known: left, right, bottom, top"));
  CHECK_THAT(error_with_load("[[loads]]\nbox = [1, 1, 2, 2]\ntype = \"fixed\"\n"),
             Catch::Contains("'loads[0]'") && Catch::Contains("contains no particle"));
  CHECK_THAT(error_with_load("[[loads]]\ntype = \"fixed\"\n"), Catch::Contains("missing key 'loads[0].set'"));
  CHECK(error_with_load("[[loads]]\nset = \"all\"\ntype = \"fixed\"\n") == "no error");
}
