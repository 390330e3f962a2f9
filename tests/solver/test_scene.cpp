// Scene parsing: a complete scene is read with its values and defaults, and
// every kind of mistake gives a message naming the file, the key and the value.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdlib>
#include <string>

#include "error.hpp"
#include "lattice.hpp"
#include "results_format.hpp"
#include "scene.hpp"
#include "simulation.hpp"

using pd::solver::parse_scene;

namespace {
// The line (from 1) of the first occurrence of `needle` in `text`.
std::size_t line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  REQUIRE(at != std::string::npos);
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

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
    const std::string text = replaced(valid_scene, "density = 1190", "density = 1190\ndensty = 1");
    const auto m = error_of(text);
    // With its line, as every other key's message (before 5 December 2026 without).
    CHECK_THAT(m, Catch::StartsWith("dir/scene.toml:" + std::to_string(line_of(text, "densty")) +
                                    ": unknown key 'material.densty' = 1"));
  }
  SECTION("unknown key in a load") {
    CHECK_THAT(error_of(replaced(valid_scene, "y = 0.3", "y = 0.3\nramp = 1")),
               Catch::Contains("unknown key 'loads[0].ramp'"));
  }
  SECTION("a very long key or value is shown by its start and its length") {
    const std::string key(100000, 'a');
    const auto m = error_of(replaced(valid_scene, "density = 1190", "density = 1190\n" + key + " = 1"));
    CHECK_THAT(m, Catch::Contains("unknown key 'material." + std::string(71, 'a') + "... (100009 characters)' = 1"));
    CHECK(m.size() < 400);
    const auto v = error_of(valid_scene, {"time.end=\"" + std::string(5000, '9') + " lightyears\""});
    CHECK_THAT(v, Catch::Contains("(5011 characters)"));
    CHECK(v.size() < 500);
  }
  SECTION("unknown top-level table") {
    CHECK_THAT(error_of(std::string(valid_scene) + "[outputs]\nx = 1\n"), Catch::Contains("unknown key 'outputs'"));
  }
  SECTION("wrong type") {
    const auto m = error_of(replaced(valid_scene, "density = 1190", "density = \"heavy\""));
    CHECK_THAT(m, Catch::Contains("'material.density'"));
    CHECK_THAT(m, Catch::Contains("heavy"));
    CHECK_THAT(m, Catch::Contains("not a number with a unit"));
    CHECK_THAT(error_of(replaced(valid_scene, "damage = true", "damage = 1")),
               Catch::Contains("'effects.damage' = 1: expected true or false"));
  }
  SECTION("missing key") {
    CHECK_THAT(error_of(replaced(valid_scene, "fracture_energy = 200", "")),
               Catch::Contains("missing required key 'material.fracture_energy'"));
    CHECK_THAT(error_of(replaced(valid_scene, "end = 1e-5", "")), Catch::Contains("missing required key 'time.end'"));
    // A value --set put there is blamed on --set, not on a line of the file.
    CHECK_THAT(error_of(valid_scene, {"material.density=-1"}),
               Catch::Contains("dir/scene.toml, --set: key 'material.density' = -1: expected a positive number"));
    // A misspelt required key or table is named where it is.
    CHECK_THAT(error_of(replaced(valid_scene, "youngs_modulus = 3.24e9", "youngs_modulos = 3.24e9")),
               Catch::Contains("missing required key 'material.youngs_modulus' (line 4 has 'youngs_modulos': misspelt?)"));
    CHECK_THAT(error_of(replaced(valid_scene, "[time]", "[tme]")),
               Catch::Contains("missing required table [time] (line 11 has 'tme': misspelt?)"));
    CHECK_THAT(error_of(replaced(valid_scene, "fracture_energy = 200", "")), !Catch::Contains("misspelt"));
  }
  SECTION("bad values") {
    CHECK_THAT(error_of(replaced(valid_scene, "youngs_modulus = 3.24e9", "youngs_modulus = -3.24e9")),
               Catch::Contains("'material.youngs_modulus' = -3.24e+09: expected a positive number"));
    CHECK_THAT(error_of(replaced(valid_scene, "youngs_modulus = 3.24e9", "youngs_modulus = nan")),
               Catch::Contains("'material.youngs_modulus' = nan: expected a finite number"));
    CHECK_THAT(error_of(replaced(valid_scene, "step = 2e-8", "step = \"fast\"")),
               Catch::Contains("'time.step' = 'fast'"));
    CHECK_THAT(error_of(replaced(valid_scene, "type = \"velocity\"", "type = \"pull\"")),
               Catch::Contains("'loads[0].type' = 'pull'"));
    CHECK_THAT(error_of(replaced(valid_scene, "to = [0.002, 0.0125]", "to = [0.002]")),
               Catch::Contains("'precracks[0].to'"));
    // A crack given twice (reversed), or overlapping another on its line, is
    // cut as one longer crack; cracks that meet end to end are fine.
    const std::string crack = "to = [0.002, 0.0125]\n";
    CHECK_THAT(error_of(replaced(valid_scene, crack, crack + "[[precracks]]\nfrom = [0.002, 0.0125]\nto = [0, 0.0125]\n")),
               Catch::Contains("'precracks[1].from'") && Catch::Contains("the crack lies along precracks[0] over 0.002 m"));
    CHECK_THAT(error_of(replaced(valid_scene, crack, crack + "[[precracks]]\nfrom = [0.001, 0.0125]\nto = [0.003, 0.0125]\n")),
               Catch::Contains("the crack lies along precracks[0] over 0.001 m"));
    // 0.1 um off its line (written with a rounded coordinate): the same bonds, the same refusal.
    CHECK_THAT(error_of(replaced(valid_scene, crack, crack + "[[precracks]]\nfrom = [0.001, 0.0125001]\nto = [0.003, 0.0125001]\n")),
               Catch::Contains("the crack lies along precracks[0]"));
    CHECK(parse_scene(replaced(valid_scene, crack, crack + "[[precracks]]\nfrom = [0.002, 0.0125]\nto = [0.003, 0.0125]\n"),
                      "dir/scene.toml", {})
              .precracks.size() == 2);
    CHECK(parse_scene(replaced(valid_scene, crack, crack + "[[precracks]]\nfrom = [0, 0.013]\nto = [0.002, 0.013]\n"),
                      "dir/scene.toml", {})
              .precracks.size() == 2);
    CHECK_THAT(error_of(replaced(valid_scene, "damage_thresholds = [0.3]", "damage_thresholds = [1.5]")),
               Catch::Contains("'output.damage_thresholds'"));
    CHECK_THAT(error_of(valid_scene, {"particles=\"\""}), Catch::Contains("key 'particles' = ''"));
    // Each threshold is an array of arrival.vtp, named so that no two share
    // one (before 6 December 2026 by two decimals, which refused these two as
    // both "arrival_time_0.12").
    CHECK(parse_scene(replaced(valid_scene, "damage_thresholds = [0.3]", "damage_thresholds = [0.121, 0.124]"),
                      "dir/scene.toml", {})
              .output.damage_thresholds == std::vector<double>{0.121, 0.124});
    CHECK_THAT(error_of(replaced(valid_scene, "damage_thresholds = [0.3]", "damage_thresholds = [0.3, 0.2, 0.3]")),
               Catch::Contains("key 'output.damage_thresholds' = [0.3, 0.2, 0.3]: threshold 0.3 is given twice"));
  }
  SECTION("models not implemented yet are rejected clearly") {
    const auto m = error_of(std::string(valid_scene) + "[model]\ntype = \"lps\"\n");
    CHECK_THAT(m, Catch::Contains("'model.type' = 'lps': not implemented yet"));
  }
  SECTION("syntax error gives the line") {
    CHECK_THAT(error_of("particles = \"a.pdp\"\n[material\n"), Catch::Contains("dir/scene.toml:2"));
  }
}

