#pragma once
// Shared helpers of the solver tests: small plates and scenes.
#include <unistd.h>

#include <filesystem>
#include <string>

#include "lattice.hpp"
#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::solver::test {

// A fresh, empty folder under the build tree for one test (one parent folder
// per process: CTest runs test cases in parallel).
inline std::string fresh_folder(const std::string& name) {
  const auto path = std::filesystem::path(PD_SOLVER_TEST_TMPDIR) / std::to_string(::getpid()) / name;
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path.string();
}

// A scene in code: PMMA-like material, no loads, automatic time step.
inline Scene basic_scene(double end_time = 1e-6) {
  Scene s;
  s.path = "test-scene.toml";
  s.particle_file = "in-memory";
  s.material.youngs_modulus = 3.24e9;
  s.material.density = 1190;
  s.material.fracture_energy = 200;
  s.material.poisson_ratio = 0.35;
  s.effects.damage = false;
  s.effects.surface_correction = false;
  s.time.automatic = true;
  s.time.safety = 0.8;
  s.time.end = end_time;
  return s;
}

// Writes a lattice plate as a particle file and returns its path.
inline std::string write_plate(const std::string& folder, const std::string& name, double width, double height,
                               double spacing, double horizon) {
  const auto p = make_rectangle_lattice(width, height, spacing, horizon, Quadrature::analytic);
  const std::string path = (std::filesystem::path(folder) / name).string();
  write_particle_file(path, p);
  return path;
}

}  // namespace pd::solver::test
