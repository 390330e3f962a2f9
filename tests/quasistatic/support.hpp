#pragma once
// Shared helpers of the quasi-static tests: temporary folders and scenes in code.
#include <unistd.h>

#include <filesystem>
#include <string>

#include "scene.hpp"
#include "strip_stiffness.hpp"
#include "../test_folder.hpp"

namespace pd::quasistatic::test {

// A fresh, empty folder under the build tree for one test (one parent per
// process: CTest runs test cases in parallel).
inline std::string fresh_folder(const std::string& name) { return pd::test_support::fresh_folder_under(PD_QS_TEST_TMPDIR, name); }

// A quasi-static scene in code: PMMA-like material (C1/C2 of docs/validation.md),
// one load step, no loads yet.
inline solver::Scene quasi_static_scene(bool damage = false) {
  solver::Scene s;
  s.path = "test-scene.toml";
  s.particle_file = "in-memory";
  s.material.youngs_modulus = 3.24e9;
  s.material.fracture_energy = 200;
  s.effects.damage = damage;
  s.effects.surface_correction = false;
  s.quasi_static.enabled = true;
  s.quasi_static.load_factors = {1.0};
  s.quasi_static.tolerance = 1e-10;
  return s;
}

using pd::validation::x_displacement;  // one owner: validation/strip_stiffness

inline solver::LoadSpec fixed(const std::string& set) {
  solver::LoadSpec l;
  l.name = set;
  l.kind = solver::LoadKind::fixed;
  l.region.set = set;
  l.has_x = l.has_y = true;
  return l;
}

}  // namespace pd::quasistatic::test