// Scene numbers are SI; a number far outside what solids have is most
// likely in another unit, and a value may be written with its unit instead.
// Two decimals where they give the threshold back, else the digits that do:
// the solver's names, and the ones pd-post looks for.
TEST_CASE("each damage threshold names an arrival array of its own, which reads back as it", "[scene]") {
  using pd::results::arrival_array_name;
  CHECK(arrival_array_name(0.35) == "arrival_time_0.35");
  CHECK(arrival_array_name(0.2) == "arrival_time_0.20");
  CHECK(arrival_array_name(1) == "arrival_time_1.00");
  // Before 6 December 2026: "arrival_time_0.00", "arrival_time_0.35", "arrival_time_0.00", "arrival_time_1.00".
  CHECK(arrival_array_name(0.001) == "arrival_time_0.001");
  CHECK(arrival_array_name(0.354) == "arrival_time_0.354");
  CHECK(arrival_array_name(1e-300) == "arrival_time_1e-300");
  CHECK(arrival_array_name(0.999) == "arrival_time_0.999");
  for (double threshold : {0.121, 0.124, 0.1 + 0.2, 1.0 / 3.0, 5e-324, 0.005})
    CHECK(std::strtod(arrival_array_name(threshold).c_str() + std::string(pd::results::arrival_prefix).size(),
                      nullptr) == threshold);
}

TEST_CASE("material values in another unit are refused with the likely unit, and values may carry their unit",
          "[scene][units]") {
  const auto with = [](const std::string& from, const std::string& to) { return replaced(valid_scene, from, to); };
  SECTION("written with a unit, converted to SI") {
    const auto s = parse_scene(with("youngs_modulus = 3.24e9", "youngs_modulus = \"3.24 GPa\"\nthickness = \"5 mm\""),
                               "dir/scene.toml",
                               {"material.density=1.19g/cm^3", "material.fracture_energy=\"0.2 kJ/m^2\"",
                                "time.end=\"10 us\"", "time.step=\"20 ns\"", "loads.0.ramp_time=\"200 us\""});
    CHECK(s.material.youngs_modulus == Approx(3.24e9).epsilon(1e-15));
    CHECK(s.material.thickness == Approx(5e-3).epsilon(1e-15));
    CHECK(s.material.density == Approx(1190).epsilon(1e-15));
    CHECK(s.material.fracture_energy == Approx(200).epsilon(1e-15));
    CHECK(s.time.end == Approx(1e-5).epsilon(1e-15));
    CHECK(s.time.step == Approx(2e-8).epsilon(1e-15));
    CHECK(s.loads.at(0).time_function.ramp_time == Approx(2e-4).epsilon(1e-15));
  }
  SECTION("a value written with its unit is the same scene as its SI number (summary.json, restarts)") {
    const auto plain = parse_scene(valid_scene, "dir/scene.toml");
    const auto with_units = parse_scene(with("youngs_modulus = 3.24e9", "youngs_modulus = \"3.24 GPa\""),
                                        "dir/scene.toml", {"time.step=20ns", "loads.0.ramp_time=\"200 us\""});
    CHECK(with_units.restart_key_text == plain.restart_key_text);
    CHECK(with_units.canonical_text == plain.canonical_text);
  }
  SECTION("a key written with its default value is the same scene as one that leaves it out (restarts)") {
    // Before 5 December 2026 the restart key was the scene's text: a restart
    // with --set output.energy_interval=100 (the default) was refused.
    const auto plain = parse_scene(valid_scene, "dir/scene.toml");
    const auto defaults = parse_scene(valid_scene, "dir/scene.toml",
                                      {"output.energy_interval=100", "output.checkpoint_interval=0",
                                       "effects.damage=true", "model.type=pmb", "loads.0.name=top"});
    CHECK(defaults.restart_key_text == plain.restart_key_text);
    CHECK(defaults.canonical_text != plain.canonical_text);  // summary.json keeps the scene as written
    // A value other than the default is another scene.
    CHECK(parse_scene(valid_scene, "dir/scene.toml", {"output.energy_interval=50"}).restart_key_text !=
          plain.restart_key_text);
    CHECK(parse_scene(valid_scene, "dir/scene.toml", {"model.type=osb"}).restart_key_text != plain.restart_key_text);
    // How often checkpoints are written changes no result: it is no part of
    // the key (before 6 December 2026 it was, and a restart that changed it was refused).
    CHECK(parse_scene(valid_scene, "dir/scene.toml", {"output.checkpoint_interval=30"}).restart_key_text ==
          plain.restart_key_text);
    // The keys that change results, or the files so far, stay in it.
    CHECK(parse_scene(valid_scene, "dir/scene.toml", {"output.snapshot_interval=30"}).restart_key_text !=
          plain.restart_key_text);
    CHECK(parse_scene(valid_scene, "dir/scene.toml", {"model.dual_horizon=true"}).restart_key_text !=
          plain.restart_key_text);
    // [refinement] asks for refinement by being there, with every key at its default.
    const auto dual = parse_scene(valid_scene, "dir/scene.toml", {"model.dual_horizon=true"});
    const auto refined = parse_scene(valid_scene, "dir/scene.toml", {"model.dual_horizon=true", "refinement.levels=1"});
    CHECK(refined.refinement.enabled);
    CHECK(refined.restart_key_text != dual.restart_key_text);
    // Lists at their defaults (before the second sitting of 5 December 2026
    // another scene): the default damage thresholds; no pre-cracks.
    const std::string default_thresholds = with("damage_thresholds = [0.3]\n", "");
    CHECK(parse_scene(default_thresholds, "dir/scene.toml", {"output.damage_thresholds=[0.2, 0.35, 0.5]"})
              .restart_key_text == parse_scene(default_thresholds, "dir/scene.toml").restart_key_text);
    CHECK(parse_scene(default_thresholds, "dir/scene.toml", {"output.damage_thresholds=[0.2, 0.5]"}).restart_key_text !=
          parse_scene(default_thresholds, "dir/scene.toml").restart_key_text);
    const std::string without_cracks = std::string(valid_scene).substr(0, std::string(valid_scene).find("[[precracks]]")) +
                                       std::string(valid_scene).substr(std::string(valid_scene).find("[output]"));
    CHECK(parse_scene(without_cracks, "dir/scene.toml", {"precracks=[]"}).restart_key_text ==
          parse_scene(without_cracks, "dir/scene.toml").restart_key_text);
    // OSB's default failure variant written out (before 7 December 2026 another scene, whose restart was refused).
    const std::vector<std::string> osb{"model.type=osb"};
    auto with_default_failure = osb;
    with_default_failure.push_back("model.osb_failure=force_and_dilatation");
    CHECK(parse_scene(valid_scene, "dir/scene.toml", with_default_failure).restart_key_text ==
          parse_scene(valid_scene, "dir/scene.toml", osb).restart_key_text);
    auto with_other_failure = osb;
    with_other_failure.push_back("model.osb_failure=force_only");
    CHECK(parse_scene(valid_scene, "dir/scene.toml", with_other_failure).restart_key_text !=
          parse_scene(valid_scene, "dir/scene.toml", osb).restart_key_text);
  }
  SECTION("plain numbers in another unit name the unit they are likely in") {
    const auto e = error_of(with("youngs_modulus = 3.24e9", "youngs_modulus = 3.24"));
    CHECK_THAT(e, Catch::Contains("dir/scene.toml:4: key 'material.youngs_modulus' = 3.24"));
    CHECK_THAT(e, Catch::Contains("3.24 Pa is outside the Young's moduli of solids"));
    CHECK_THAT(e, Catch::Contains("If it is in GPa, write \"3.24 GPa\""));
    CHECK_THAT(error_of(with("youngs_modulus = 3.24e9", "youngs_modulus = 3240")), Catch::Contains("If it is in MPa"));
    CHECK_THAT(error_of(with("density = 1190", "density = 1.19")), Catch::Contains("If it is in g/cm^3"));
    CHECK_THAT(error_of(with("density = 1190", "density = 1190\nthickness = 5")),
               Catch::Contains("'material.thickness' = 5: 5 m is outside plate thicknesses") &&
                   Catch::Contains("If it is in mm, write \"5 mm\""));
    CHECK_THAT(error_of(with("fracture_energy = 200", "fracture_energy = 0.05")),
               Catch::Contains("'material.fracture_energy'") && Catch::Contains("If it is in kJ/m^2"));
  }
  SECTION("extreme values are refused by their key, not by their consequences") {
    CHECK_THAT(error_of(with("density = 1190", "density = 1e-300")),
               Catch::Contains("'material.density' = 1e-300") && Catch::Contains("write it with its unit"));
    CHECK_THAT(error_of(with("youngs_modulus = 3.24e9", "youngs_modulus = 1e300")),
               Catch::Contains("'material.youngs_modulus'") && Catch::Contains("outside the Young's moduli"));
    CHECK_THAT(error_of(with("density = 1190", "density = 1190\nthickness = 1e308")),
               Catch::Contains("'material.thickness'") && Catch::Contains("outside plate thicknesses"));
    // Written with its unit, the value is the user's word (here an unusually soft solid).
    CHECK(parse_scene(with("youngs_modulus = 3.24e9", "youngs_modulus = \"3 kPa\""), "s.toml").material.youngs_modulus ==
          Approx(3e3));
  }
  SECTION("a value with a unit must have a known one") {
    CHECK_THAT(error_of(with("youngs_modulus = 3.24e9", "youngs_modulus = \"3.24 GPx\"")),
               Catch::Contains("'material.youngs_modulus' = '3.24 GPx': unknown unit 'GPx'") &&
                   Catch::Contains("(use Pa, kPa, MPa, GPa"));
    CHECK_THAT(error_of(with("end = 1e-5", "end = \"80\"")),
               Catch::Contains("'time.end' = '80': '80' has no unit"));
    CHECK_THAT(error_of(with("youngs_modulus = 3.24e9", "youngs_modulus = \"-3 GPa\"")),
               Catch::Contains("expected a positive value"));
    CHECK_THAT(error_of(with("step = 2e-8", "step = \"fast\"")), Catch::Contains("or \"auto\""));
    CHECK_THAT(error_of(with("density = 1190", "density = \"1.19 g/cc\"")),
               Catch::Contains("(use kg/m^3, g/cm^3)"));
  }
}

