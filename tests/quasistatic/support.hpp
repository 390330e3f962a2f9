#pragma once
// Shared helpers of the quasi-static tests: temporary folders and scenes in code.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "plate_grid.hpp"
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

// A coarse NB-NUG grid of the C1 plate: non-uniform cells near the hole, where
// the dynamic kernel's bond stiffnesses are not symmetric.
inline ParticleSet coarse_c1_nbnug() {
  return validation::make_plate_grid({PD_C1_GEOMETRY, GridKind::nbnug, 4e-4, 1.2e-3, Quadrature::analytic});
}

// A smooth field at a strain of about 1e-3 with particle-to-particle noise
// (so that the residual is far from 0 everywhere): [u_x of all, u_y of all].
inline std::vector<double> test_field(const ParticleSet& p) {
  const std::size_t n = p.size();
  std::vector<double> u(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    u[i] = 1e-3 * p.x[i] + 2e-6 * std::sin(3e3 * p.y[i]) + 1e-7 * std::sin(1.7 * i);
    u[n + i] = -4e-4 * p.y[i] + 1e-6 * std::cos(2e3 * p.x[i]) + 1e-7 * std::cos(2.3 * i);
  }
  return u;
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
