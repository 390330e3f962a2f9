#pragma once
// Shared helpers of the quasi-static tests: temporary folders and scenes in code.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fstream>

#include "calculix.hpp"
#include "fem_mesh.hpp"
#include "gmsh_session.hpp"
#include "plate_grid.hpp"
#include "quasi_static_problem.hpp"
#include "scene.hpp"
#include "strip_stiffness.hpp"
#include "../test_folder.hpp"

namespace pd::quasistatic::test {

// Euclidean norm of a vector, and of the difference of two.
inline double norm(const std::vector<double>& a) {
  double s = 0;
  for (double v : a) s += v * v;
  return std::sqrt(s);
}

inline double difference(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t k = 0; k < a.size(); ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(s);
}

// The residuals of one field on the energy table (`lists`) and on the lattice
// kernels (`fast`: its float pass, then its double pass), both at load factor 1,
// and the table's residual norm as the scale of their differences.
struct ResidualsOfBothPaths {
  std::vector<double> lists, fast, fast_double;
  double scale = 0;
};

inline ResidualsOfBothPaths residuals_of_both_paths(solver::QuasiStaticProblem& lists, solver::QuasiStaticProblem& fast,
                                                    std::vector<double>& u) {
  ResidualsOfBothPaths r;
  lists.set_load_factor(1.0, u);
  fast.set_load_factor(1.0, u);
  lists.residual(u, r.lists);
  fast.residual(u, r.fast);
  fast.set_double_residual(true);
  fast.residual(u, r.fast_double);
  r.scale = norm(r.lists);
  return r;
}

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

// A displacement load along y on a set of the particle file (`value` [m] at load factor 1).
inline solver::LoadSpec y_displacement(const std::string& set, double value) {
  solver::LoadSpec l;
  l.name = set;
  l.kind = solver::LoadKind::displacement;
  l.region.set = set;
  l.has_y = true;
  l.y = value;
  return l;
}

// The scene of test_quasi_static_restart.cpp in code, on the 4 mm x 2 mm
// plate (dx = 0.1 mm, delta = 0.3 mm; make_rectangle_lattice(4e-3, 2e-3,
// 1e-4, 3e-4)) with a 1.5 mm edge pre-crack at mid-height, its top and bottom
// strips pulled apart by +-7.8 um x the load factor: some pairs break ahead
// of the crack tip at 1.0, the crack runs at 1.1. Damage and surface
// correction on, tolerance 1e-8; the load factors are the caller's.
inline solver::Scene precracked_plate_scene() {
  solver::Scene s = quasi_static_scene(true);
  s.effects.surface_correction = true;
  s.loads = {y_displacement("top", 7.8e-6), y_displacement("bottom", -7.8e-6)};
  s.precracks = {{{0.0, 1e-3}, {1.5e-3, 1e-3}}};
  s.quasi_static.tolerance = 1e-8;
  return s;
}

// The scene on the dynamic solver's kernels (quasi_static.kernels = "lattice").
inline solver::Scene lattice_scene(solver::Scene scene) {
  scene.quasi_static.lattice_kernels = true;
  return scene;
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

// The C1 plate (20 mm x 20 mm) with a hole of radius 0.01 mm at its centre,
// written as a .geo into `folder` and read back (metres).
inline PlateGeometry tiny_hole_plate(const std::string& folder) {
  // Far from the hole the field is the homogeneous one to (0.01 / r)^2.
  const std::string geo = folder + "/tiny_hole.geo";
  std::ofstream f(geo);
  f << "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0}; Point(4) = {0, 20, 0};\n"
       "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
       "Curve Loop(1) = {1, 2, 3, 4};\n"
       "Point(5) = {10, 10, 0}; Point(6) = {10.01, 10, 0}; Point(7) = {10, 10.01, 0}; Point(8) = {9.99, 10, 0};\n"
       "Point(9) = {10, 9.99, 0};\n"
       "Circle(5) = {6, 5, 7}; Circle(6) = {7, 5, 8}; Circle(7) = {8, 5, 9}; Circle(8) = {9, 5, 6};\n"
       "Curve Loop(2) = {5, 6, 7, 8};\nPlane Surface(1) = {1, 2};\n";
  f.close();
  GmshSession session;
  return load_plate_geometry(session, geo, 1e-3, 1e-4);
}

// The tiny-hole plate's CalculiX solution, pulled at -/+ 1e-7 m on its left and
// right edges (E = 3.24 GPa, plane stress), meshed at `hole_size` at the hole
// and 1 mm far from it.
struct TinyHoleFem {
  validation::FemMesh mesh;
  validation::FemSolution solution;
  validation::FemLoadCase load;
};
inline TinyHoleFem tiny_hole_fem(const std::string& folder, double hole_size, const std::string& job,
                                 double section_thickness = validation::FemLoadCase{}.section_thickness) {
  using namespace validation;
  const auto plate = tiny_hole_plate(folder);
  FemMeshOptions mesh_options;
  mesh_options.hole_size = hole_size;
  mesh_options.far_size = 1e-3;
  mesh_options.grading_distance = 4e-3;
  TinyHoleFem fem;
  fem.mesh = write_fem_mesh(plate, mesh_options, folder + "/" + job + "_mesh.inp");
  fem.load.youngs_modulus = 3.24e9;
  fem.load.left_ux = -1e-7;
  fem.load.right_ux = 1e-7;
  fem.load.section_thickness = section_thickness;
  fem.solution = run_calculix(fem.mesh, plate, fem.load, job);
  return fem;
}

}  // namespace pd::quasistatic::test