TEST_CASE("model.type = \"osb\" needs the material's Poisson ratio and refuses what it lacks", "[scene][osb]") {
  // The OSB model of theory.md Sec. 5 takes nu from the material; surface
  // correction and the quasi-static problem are not there for it yet (docs/scenes.md).
  const std::string osb = replaced(valid_scene, "surface_correction = true", "surface_correction = false") +
                          "[model]\ntype = \"osb\"\n";
  const auto scene = parse_scene(osb, "dir/scene.toml");
  CHECK(scene.model == pd::solver::ModelType::osb);
  CHECK(scene.material.poisson_ratio == 0.35);
  const auto plane_strain = parse_scene(replaced(osb, "poisson_ratio = 0.35", "poisson_ratio = 0.2\nplane = \"strain\""),
                                        "dir/scene.toml");
  CHECK(plane_strain.material.plane == pd::solver::PlaneKind::strain);

  const auto missing = error_of(replaced(osb, "poisson_ratio = 0.35\n", ""));
  CHECK_THAT(missing, Catch::Contains("dir/scene.toml") && Catch::Contains("'material.poisson_ratio'") &&
                          Catch::Contains("required by model.type = \"osb\"") && Catch::Contains("(0, 0.5)"));
  for (const char* bad : {"0.5", "0.0", "-0.25", "0.75"}) {
    const auto m = error_of(replaced(osb, "poisson_ratio = 0.35", std::string("poisson_ratio = ") + bad));
    INFO(m);
    CHECK_THAT(m, Catch::Contains("dir/scene.toml:") && Catch::Contains("'material.poisson_ratio' = " + std::string(bad)) &&
                      Catch::Contains("(0, 0.5)"));
  }
  // Surface correction is accepted with OSB (theory.md Sec. 5.7).
  CHECK(parse_scene(replaced(osb, "surface_correction = false", "surface_correction = true"), "dir/scene.toml")
            .effects.surface_correction);
  const std::string quasi_static = R"(
particles = "plate.pdp"
[model]
type = "osb"
[material]
youngs_modulus = 3.24e9
poisson_ratio = 0.3
[effects]
damage = false
[quasi_static]
load_factors = [1]
[[loads]]
set = "top"
type = "displacement"
y = 1e-6
)";
  // Quasi-static OSB scenes are accepted (theory.md Sec. 5.6), with the material's nu.
  const auto quasi_static_scene = parse_scene(quasi_static, "dir/scene.toml");
  CHECK(quasi_static_scene.model == pd::solver::ModelType::osb);
  CHECK(quasi_static_scene.quasi_static.enabled);
  CHECK(quasi_static_scene.material.poisson_ratio == 0.3);
  // PMB keeps accepting the key as before (reported, not used).
  CHECK(parse_scene(valid_scene, "dir/scene.toml").material.poisson_ratio == 0.35);
}

