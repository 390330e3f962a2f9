#include "c1_comparison.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "dual_horizon_statics.hpp"
#include "error.hpp"
#include "lattice.hpp"
#include "loading_layer.hpp"
#include "plate_grid.hpp"
#include "simulation.hpp"
#include "ncg.hpp"
#include "quasi_static_problem.hpp"

namespace pd::validation {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The C1 scene, in code: the same keys a scene file would give (docs/scenes.md).
solver::Scene c1_scene(const C1Material& material, const PdOptions& options) {
  solver::Scene s;
  s.path = "C1 (validation)";
  s.particle_file = "in-memory";
  s.material.youngs_modulus = material.youngs_modulus;
  s.material.fracture_energy = material.fracture_energy;
  s.model = options.model;
  if (options.model == solver::ModelType::osb) s.material.poisson_ratio = material.poisson_ratio;
  s.material.plane = solver::PlaneKind::stress;
  s.bond_weights = options.bond_weights;
  s.effects.damage = false;
  s.effects.surface_correction = options.surface_correction;
  s.quasi_static.enabled = true;
  s.quasi_static.load_factors = {1.0};
  s.quasi_static.tolerance = options.tolerance;
  s.quasi_static.max_iterations = options.max_iterations;
  s.loads = options.loading == C1Loading::layers
                ? opposite_edge_displacements(material.edge_displacement, loading_layer_set_name("left"),
                                              loading_layer_set_name("right"))
                : opposite_edge_displacements(material.edge_displacement);
  if (options.dual_horizon) {
    if (options.surface_correction)
      throw Error("C1: dual-horizon runs have no surface correction (theory.md Sec. 6); turn it off");
    s.dual_horizon = true;
    s.quasi_static.enabled = false;  // the linear solution of dual_horizon_statics.hpp instead
  }
  return s;
}

void accumulate(ErrorStats& s, double d, double& sum_squares, std::size_t& count) {
  s.max_abs = std::max(s.max_abs, std::fabs(d));
  sum_squares += d * d;
  ++count;
}

void finish(ErrorStats& s, double sum_squares, std::size_t count, double reference) {
  s.rms = count ? std::sqrt(sum_squares / count) : 0;
  s.max_rel = s.max_abs / reference;
  s.rms_rel = s.rms / reference;
}

}  // namespace

const char* to_string(C1Loading loading) { return loading == C1Loading::layers ? "layers" : "strips"; }

ParticleSet c1_particles(const PlateGridSpec& spec, C1Loading loading, PlateGeometry* geometry) {
  LoadingLayers layers;
  if (loading == C1Loading::layers) layers.edges = {"left", "right"};
  return make_plate_grid(spec, geometry, layers);
}

PdSolution solve_c1_pd(const ParticleSet& particles, const C1Material& material, const PdOptions& options) {
  const auto scene = c1_scene(material, options);
  PdSolution out;
  if (options.dual_horizon) {
    const double u = material.edge_displacement;
    auto r = solve_dual_horizon_static(scene, particles, {{"left", -u}, {"right", u}}, options.tolerance,
                                       options.max_iterations);
    if (!r.converged)
      throw Error("C1: the linear dual-horizon solution did not converge: relative residual " +
                  std::to_string(r.relative_residual) + " after " + std::to_string(r.iterations) + " iterations");
    out.ux = std::move(r.ux);
    out.uy = std::move(r.uy);
    out.reaction_x = r.reaction_x.at(1);
    out.iterations = r.iterations;
    out.relative_residual = r.relative_residual;
    out.setup_seconds = r.setup_seconds;
    out.solve_seconds = r.solve_seconds;
    // W_i at the solution from the dual-horizon force field (theory.md
    // Sec. 6), for the plate's rows and the hole's energy density.
    auto dynamic = scene;
    dynamic.loads.clear();
    solver::Simulation energies(dynamic, particles);
    energies.set_displacements(out.ux, out.uy);
    out.strain_energy_density = energies.strain_energy_density();
    return out;
  }
  auto start = std::chrono::steady_clock::now();
  solver::QuasiStaticProblem problem(scene, particles);
  out.setup_seconds = seconds_since(start);
  start = std::chrono::steady_clock::now();
  std::vector<double> u;
  problem.set_load_factor(1.0, u);
  solver::NcgSettings settings;
  settings.tolerance = options.tolerance;
  settings.max_iterations = options.max_iterations;
  const auto result = solver::minimise_energy(problem, u, settings);
  out.solve_seconds = seconds_since(start);
  if (!result.converged)
    throw Error("C1: the PD minimisation did not converge: relative residual " +
                std::to_string(result.relative_residual()) + " after " + std::to_string(result.iterations) +
                " iterations");
  out.iterations = result.iterations;
  out.relative_residual = result.relative_residual();
  const std::size_t n = particles.size();
  out.ux.assign(u.begin(), u.begin() + static_cast<std::ptrdiff_t>(n));
  out.uy.assign(u.begin() + static_cast<std::ptrdiff_t>(n), u.end());
  out.reaction_x = problem.reactions().at(1).reaction_x / scene.material.thickness;
  out.strain_energy_density = problem.strain_energy_density(u);
  return out;
}

