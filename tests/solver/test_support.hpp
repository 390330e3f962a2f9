#pragma once
// Shared helpers of the solver tests: small plates and scenes.
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bond_setup.hpp"
#include "compact_families.hpp"
#include "force_field.hpp"
#include "lattice.hpp"
#include "particle_file.hpp"
#include "particle_state.hpp"
#include "refinement.hpp"
#include "run.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "../c1_plate.hpp"
#include "../test_folder.hpp"

namespace pd::solver::test {

// Options of a run inside a test: no progress lines, the plan and report
// into `log` (the tests read it), outputs into `output_dir` (empty: none).
inline RunOptions quiet_options(std::ostream& log, const std::string& output_dir = "") {
  RunOptions options;
  options.show_progress = false;
  options.log = &log;
  options.output_dir = output_dir;
  return options;
}

// A fresh, empty folder under the build tree for one test (one parent folder
// per process: CTest runs test cases in parallel).
inline std::string fresh_folder(const std::string& name) { return pd::test_support::fresh_folder_under(PD_SOLVER_TEST_TMPDIR, name); }

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

// Runs pd-mesh on geometries/GEOMETRY with `arguments` (spacing, horizon,
// grid kind) and returns the path of the particle file it wrote in `folder`:
// the mesher's own output, exactly as a user gets it.
inline std::string pd_mesh(const std::string& folder, const std::string& geometry, const std::string& arguments) {
  const std::string out = (std::filesystem::path(folder) / "particles.pdp").string();
  const std::string command = std::string("\"") + PD_MESH_EXECUTABLE + "\" \"" + PD_GEOMETRY_DIR + "/" + geometry +
                              "\" " + arguments + " -o \"" + out + "\" > \"" + folder + "/pd-mesh.log\" 2>&1";
  if (std::system(command.c_str()) != 0) throw std::runtime_error("pd-mesh failed: " + command);
  return out;
}

// A smooth velocity field [m/s] over a width x height [m] plate that excites
// many modes at once (the conservation tests).
inline void set_smooth_velocities(Simulation& sim, const ParticleSet& p, double width, double height) {
  std::vector<double> vx(p.size()), vy(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    vx[i] = 0.5 * std::sin(M_PI * p.x[i] / width) + 0.2 * std::cos(M_PI * p.y[i] / height);
    vy[i] = 0.3 * std::cos(M_PI * p.x[i] / width) * std::sin(M_PI * p.y[i] / height);
  }
  sim.set_velocities(vx, vy);
}

// Linear momentum per unit thickness (x, y) and the sum of |m v|, its scale [kg/s].
inline std::array<double, 3> momentum_of(const Simulation& sim, const ParticleSet& p, double density) {
  double px = 0, py = 0, magnitude = 0;
  const auto& k = sim.kinematics();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double m = density * p.volume[i];
    px += m * k.vx[i], py += m * k.vy[i];
    magnitude += m * std::hypot(k.vx[i], k.vy[i]);
  }
  return {px, py, magnitude};
}

// A plate [0, width] x [0, height] of dx squares whose right half is refined
// `factor` times, each square with the horizon m x its own side, analytic
// partial volumes (refinement.hpp): two horizons meeting at x = width / 2.
inline ParticleSet half_refined_plate(double width, double height, double dx, double m, int factor) {
  RefinementRegion r;
  r.x0 = 0.5 * width, r.y0 = 0, r.x1 = width, r.y1 = height;
  r.factor = factor;
  return make_refined_rectangle_lattice(width, height, dx, m * dx, r, Quadrature::analytic);
}

// Internal force densities [N/m^3] of `scene`'s model for the displacement
// field u(x, y) -> pair (u_x, u_y) [m], on the neighbour lists.
template <class Field>
std::pair<std::vector<double>, std::vector<double>> internal_forces(const Scene& scene, const ParticleSet& p,
                                                                    Field u) {
  const auto setup = build_bond_setup(scene, p, compact_families(p), {});
  auto field = make_force_field(scene, p, setup, false);
  auto state = state_at_rest(p, scene.output.damage_thresholds.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto [ux, uy] = u(p.x[i], p.y[i]);
    state.motion.ux[i] = ux;
    state.motion.uy[i] = uy;
  }
  field->compute(state);
  return {state.motion.fx, state.motion.fy};
}

// Random velocities in [-amplitude, amplitude] [m/s] from `seed`, `steps`
// steps of `sim`: the change of linear momentum over the sum of |m v| (the
// dual property's check; the run must stay finite).
inline double momentum_change_over_steps(Simulation& sim, const ParticleSet& p, double density, double amplitude,
                                         unsigned seed, int steps) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> velocity(-amplitude, amplitude);
  std::vector<double> vx(p.size()), vy(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) vx[i] = velocity(random), vy[i] = velocity(random);
  sim.set_velocities(vx, vy);
  const auto p0 = momentum_of(sim, p, density);
  for (int s = 0; s < steps; ++s) sim.step();
  if (sim.non_finite().found) throw std::runtime_error("the run became non-finite");
  const auto p1 = momentum_of(sim, p, density);
  return std::hypot(p1[0] - p0[0], p1[1] - p0[1]) / p0[2];
}

// momentum_change_over_steps from seed 12345 over 300 steps with every bond
// on the neighbour lists (double precision; the lattice sweep, which
// dual-horizon PMB runs use for their constant-horizon squares, conserves
// momentum to float round-off only): the change of the total momentum over
// the sum of |m v|, and the directed bonds broken by then.
inline std::pair<double, std::uint64_t> momentum_change_on_lists(const Scene& scene, const ParticleSet& p,
                                                                 double amplitude) {
  SetupOptions lists;
  lists.lattice_kernel = false;
  Simulation sim(scene, p, lists);
  const double change = momentum_change_over_steps(sim, p, scene.material.density, amplitude, 12345, 300);
  return {change, sim.broken_bond_count()};
}

// A velocity load in y [m/s] on a named set, ramped up linearly over ramp_time [s].
inline LoadSpec ramped_y_velocity(const std::string& set, double vy, double ramp_time) {
  LoadSpec l;
  l.kind = LoadKind::velocity;
  l.region.set = set;
  l.has_y = true;
  l.y = vy;
  l.time_function.kind = TimeFunction::Kind::ramp;
  l.time_function.ramp_time = ramp_time;
  return l;
}

// A smooth displacement field (ux, uy) [m] with strains of about 1e-4 and
// rotations over the plate: every bond stretched differently.
inline std::pair<std::vector<double>, std::vector<double>> smooth_field(const ParticleSet& p) {
  const double xc = 0.5 * (p.xmin + p.xmax), yc = 0.5 * (p.ymin + p.ymax), L = p.xmax - p.xmin;
  std::vector<double> ux(p.size()), uy(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x = p.x[i] - xc, y = p.y[i] - yc;
    ux[i] = 1e-4 * x + 2e-4 * y * y / L + 5e-5 * L * std::sin(7 * y / L);
    uy[i] = -3e-5 * y + 1e-4 * x * y / L + 4e-5 * L * std::cos(5 * x / L);
  }
  return {ux, uy};
}

// The C1 plate with its hole as an NB-NUG grid at dx = 0.25 mm, delta = 1 mm
// (or `delta`): lattice squares away from the hole, free gmsh cells
// (polygons) around it, squares off the stencil along the edges.
inline pd::ParticleSet plate_with_hole(double delta = 1e-3) {
  return pd::test_support::c1_plate_nbnug(0.25e-3, delta, pd::Quadrature::analytic);
}

}  // namespace pd::solver::test