TEST_CASE("model.osb_failure chooses what a broken OSB bond leaves, for OSB only", "[scene][osb]") {
  // theory.md Sec. 5.8, docs/scenes.md: three names; anything else, or the key
  // with a bond-based model, is refused naming the file, the key and the value.
  const std::string osb = replaced(valid_scene, "surface_correction = true", "surface_correction = false") +
                          "[model]\ntype = \"osb\"\n";
  using pd::solver::OsbFailure;
  CHECK(parse_scene(osb, "dir/scene.toml").osb_failure == OsbFailure::force_and_dilatation);  // the default
  CHECK(parse_scene(osb + "osb_failure = \"force_and_dilatation\"\n", "dir/scene.toml").osb_failure ==
        OsbFailure::force_and_dilatation);
  CHECK(parse_scene(osb + "osb_failure = \"force_only\"\n", "dir/scene.toml").osb_failure == OsbFailure::force_only);
  CHECK(parse_scene(osb + "osb_failure = \"bond_term_only\"\n", "dir/scene.toml").osb_failure ==
        OsbFailure::bond_term_only);
  const auto unknown = error_of(osb + "osb_failure = \"b\"\n");
  CHECK_THAT(unknown, Catch::Contains("dir/scene.toml:") && Catch::Contains("'model.osb_failure' = 'b'") &&
                          Catch::Contains("\"force_and_dilatation\", \"force_only\", \"bond_term_only\""));
  const auto pmb = error_of(valid_scene + std::string("[model]\ntype = \"pmb\"\nosb_failure = \"force_only\"\n"));
  CHECK_THAT(pmb, Catch::Contains("dir/scene.toml:") && Catch::Contains("'model.osb_failure' = 'force_only'") &&
                      Catch::Contains("only for model.type = \"osb\""));
  // The default model is PMB: the key alone is refused as well.
  CHECK_THAT(error_of(valid_scene + std::string("[model]\nosb_failure = \"force_only\"\n")),
             Catch::Contains("only for model.type = \"osb\""));
}

TEST_CASE("regions must exist in the particle file", "[scene]") {
  const double dx = 1e-4;
  const auto p = pd::make_rectangle_lattice(10 * dx, 10 * dx, dx, 3 * dx, pd::Quadrature::analytic);
  const auto error_with_load = [&](const std::string& load, std::vector<std::string> overrides = {}) {
    const std::string text = std::string(valid_scene).substr(0, std::string(valid_scene).find("[[loads]]")) + load;
    try {
      pd::solver::Simulation(parse_scene(text, "dir/scene.toml", overrides), p);
    } catch (const pd::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto unknown = error_with_load("[[loads]]\nset = \"middle\"\ntype = \"fixed\"\n");
  // The message names the scene's line of the key, or --set for a value given there.
  const auto line = 1 + std::count(valid_scene, valid_scene + std::string(valid_scene).find("[[loads]]"), '\n') + 1;
  CHECK_THAT(unknown, Catch::StartsWith("dir/scene.toml:" + std::to_string(line) + ": key 'loads[0].set' = \"middle\"") &&
                          Catch::Contains("known: left, right, bottom, top"));
  CHECK_THAT(error_with_load("[[loads]]\nset = \"left\"\ntype = \"fixed\"\n", {"loads.0.set=middle"}),
             Catch::StartsWith("dir/scene.toml, --set: key 'loads[0].set' = \"middle\": no such boundary set"));
  CHECK_THAT(error_with_load("[[loads]]\nbox = [1, 1, 2, 2]\ntype = \"fixed\"\n"),
             Catch::Contains("'loads[0]'") && Catch::Contains("contains no particle") &&
                 Catch::Contains("(the plate spans x in [0, 0.001], y in [0, 0.001] m; box coordinates are in m"));
  CHECK_THAT(error_with_load("[[loads]]\ntype = \"fixed\"\n"), Catch::Contains("missing key 'loads[0].set'"));
  CHECK(error_with_load("[[loads]]\nset = \"all\"\ntype = \"fixed\"\n") == "no error");
  // A file without sets (a round plate without named curves): before 5
  // December 2026 the message read "(known: , or "all")".
  auto no_sets = p;
  no_sets.sets.clear();
  const std::string text = std::string(valid_scene).substr(0, std::string(valid_scene).find("[[loads]]")) +
                           "[[loads]]\nset = \"top\"\ntype = \"fixed\"\n";
  CHECK_THROWS_WITH(pd::solver::Simulation(parse_scene(text, "dir/scene.toml"), no_sets),
                    Catch::Contains("no such boundary set in the particle file (it has none:") &&
                        Catch::Contains("use \"all\", a box or nearest"));
}

TEST_CASE("scene overrides (--set) reach each load by index or name and each pre-crack by index", "[scene]") {
  const auto s = parse_scene(valid_scene, "dir/scene.toml",
                             {"loads.0.y=1e6", "loads.load1.y=-5e6", "precracks.0.to=[0.003, 0.0125]"});
  CHECK(s.loads[0].y == 1e6);
  CHECK(s.loads[1].y == -5e6);  // the box load goes by load<k>
  CHECK(s.precracks[0].to.x == 0.003);
  // By name: the load's `name`, else its set; a renamed load is still found by its set.
  const auto named = parse_scene(replaced(valid_scene, "set = \"top\"", "set = \"top\"\nname = \"pull\""),
                                 "dir/scene.toml", {"loads.pull.ramp_time=1e-4", "loads.top.y=2"});
  CHECK(named.loads[0].time_function.ramp_time == 1e-4);
  CHECK(named.loads[0].y == 2);
  // Keys inside an entry are checked as in the file.
  CHECK_THAT(error_of(valid_scene, {"loads.0.ramp=1"}), Catch::Contains("unknown key 'loads[0].ramp'"));
  // What cannot be found: the message lists what exists.
  const auto no_load = error_of(valid_scene, {"loads.bottom.y=1"});
  CHECK_THAT(no_load, Catch::Contains("dir/scene.toml: --set 'loads.bottom.y=1'") &&
                          Catch::Contains("no entry 'bottom' in [[loads]]") &&
                          Catch::Contains("0 ('top'), 1 ('load1')"));
  CHECK_THAT(error_of(valid_scene, {"loads.2.y=1"}), Catch::Contains("no entry '2' in [[loads]]"));
  CHECK_THAT(error_of(valid_scene, {"precracks.1.to=[0, 0]"}),
             Catch::Contains("no entry '1' in [[precracks]] (the scene has entry 0)") && Catch::Contains("index"));
  CHECK_THAT(error_of(valid_scene, {"precracks.tip.to=[0, 0]"}), Catch::Contains("no entry 'tip' in [[precracks]]"));
  CHECK_THAT(error_of(valid_scene, {"loads.0=1"}), Catch::Contains("name a key of one entry of 'loads'"));
  const std::string without_cracks = std::string(valid_scene).substr(0, std::string(valid_scene).find("[[precracks]]"));
  CHECK_THAT(error_of(without_cracks, {"precracks.0.to=[0, 0]"}),
             Catch::Contains("the scene has no [[precracks]] (give the whole array instead, e.g. --set 'precracks=["));
  // As the message says: the whole array, in TOML.
  CHECK(parse_scene(without_cracks, "dir/scene.toml", {"precracks=[{from = [0, 0.001], to = [0.002, 0.001]}]"})
            .precracks.size() == 1);
  // Two loads on one set (in the two parts of a switching scene): the name is ambiguous, the index is not.
  const std::string switching = R"(particles = "plate.pdp"
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
set = "top"
type = "velocity"
y = 0.3
)";
  CHECK_THAT(error_of(switching, {"loads.top.y=1"}), Catch::Contains("'top' names more than one entry of [[loads]] (0 (displacement, phase quasi_static) and 1 "
                                 "(velocity, phase dynamic))"));
  CHECK(parse_scene(switching, "dir/scene.toml", {"loads.1.y=0.5"}).loads[1].y == 0.5);
}

TEST_CASE("a quasi-static scene's restart key leaves out the energy interval, a switching scene's keeps it",
          "[scene][restart]") {
  // Only time steps write energy rows (docs/solver.md, "Safety"): a
  // quasi-static run never reads output.energy_interval, and before the
  // third sitting of 6 December 2026 a restart that changed it was refused
  // all the same. A static-then-dynamic scene's dynamic part checks its
  // energy at those rows: it stays in the key.
  const std::string quasi_static = R"(particles = "plate.pdp"
[material]
youngs_modulus = 3.24e9
fracture_energy = 200
[quasi_static]
load_factors = [0.5, 1.0]
[[loads]]
set = "top"
type = "displacement"
y = 1e-6
[output]
energy_interval = 10
)";
  const auto key_of = [](const std::string& text, const std::vector<std::string>& overrides) {
    return parse_scene(text, "dir/scene.toml", overrides).restart_key_text;
  };
  CHECK(key_of(quasi_static, {"output.energy_interval=50"}) == key_of(quasi_static, {}));
  CHECK(key_of(quasi_static, {"output.energy_interval=50"}).find("energy_interval") == std::string::npos);
  // Its other output keys stay.
  CHECK(key_of(quasi_static, {"output.snapshot_interval=2"}) != key_of(quasi_static, {}));
  const std::string switching = replaced(
      replaced(replaced(quasi_static, "load_factors = [0.5, 1.0]\n",
                        "load_factors = [0.5, 1.0]\nthen = \"dynamic\"\n[time]\nstep = \"auto\"\nend = 1e-6\n"),
               "[[loads]]\n", "[[loads]]\nphase = \"quasi_static\"\n"),
      "youngs_modulus = 3.24e9\n", "youngs_modulus = 3.24e9\ndensity = 1190\n");
  CHECK(parse_scene(switching, "dir/scene.toml").quasi_static.then_dynamic);
  CHECK(key_of(switching, {"output.energy_interval=50"}) != key_of(switching, {}));
}

