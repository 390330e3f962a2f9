#include "crack_opening.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "error.hpp"
#include "fem_interpolation.hpp"
#include "quasi_static_problem.hpp"

namespace pd::validation {

FemCrack crack_of(const PlateGeometry& g, const CrackCase& c) {
  const double xc = 0.5 * (g.xmin + g.xmax), yc = 0.5 * (g.ymin + g.ymax);
  return {xc - c.crack_half_length, xc + c.crack_half_length, yc};
}

solver::Scene crack_scene(const PlateGeometry& g, const CrackCase& c, solver::OsbFailure failure, bool damage,
                          const std::vector<double>& load_factors) {
  solver::Scene s;
  s.path = "centre-cracked plate (validation)";
  s.particle_file = "in-memory";
  s.model = solver::ModelType::osb;
  s.osb_failure = failure;
  s.material.youngs_modulus = c.youngs_modulus;
  s.material.poisson_ratio = c.poisson_ratio;
  s.material.fracture_energy = c.fracture_energy;
  s.material.plane = solver::PlaneKind::stress;
  s.effects.damage = damage;
  s.effects.surface_correction = false;
  s.quasi_static.enabled = true;
  s.quasi_static.load_factors = load_factors;
  s.quasi_static.tolerance = 1e-8;
  s.quasi_static.max_iterations = 200000;
  for (const auto& [set, sign] : {std::pair{"bottom", -1.0}, std::pair{"top", 1.0}}) {
    solver::LoadSpec l;
    l.name = set;
    l.kind = solver::LoadKind::displacement;
    l.region.set = set;
    l.has_y = true;
    l.y = sign * c.edge_displacement;
    s.loads.push_back(l);
  }
  // Two halves drawn from the centre out: a pre-crack cuts the bonds that meet
  // it at its start but not at its end (docs/scenes.md, "[[precracks]]"), so
  // one segment from tip to tip would be longer at its first tip whenever the
  // tips fall on cell boundaries (as here); two halves end at both tips alike.
  const FemCrack crack = crack_of(g, c);
  const double xc = 0.5 * (crack.x1 + crack.x2);
  s.precracks.push_back({{xc, crack.y}, {crack.x1, crack.y}});
  s.precracks.push_back({{xc, crack.y}, {crack.x2, crack.y}});
  return s;
}

CrackFem solve_crack_fem(const PlateGeometry& g, const CrackCase& c, double strip_width, double tip_size,
                         const std::string& folder, const std::string& job_name) {
  std::filesystem::create_directories(folder);
  const auto start = std::chrono::steady_clock::now();
  CrackedPlateMeshOptions options;
  options.tip_size = tip_size;
  options.strip_width = strip_width;
  CrackFem fem;
  fem.mesh = write_cracked_plate_mesh(g, crack_of(g, c), options,
                                      (std::filesystem::path(folder) / (job_name + "_mesh.inp")).string());
  FemLoadCase load;
  load.youngs_modulus = c.youngs_modulus;
  load.poisson_ratio = c.poisson_ratio;
  load.clamp_width = strip_width;
  load.along_y = true;
  load.bottom_uy = -c.edge_displacement;
  load.top_uy = c.edge_displacement;
  fem.solution = run_calculix(fem.mesh, g, load, job_name);
  fem.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return fem;
}

double fem_face_opening(const CrackFem& fem, const FemCrack& crack, double x) {
  // The doubled nodes on the crack line: at each x one belongs to the upper
  // half's elements and one to the lower's; on the faces under tension the
  // upper one has the larger u_y. The pair nearest to x.
  double best = INFINITY, upper = NAN, lower = NAN;
  const double tolerance = 1e-9;
  for (std::size_t k = 0; k < fem.mesh.x.size(); ++k) {
    if (std::fabs(fem.mesh.y[k] - crack.y) > tolerance) continue;
    for (std::size_t l = k + 1; l < fem.mesh.x.size(); ++l) {
      if (std::fabs(fem.mesh.y[l] - crack.y) > tolerance || std::fabs(fem.mesh.x[l] - fem.mesh.x[k]) > tolerance)
        continue;
      const double d = std::fabs(fem.mesh.x[k] - x);
      if (d < best) {
        best = d;
        upper = std::max(fem.solution.uy[k], fem.solution.uy[l]);
        lower = std::min(fem.solution.uy[k], fem.solution.uy[l]);
      }
    }
  }
  if (!std::isfinite(best)) throw Error("FEM crack opening: the mesh has no doubled nodes on the crack line");
  return upper - lower;
}

CrackPairs crack_pairs(const ParticleSet& p, const FemCrack& crack) {
  // The particles nearest to the line on each side, over the crack: on a
  // uniform grid with the line on a row boundary, the rows at +-dx/2.
  double nearest_above = INFINITY, nearest_below = INFINITY;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.x[i] < crack.x1 || p.x[i] > crack.x2) continue;
    const double d = p.y[i] - crack.y;
    if (d > 0) nearest_above = std::min(nearest_above, d);
    else nearest_below = std::min(nearest_below, -d);
  }
  const double tolerance = 1e-3 * p.spacing;
  std::vector<std::uint32_t> above, below;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (p.x[i] < crack.x1 || p.x[i] > crack.x2) continue;
    if (std::fabs(p.y[i] - crack.y - nearest_above) < tolerance) above.push_back(i);
    if (std::fabs(crack.y - p.y[i] - nearest_below) < tolerance) below.push_back(i);
  }
  const auto by_x = [&](std::uint32_t i, std::uint32_t j) { return p.x[i] < p.x[j]; };
  std::sort(above.begin(), above.end(), by_x);
  std::sort(below.begin(), below.end(), by_x);
  CrackPairs pairs;
  for (const auto i : above) {
    const auto j = std::min_element(below.begin(), below.end(), [&](std::uint32_t a, std::uint32_t b) {
      return std::fabs(p.x[a] - p.x[i]) < std::fabs(p.x[b] - p.x[i]);
    });
    if (j == below.end() || std::fabs(p.x[*j] - p.x[i]) > tolerance) continue;  // no partner at this x
    pairs.above.push_back(i);
    pairs.below.push_back(*j);
  }
  if (pairs.above.empty()) throw Error("crack opening: no particle pairs straddle the crack line");
  return pairs;
}

