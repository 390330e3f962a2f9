#include "strip_stiffness.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"
#include "ncg.hpp"
#include "quasi_static_problem.hpp"
#include "simulation.hpp"

namespace pd::validation {

namespace {
constexpr double youngs_modulus = 3.24e9;  // [Pa]

// Least-squares slope of v over s.
double slope(const std::vector<double>& s, const std::vector<double>& v) {
  const double n = static_cast<double>(s.size());
  double ss = 0, sv = 0, sss = 0, ssv = 0;
  for (std::size_t k = 0; k < s.size(); ++k) ss += s[k], sv += v[k], sss += s[k] * s[k], ssv += s[k] * v[k];
  return (n * ssv - ss * sv) / (n * sss - ss * ss);
}
}  // namespace

solver::Scene strip_scene(bool surface_correction, const std::vector<solver::LoadSpec>& loads) {
  solver::Scene s;
  s.path = "strip (validation)";
  s.particle_file = "in-memory";
  s.material.youngs_modulus = youngs_modulus;
  s.material.density = 1190;
  s.material.fracture_energy = 200;
  s.effects.damage = false;
  s.effects.surface_correction = surface_correction;
  s.time.automatic = true;
  s.time.end = 1e-6;
  s.quasi_static.enabled = true;
  s.quasi_static.load_factors = {1.0};
  s.quasi_static.tolerance = 1e-10;
  s.quasi_static.max_iterations = 100000;
  s.loads = loads;
  return s;
}

solver::LoadSpec x_displacement(const std::string& set, double value) {
  solver::LoadSpec l;
  l.name = set;
  l.kind = solver::LoadKind::displacement;
  l.region.set = set;
  l.has_x = true;
  l.x = value;
  return l;
}

ImposedStrainModuli imposed_strain_moduli(const ParticleSet& p, const solver::Scene& scene) {
  auto dynamic = scene;  // the strain energies of the dynamic kernels (lattice and lists), no time loop
  dynamic.quasi_static = {};
  dynamic.loads.clear();
  solver::Simulation sim(dynamic, p);
  const double nu = sim.model().model_poisson_ratio, eps = 1e-6;
  const double x_mid = 0.5 * (p.xmin + p.xmax), quarter = 0.25 * (p.xmax - p.xmin);
  const auto modulus_error = [&](double exx, double eyy) {
    std::vector<double> ux(p.size()), uy(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) ux[i] = exx * p.x[i], uy[i] = eyy * p.y[i];
    sim.set_displacements(ux, uy);
    const auto w = sim.strain_energy_density();
    double energy = 0, area = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (std::fabs(p.x[i] - x_mid) <= quarter) energy += p.volume[i] * w[i], area += p.volume[i];
    return energy / (area * 0.5 * scene.material.youngs_modulus * eps * eps) - 1;
  };
  return {modulus_error(eps, -nu * eps), modulus_error(-nu * eps, eps)};
}

TensileTest tensile_test(const ParticleSet& p, const solver::Scene& scene, const std::string& reaction_load,
                         double body_xmin, double body_xmax) {
  solver::QuasiStaticProblem problem(scene, p);
  std::vector<double> u;
  problem.set_load_factor(1.0, u);
  solver::NcgSettings settings;
  settings.tolerance = scene.quasi_static.tolerance;
  settings.max_iterations = scene.quasi_static.max_iterations;
  const auto result = solver::minimise_energy(problem, u, settings);
  if (!result.converged)
    throw Error("tensile test: no convergence (relative residual " + std::to_string(result.relative_residual()) + ")");
  TensileTest t;
  t.iterations = result.iterations;
  const std::size_t n = p.size();
  const double x_mid = 0.5 * (body_xmin + body_xmax), quarter = 0.25 * (body_xmax - body_xmin);
  std::vector<double> x, ux, y, uy;
  double ymin = INFINITY, ymax = -INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.x[i] < body_xmin || p.x[i] > body_xmax) continue;
    const double half = 0.5 * p.cell_size[i];
    ymin = std::min(ymin, p.y[i] - half), ymax = std::max(ymax, p.y[i] + half);
    if (std::fabs(p.x[i] - x_mid) > quarter) continue;
    x.push_back(p.x[i]), ux.push_back(u[i]), y.push_back(p.y[i]), uy.push_back(u[n + i]);
  }
  t.strain = slope(x, ux);
  t.lateral_strain = slope(y, uy);
  const auto& loads = problem.loads();
  const auto load = std::find_if(loads.begin(), loads.end(), [&](const auto& l) { return l.spec.name == reaction_load; });
  if (load == loads.end()) throw Error("tensile test: no load named '" + reaction_load + "'");
  t.reaction = problem.reactions()[static_cast<std::size_t>(load - loads.begin())].reaction_x;
  t.stress = t.reaction / ((ymax - ymin) * scene.material.thickness);
  return t;
}

}  // namespace pd::validation