TEST_CASE("a particle file given with --set is relative to the working directory, in the scene to its folder", "[scene]") {
  CHECK(parse_scene(valid_scene, "dir/scene.toml").particle_file == "dir/plate.pdp");
  CHECK(parse_scene(valid_scene, "dir/scene.toml", {"particles=other.pdp"}).particle_file == "other.pdp");
  CHECK(parse_scene(valid_scene, "dir/scene.toml", {"particles=out/c3a.pdp"}).particle_file == "out/c3a.pdp");
  CHECK(parse_scene(valid_scene, "dir/scene.toml", {"particles=/abs/p.pdp"}).particle_file == "/abs/p.pdp");
}

TEST_CASE("keys of an effect that is off are not required, but unknown keys still are errors", "[scene]") {
  const std::string no_fracture_energy = replaced(valid_scene, "fracture_energy = 200", "");
  CHECK_THAT(error_of(no_fracture_energy), Catch::Contains("missing required key 'material.fracture_energy'"));
  const auto s = parse_scene(replaced(no_fracture_energy, "damage = true", "damage = false"), "dir/scene.toml");
  CHECK_FALSE(s.effects.damage);
  CHECK(s.material.fracture_energy == 0);
  CHECK_FALSE(parse_scene(no_fracture_energy, "dir/scene.toml", {"effects.damage=false"}).effects.damage);
  // Given anyway, it is still checked, and misspelt keys are still errors.
  CHECK_THAT(error_of(replaced(valid_scene, "damage = true", "damage = false"), {"material.fracture_energy=-1"}),
             Catch::Contains("'material.fracture_energy' = -1: expected a positive number"));
  CHECK_THAT(error_of(replaced(no_fracture_energy, "damage = true", "damage = false"), {"material.fracture_enrgy=1"}),
             Catch::Contains("unknown key 'material.fracture_enrgy'"));
}

TEST_CASE("two loads with the same name are an error, unless they act in different parts", "[scene]") {
  const std::string twice = std::string(valid_scene) + "[[loads]]\nset = \"top\"\ntype = \"fixed\"\n";
  CHECK_THAT(error_of(twice), Catch::Contains("dir/scene.toml: loads[0] and loads[2] are both named 'top'") &&
                                  Catch::Contains("energy.csv"));
  CHECK(error_of(twice, {"loads.2.name=\"top_support\""}) == "no error");
}