std::vector<OpeningRow> opening_profile(const ParticleSet& p, const CrackPairs& pairs, const std::vector<double>& u,
                                        const std::vector<double>& damage, const CrackFem& fem) {
  const FemInterpolator interpolate(fem.mesh);
  const std::size_t n = p.size();
  std::vector<OpeningRow> rows;
  for (std::size_t k = 0; k < pairs.above.size(); ++k) {
    const auto i = pairs.above[k], j = pairs.below[k];
    OpeningRow r;
    r.x = 0.5 * (p.x[i] + p.x[j]);
    r.pd = u[n + i] - u[n + j];
    r.fem = interpolate.value(fem.solution.uy, p.x[i], p.y[i]) - interpolate.value(fem.solution.uy, p.x[j], p.y[j]);
    r.damage_above = damage.empty() ? 0.0 : damage[i];
    r.damage_below = damage.empty() ? 0.0 : damage[j];
    rows.push_back(r);
  }
  return rows;
}

CrackPdRun solve_crack_pd(const ParticleSet& particles, const solver::Scene& scene) {
  const auto start = std::chrono::steady_clock::now();
  solver::QuasiStaticProblem problem(scene, particles);
  CrackPdRun run;
  run.precrack_bonds = problem.precrack_bonds_cut();
  std::ostringstream log;
  auto result = solver::solve_quasi_static(problem, scene, {}, log);
  run.steps = std::move(result.steps);
  run.u = std::move(result.u);
  run.damage = std::move(result.damage);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace pd::validation