PlateOnly plate_only(const ParticleSet& p, const PdSolution& pd, const PlateGeometry& geometry) {
  PlateOnly out;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!in_loading_layer(p, geometry, i)) out.source.push_back(i);
  // The plate's own bounding box: the layers lie outside it.
  out.particles = pd::empty_like(p);
  auto& q = out.particles;
  q.xmin = geometry.xmin, q.xmax = geometry.xmax, q.ymin = geometry.ymin, q.ymax = geometry.ymax;
  out.pd = pd;
  out.pd.ux.clear(), out.pd.uy.clear(), out.pd.strain_energy_density.clear();
  for (const auto i : out.source) {
    pd::append_particle(q, p, i);
    out.pd.ux.push_back(pd.ux[i]);
    out.pd.uy.push_back(pd.uy[i]);
    out.pd.strain_energy_density.push_back(pd.strain_energy_density[i]);
  }
  return out;
}

FemReference solve_c1_fem(const PlateGeometry& geometry, const C1Material& material, double clamp_width,
                          double hole_size, const std::string& folder, const std::string& job_name) {
  std::filesystem::create_directories(folder);
  FemReference fem;
  const auto start = std::chrono::steady_clock::now();
  FemMeshOptions mesh_options;
  mesh_options.hole_size = hole_size;
  mesh_options.clamp_width = clamp_width;
  fem.mesh = write_fem_mesh(geometry, mesh_options, (std::filesystem::path(folder) / (job_name + "_mesh.inp")).string());
  fem.mesh_seconds = seconds_since(start);
  fem.mesh_size = hole_size;
  FemLoadCase load;
  load.youngs_modulus = material.youngs_modulus;
  load.poisson_ratio = material.poisson_ratio;
  load.clamp_width = clamp_width;
  load.left_ux = -material.edge_displacement;
  load.right_ux = material.edge_displacement;
  fem.solution = run_calculix(fem.mesh, geometry, load, job_name);
  return fem;
}

FemAtParticles fem_at_particles(const FemReference& fem, const ParticleSet& particles) {
  const FemInterpolator interpolate(fem.mesh);
  FemAtParticles out;
  out.ux.resize(particles.size());
  out.uy.resize(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const auto where = interpolate.locate(particles.x[i], particles.y[i]);
    out.ux[i] = interpolate.value_at(fem.solution.ux, where);
    out.uy[i] = interpolate.value_at(fem.solution.uy, where);
  }
  return out;
}

C1Errors compare_with_fem(const ParticleSet& p, const PdSolution& pd, const FemAtParticles& fem, double hole_cx,
                          double hole_cy, double hole_radius, double near_distance) {
  const std::size_t n = p.size();
  C1Errors e;
  e.particles = n;
  for (std::size_t i = 0; i < n; ++i) e.reference = std::max(e.reference, std::fabs(fem.ux[i]));
  // Rigid translation in y: remove the area-weighted mean of the difference.
  double shift = 0, area = 0;
  for (std::size_t i = 0; i < n; ++i) {
    shift += p.volume[i] * (pd.uy[i] - fem.uy[i]);
    area += p.volume[i];
  }
  shift /= area;
  e.dux.resize(n);
  e.duy.resize(n);
  double sx = 0, sy = 0, snx = 0, sny = 0;
  std::size_t cx = 0, cy = 0, cnx = 0, cny = 0;
  for (std::size_t i = 0; i < n; ++i) {
    e.dux[i] = pd.ux[i] - fem.ux[i];
    e.duy[i] = pd.uy[i] - fem.uy[i] - shift;
    accumulate(e.ux, e.dux[i], sx, cx);
    accumulate(e.uy, e.duy[i], sy, cy);
    if (std::hypot(p.x[i] - hole_cx, p.y[i] - hole_cy) - hole_radius <= near_distance) {
      accumulate(e.ux_near_hole, e.dux[i], snx, cnx);
      accumulate(e.uy_near_hole, e.duy[i], sny, cny);
    }
  }
  e.near_hole_particles = cnx;
  finish(e.ux, sx, cx, e.reference);
  finish(e.uy, sy, cy, e.reference);
  finish(e.ux_near_hole, snx, cnx, e.reference);
  finish(e.uy_near_hole, sny, cny, e.reference);
  return e;
}

}  // namespace pd::validation