TEST_CASE("load components may vary linearly with position, and pins take the particle nearest to a point", "[scene]") {
  const std::string head = std::string(valid_scene).substr(0, std::string(valid_scene).find("[[loads]]"));
  const auto s = parse_scene(head + R"([[loads]]
set = "right"
type = "displacement"
x = { value = 1e-6, gradient = [0, 2e-4], at = [0.01, 0.005] }
y = { from = [0, 0], to = [0, 0.01], values = [-1e-6, 3e-6] }
[[loads]]
nearest = [0.005, 0]
type = "fixed"
)", "dir/scene.toml");
  const auto& linear = s.loads[0];
  CHECK(linear.x_at({0.01, 0.005}) == Approx(1e-6));
  CHECK(linear.x_at({0.02, 0.015}) == Approx(1e-6 + 2e-4 * 0.01));
  CHECK(linear.y_at({0.7, 0}) == Approx(-1e-6).margin(1e-18));  // constant across the line of the two points
  CHECK(linear.y_at({0, 0.01}) == Approx(3e-6));
  CHECK(linear.y_at({0, 0.005}) == Approx(1e-6));
  CHECK(s.loads[1].region.has_nearest);
  CHECK(s.loads[1].region.nearest.x == 0.005);
  CHECK(s.loads[1].name == "load1");
  // Mistakes.
  const auto load_error = [&](const std::string& load) { return error_of(head + "[[loads]]\n" + load); };
  CHECK_THAT(load_error("set = \"top\"\ntype = \"traction\"\ny = { value = 1, gradient = [0, 1] }\n"),
             Catch::Contains("'loads[0].y'") && Catch::Contains("velocity, displacement and initial_velocity"));
  CHECK_THAT(load_error("set = \"top\"\ntype = \"velocity\"\ny = { value = 1, values = [0, 1] }\n"),
             Catch::Contains("'loads[0].y'") && Catch::Contains("not a mix"));
  const std::string slope = head + "[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = { value = 1, gradient = [0, 1], slope = 2 }\n";
  CHECK_THAT(error_of(slope), Catch::StartsWith("dir/scene.toml:" + std::to_string(line_of(slope, "slope")) +
                                                ": unknown key 'loads[0].y.slope'"));
  // A table that --set wrote whole lacks a key: blamed on --set.
  CHECK_THAT(error_of(valid_scene, {"loads.0.y={value=0.3}"}),
             Catch::StartsWith("dir/scene.toml, --set: missing required key 'loads[0].y.gradient'"));
  // A name heads CSV columns (reaction_x_<name>_N): no comma, quote or line break in it.
  CHECK_THAT(load_error("set = \"top\"\nname = \"a,b\"\ntype = \"velocity\"\ny = 1\n"),
             Catch::Contains("'loads[0].name' = 'a,b'") && Catch::Contains("must not be empty nor hold a comma"));
  CHECK_THAT(load_error("set = \"grip, upper\"\ntype = \"velocity\"\ny = 1\n"),
             Catch::Contains("'loads[0].set'") && Catch::Contains("give the load a 'name' of its own"));
  CHECK_THAT(load_error("set = \"top\"\ntype = \"velocity\"\ny = { from = [0, 0], to = [0, 0], values = [0, 1] }\n"),
             Catch::Contains("'loads[0].y.to'"));
  CHECK_THAT(load_error("set = \"top\"\ntype = \"velocity\"\ny = \"fast\"\n"),
             Catch::Contains("'loads[0].y' = 'fast': expected a number"));
  CHECK_THAT(load_error("set = \"top\"\nnearest = [0, 0]\ntype = \"fixed\"\n"),
             Catch::Contains("give one of 'set', 'box' and 'nearest'"));
  CHECK_THAT(load_error("nearest = [0]\ntype = \"fixed\"\n"), Catch::Contains("'loads[0].nearest'"));
}

TEST_CASE("model.dual_horizon is read when given and left unset otherwise", "[scene][dual_horizon]") {
  // Unset matters: a particle file whose horizons differ needs the key (horizon_mode.hpp).
  CHECK_FALSE(parse_scene(valid_scene, "dir/scene.toml").dual_horizon.has_value());
  const auto on = parse_scene(std::string(valid_scene) + "[model]\ndual_horizon = true\n", "dir/scene.toml");
  REQUIRE(on.dual_horizon.has_value());
  CHECK(*on.dual_horizon);
  const auto off = parse_scene(std::string(valid_scene) + "[model]\ndual_horizon = false\n", "dir/scene.toml");
  REQUIRE(off.dual_horizon.has_value());
  CHECK_FALSE(*off.dual_horizon);
  CHECK_THAT(error_of(std::string(valid_scene) + "[model]\ndual_horizon = \"yes\"\n"),
             Catch::Contains("'model.dual_horizon' = 'yes'"));
}

// [refinement] needs dual horizons: the refusal says which of the two --set
// gave, and how to give the other there (before 7 December 2026 it named
// the scene file alone, "(got false)" of a --set value, and a [refinement]
// that --set made was blamed on the file, which has none).
TEST_CASE("the refusal of refinement without dual horizons names what --set gave", "[scene][refinement]") {
  const std::string needs = "[refinement] needs model.dual_horizon = true (children have half their parent's "
                            "horizon; dual-horizon PD, theory.md Sec. 6)";
  const std::string refined = std::string(valid_scene) + "[refinement]\nlevels = 1\n";
  CHECK(error_of(refined) == "dir/scene.toml: " + needs + " (not given)");
  CHECK(error_of(refined + "[model]\ndual_horizon = false\n") == "dir/scene.toml: " + needs + " (got false)");
  CHECK(error_of(refined, {"model.dual_horizon=false"}) ==
        "dir/scene.toml, --set: " + needs + " (got false from --set); give --set model.dual_horizon=true");
  // The whole [model] table given by --set gives the key too.
  CHECK(error_of(refined, {"model={dual_horizon = false}"}) ==
        "dir/scene.toml, --set: " + needs + " (got false from --set); give --set model.dual_horizon=true");
  CHECK(error_of(valid_scene, {"refinement.levels=2", "refinement.check_interval=5"}) ==
        "dir/scene.toml, --set: [refinement] (made by --set refinement.check_interval, refinement.levels; the scene "
        "has none) needs model.dual_horizon = true (children have half their parent's horizon; dual-horizon PD, "
        "theory.md Sec. 6) (not given); give --set model.dual_horizon=true");
}

// A key that takes a plain number in a fixed unit refuses a value written
// with a unit by saying its unit and the number to write (before 7 December
// 2026 "expected a number" or "expected an array of numbers", no more).
TEST_CASE("a value with a unit where a key takes a plain number in a fixed unit is refused with the number to write",
          "[scene]") {
  const std::string quasi_static = replaced(valid_scene, "[time]\nstep = 2e-8\nend = 1e-5\n",
                                            "[quasi_static]\nload_factors = [1]\nprogress_interval = 10\n");
  const std::string fixed = replaced(replaced(quasi_static, "type = \"velocity\"\ny = 0.3\nramp_time = 2e-4",
                                              "type = \"displacement\"\ny = 1e-6"),
                                     "table = [[0, 0], [1e-6, 1], [2e-6, 1]]\n", "");
  REQUIRE(parse_scene(fixed, "dir/scene.toml").quasi_static.progress_interval == 10);
  CHECK(error_of(replaced(fixed, "progress_interval = 10", "progress_interval = \"500 ms\"")) ==
        "dir/scene.toml:" + std::to_string(line_of(fixed, "progress_interval")) +
            ": key 'quasi_static.progress_interval' = '500 ms': expected a number: this key is in s and takes a plain "
            "number, no unit; write progress_interval = 0.5");
  // A unit the key's quantity does not know: the example.
  CHECK(error_of(fixed, {"quasi_static.progress_interval=10min"}) ==
        "dir/scene.toml, --set: key 'quasi_static.progress_interval' = '10min': expected a number: this key is in s "
        "and takes a plain number, no unit (e.g. progress_interval = 10)");
  // Positions [m]: the whole array as the key takes it.
  CHECK_THAT(error_of(valid_scene, {"precracks.0.to=['2 mm', 0.0125]"}),
             Catch::EndsWith(": key 'precracks[0].to' = ['2 mm', 0.0125]: expected an array of numbers: this key is "
                             "in m and takes plain numbers, no units; write to = [0.002, 0.0125]"));
  CHECK_THAT(error_of(valid_scene, {"loads.1.box=[0, 0, '1 cm', 1]"}),
             Catch::EndsWith("write box = [0, 0, 0.01, 1]"));
  // A word that is no length: the example.
  CHECK_THAT(error_of(valid_scene, {"precracks.0.from=['left', 0.0125]"}),
             Catch::EndsWith("expected an array of numbers: this key is in m and takes plain numbers, no units (e.g. "
                             "from = [0, 0.0125])"));
  // Keys whose unit is not fixed (a load's components) say what they said.
  CHECK_THAT(error_of(valid_scene, {"loads.0.y='0.3 m/s'"}), Catch::EndsWith(": expected a number, or for a value "
                                                                            "that varies linearly with position "
                                                                            "{ value = ..., gradient = [d/dx, d/dy], "
                                                                            "at = [x, y] } or { from = [x0, y0], to "
                                                                            "= [x1, y1], values = [v0, v1] }"));
}

// Every message is one line: a table in it is written inline, its floats as
// written (before, toml++'s "damage = 0.34999999999999998\nset = 'right'"), and
// a --set key with an empty part is named as such (before, "unknown key ''").
TEST_CASE("scene messages show tables and arrays of tables on one line", "[scene]") {
  const auto one_line = [](const std::string& m) {
    INFO(m);
    CHECK(m.find('\n') == std::string::npos);
    CHECK(m.find('\r') == std::string::npos);
  };
  const auto array_stop = error_of(std::string(valid_scene) + "[[stop]]\ndamage = 0.35\nset = \"right\"\n");
  one_line(array_stop);
  CHECK_THAT(array_stop, Catch::Contains("key 'stop' = [{damage = 0.35, set = 'right'}]: expected a table [stop]"));
  const std::string quasi_static_and_time =
      replaced(valid_scene, "[time]", "[quasi_static]\nload_factors = [0.5, 1.0]\n[time]");
  const auto both = error_of(replaced(quasi_static_and_time, "type = \"velocity\"", "type = \"displacement\""));
  one_line(both);
  CHECK_THAT(both, Catch::Contains("key 'time' = {step = 2e-08, end = 1e-05}: a scene is either dynamic") ||
                       Catch::Contains("key 'time' = {end = 1e-05, step = 2e-08}: a scene is either dynamic"));
  // A string holding a line break or a quote keeps its escapes on the line.
  const auto broken_name = error_of(replaced(valid_scene, "y = 0.3", "y = 0.3\nname = \"a\\nb\""));
  one_line(broken_name);
  CHECK_THAT(broken_name, Catch::Contains("key 'loads[0].name' = \"a\\nb\""));
  const auto quoted_key = error_of(replaced(valid_scene, "[time]", "[time]\n\"st\\tep\" = 1"));
  one_line(quoted_key);
  CHECK_THAT(quoted_key, Catch::Contains("unknown key 'time.\"st\\tep\"' = 1"));
  for (const std::string bad : {".end=1", "time..end=1", "time.=1"}) {
    const auto m = error_of(valid_scene, {bad});
    one_line(m);
    CHECK_THAT(m, Catch::Contains("dir/scene.toml: --set '" + bad + "': the key '" + bad.substr(0, bad.find('=')) +
                                  "' has an empty part"));
  }
}

// Typed-value errors said "FILE, --set: key ..."; an unknown key that --set
// gave was blamed on the file alone ("dir/scene.toml: unknown key 'time.stepp'").
// A key given twice with --set: one value would be dropped (before the second
// sitting of 5 December 2026 the last won without a word).
// A whole number beyond 64 bits was taken as a bare word, and then said to
// have "no unit ... without quotes" (before the second sitting of 5 December 2026).
TEST_CASE("a --set number beyond 64 bits is named as such", "[scene]") {
  CHECK_THAT(error_of(valid_scene, {"time.end=99999999999999999999"}),
             Catch::StartsWith("dir/scene.toml: --set 'time.end=99999999999999999999': 99999999999999999999 is a "
                               "whole number beyond the 64 bits TOML reads"));
  CHECK_THAT(error_of(valid_scene, {"time.end=1e20"}), !Catch::Contains("64 bits"));
  CHECK_THAT(error_of(valid_scene, {"time.step=20ns"}), Catch::Equals("no error"));  // a bare word with a unit
}

TEST_CASE("a key set twice with --set is refused", "[scene]") {
  CHECK_THAT(error_of(valid_scene, {"time.end=1e-5", "time.end=2e-5"}),
             Catch::StartsWith("dir/scene.toml, --set: key 'time.end' is set twice; give it once"));
  CHECK_THAT(error_of(valid_scene, {"time.end=1e-5", "time.step=1e-8"}), !Catch::Contains("twice"));
}

// One load's key written two ways, or a key then the table or array that holds
// it: the last won without a word (before 7 December 2026).
TEST_CASE("a key set twice with --set by two spellings, or replaced by its table, is refused", "[scene]") {
  CHECK_THAT(error_of(valid_scene, {"loads.0.y=0.5", "loads.top.y=0.6"}),
             Catch::Equals("dir/scene.toml, --set: key 'loads.top.y' is set twice (as 'loads.0.y' and "
                           "'loads.top.y', both loads[0].y); give it once"));
  CHECK_THAT(error_of(valid_scene, {"precracks.0.to=[0.003, 0.0125]", "precracks.00.to=[0.004, 0.0125]"}),
             Catch::StartsWith("dir/scene.toml, --set: key 'precracks.00.to' is set twice (as 'precracks.0.to' and "
                               "'precracks.00.to', both precracks[0].to)"));
  CHECK_THAT(error_of(valid_scene, {"time.end=2e-5", "time={step = 1e-8, end = 3e-5}"}),
             Catch::Equals("dir/scene.toml, --set: key 'time' replaces the whole of 'time', dropping the earlier "
                           "--set of 'time.end'; give 'time' first, or that key inside its value"));
  CHECK_THAT(error_of(valid_scene, {"loads.top.y=0.5", "loads=[{set = \"top\", type = \"fixed\"}]"}),
             Catch::Contains("key 'loads' replaces the whole of 'loads', dropping the earlier --set of 'loads.top.y'"));
  // Different loads, a table then a key inside it, and a key beside one are fine.
  const auto two_loads = parse_scene(valid_scene, "dir/scene.toml", {"loads.0.y=0.5", "loads.1.y=-5e6"});
  CHECK(two_loads.loads[0].y == 0.5);
  CHECK(two_loads.loads[1].y == -5e6);
  const auto table_then_key =
      parse_scene(valid_scene, "dir/scene.toml", {"time={step = 1e-8, end = 3e-5}", "time.end=4e-5"});
  CHECK(table_then_key.time.end == 4e-5);
  CHECK(table_then_key.time.step == 1e-8);
  CHECK_THAT(error_of(valid_scene, {"time.end=2e-5", "time.endx=1"}), !Catch::Contains("replaces"));
}

// "time.end = 1e-6", as a TOML line is written, made a key 'end ' that was
// refused as unknown, and " strain" a plane ' strain' (before 7 December 2026).
TEST_CASE("a --set with blanks around the key, its dots and a bare word reads as without them", "[scene]") {
  const auto spaced = parse_scene(valid_scene, "dir/scene.toml",
                                  {"time.end = 3e-5", " loads . top . y=0.7", "material.plane= strain"});
  CHECK(spaced.time.end == 3e-5);
  CHECK(spaced.loads[0].y == 0.7);
  CHECK(spaced.material.plane == pd::solver::PlaneKind::strain);
  CHECK(spaced.set_keys.count("time.end") == 1);  // its messages say ", --set"
  CHECK_THAT(error_of(valid_scene, {"time.end = 3e-5", "time.end=4e-5"}),
             Catch::Equals("dir/scene.toml, --set: key 'time.end' is set twice; give it once"));
  CHECK_THAT(error_of(valid_scene, {"time. =1"}), Catch::Contains("has an empty part"));
}

// A line break in a --set value made a second TOML line, which was dropped:
// time.end was set and step=1 ignored, exit 0 (before 7 December 2026).
TEST_CASE("a --set value holding a line break with a second key-value pair is refused", "[scene]") {
  const auto m = error_of(valid_scene, {"time.end=2e-5\nstep=1"});
  CHECK_THAT(m, Catch::Equals("dir/scene.toml: --set \"time.end=2e-5\\nstep=1\": the value \"2e-5\\nstep=1\" holds "
                              "more than one TOML key-value pair (a line break in it?); give one value per --set"));
  CHECK(m.find('\n') == std::string::npos);
  // A value that TOML reads over several lines is one value.
  const auto multi_line = parse_scene(valid_scene, "dir/scene.toml", {"output.damage_thresholds=[0.2,\n0.5]"});
  CHECK(multi_line.output.damage_thresholds == std::vector<double>{0.2, 0.5});
}

TEST_CASE("an unknown key that --set gave is blamed on --set", "[scene]") {
  CHECK_THAT(error_of(valid_scene, {"time.stepp=1e-8"}),
             Catch::StartsWith("dir/scene.toml, --set: unknown key 'time.stepp' = 1e-08"));
  CHECK_THAT(error_of(valid_scene, {"loads.top.z=1"}),
             Catch::StartsWith("dir/scene.toml, --set: unknown key 'loads[0].z' = 1"));
  CHECK_THAT(error_of(valid_scene, {"outputs.x=1"}),
             Catch::StartsWith("dir/scene.toml, --set: unknown key 'outputs' = {x = 1}"));
  CHECK_THAT(error_of(valid_scene, {"loads=[{set = \"top\", type = \"fixed\", z = 1}]"}),
             Catch::StartsWith("dir/scene.toml, --set: unknown key 'loads[0].z' = 1"));
  // A key of the file is still the file's, next to a --set one.
  const std::string stepp = replaced(valid_scene, "end = 1e-5", "end = 1e-5\nstepp = 1");
  CHECK_THAT(error_of(stepp, {"time.step=1e-8"}),
             Catch::StartsWith("dir/scene.toml:" + std::to_string(line_of(stepp, "stepp")) +
                               ": unknown key 'time.stepp' = 1"));
}

// A table that --set made lacks a key: the message named the file alone, as if
// the scene's own table lacked it (before 7 December 2026; a required key of
// such a table said ", --set" already).
TEST_CASE("a key missing from a table that --set made is blamed on --set", "[scene]") {
  CHECK_THAT(error_of(valid_scene, {"stop.damage=0.5"}),
             Catch::StartsWith("dir/scene.toml, --set: missing key 'stop.set': give 'set'"));
  CHECK_THAT(error_of(valid_scene, {"loads=[{set = \"top\", type = \"velocity\"}]"}),
             Catch::Equals("dir/scene.toml, --set: loads[0] (velocity): give at least one of 'x', 'y'"));
  // The scene's own tables stay the file's.
  CHECK_THAT(error_of(std::string(valid_scene) + "[stop]\ndamage = 0.5\n"),
             Catch::StartsWith("dir/scene.toml: missing key 'stop.set'"));
  CHECK_THAT(error_of(replaced(valid_scene, "y = 0.3\n", "")),
             Catch::StartsWith("dir/scene.toml: loads[0] (velocity): give at least one of 'x', 'y'"));
}

// A NUL in the particle path opened the file named by the part before it
// (exit 0, the NUL in summary.json); one in a load name went into the header
// of energy.csv. Every control character is refused in paths and names,
// shown escaped.
TEST_CASE("paths and names with a NUL or another control character are refused, the character escaped", "[scene]") {
  const auto nul_path = error_of(replaced(valid_scene, "particles = \"plate.pdp\"", "particles = \"plate.pdp\\u0000x\""));
  CHECK_THAT(nul_path, Catch::StartsWith("dir/scene.toml:2: key 'particles' = \"plate.pdp\\u0000x\": a path must not "
                                         "hold a control character (here \\u0000, its character 10)"));
  CHECK(nul_path.find('\0') == std::string::npos);
  CHECK_THAT(error_of(valid_scene, {"particles=\"p\\u001b.pdp\""}),
             Catch::StartsWith("dir/scene.toml, --set: key 'particles' = \"p\\u001B.pdp\": a path must not hold a "
                               "control character (here \\u001B, its character 2)"));
  const auto nul_name = error_of(replaced(valid_scene, "y = 0.3", "y = 0.3\nname = \"a\\u0000b\""));
  CHECK_THAT(nul_name, Catch::Contains("key 'loads[0].name' = \"a\\u0000b\": a load's name heads the reaction columns") &&
                           Catch::Contains("(here \\u0000, its character 2)"));
  CHECK(nul_name.find('\0') == std::string::npos);
  CHECK_THAT(error_of(replaced(valid_scene, "y = 0.3", "y = 0.3\nname = \"bell\\u0007\"")),
             Catch::Contains("'loads[0].name' = \"bell\\u0007\"") && Catch::Contains("(here \\u0007, its character 5)"));
  // A set name: the load would take it as its name; in [stop] it is refused the same way.
  CHECK_THAT(error_of(replaced(valid_scene, "set = \"top\"", "set = \"to\\u0000p\"\nname = \"pull\"")),
             Catch::Contains("key 'loads[0].set' = \"to\\u0000p\": a set name must not hold a control character"));
  CHECK_THAT(error_of(std::string(valid_scene) + "[stop]\nset = \"right\\u007f\"\n"),
             Catch::Contains("key 'stop.set' = \"right\\u007F\": a set name must not hold a control character "
                             "(here \\u007F, its character 6)"));
}
