#include "hole_stress.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace pd::validation {

PlaneStress plane_stress(const DisplacementGradient& g, double e, double nu) {
  const double exx = g.du_dx[0][0], eyy = g.du_dx[1][1];
  const double gamma_xy = g.du_dx[0][1] + g.du_dx[1][0];  // engineering shear strain
  const double c = e / (1 - nu * nu);
  return {c * (exx + nu * eyy), c * (eyy + nu * exx), e / (2 * (1 + nu)) * gamma_xy};
}

double hoop_component(const PlaneStress& s, double theta) {
  const double c = std::cos(theta), n = std::sin(theta);
  return s.xx * n * n + s.yy * c * c - 2 * s.xy * n * c;
}

double elastic_energy_density(const DisplacementGradient& g, double e, double nu) {
  const auto s = plane_stress(g, e, nu);
  return 0.5 * (s.xx * g.du_dx[0][0] + s.yy * g.du_dx[1][1] + s.xy * (g.du_dx[0][1] + g.du_dx[1][0]));
}

DisplacementGradient fem_displacement_gradient(const FemInterpolator& interpolate, const FemSolution& solution,
                                               double x, double y) {
  const auto where = interpolate.locate(x, y);
  const auto gx = interpolate.gradient_at(solution.ux, where), gy = interpolate.gradient_at(solution.uy, where);
  DisplacementGradient g;
  g.du_dx[0][0] = gx[0], g.du_dx[0][1] = gx[1];
  g.du_dx[1][0] = gy[0], g.du_dx[1][1] = gy[1];
  return g;
}

std::vector<HoleStressSample> hole_stress_samples(const ParticleSet& p, const PdSolution& pd, const HoleCircle& hole,
                                                  double depth, const std::vector<const FemReference*>& fems,
                                                  double e, double nu) {
  std::vector<std::unique_ptr<FemInterpolator>> interpolators;
  for (const auto* fem : fems) interpolators.push_back(std::make_unique<FemInterpolator>(fem->mesh));
  std::vector<HoleStressSample> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double dx = p.x[i] - hole.cx, dy = p.y[i] - hole.cy;
    const double distance = std::hypot(dx, dy) - hole.radius;
    if (distance > depth) continue;
    HoleStressSample s;
    s.particle = i;
    s.distance = distance;
    s.theta = std::atan2(dy, dx);
    if (s.theta < 0) s.theta += 2 * M_PI;
    s.pd_hoop = hoop_component(plane_stress(family_displacement_gradient(p, pd.ux, pd.uy, i), e, nu), s.theta);
    s.pd_energy_density = pd.strain_energy_density.at(i);
    for (std::size_t f = 0; f < fems.size(); ++f) {
      const auto g = fem_displacement_gradient(*interpolators[f], fems[f]->solution, p.x[i], p.y[i]);
      s.fem_hoop.push_back(hoop_component(plane_stress(g, e, nu), s.theta));
      s.fem_energy_density.push_back(elastic_energy_density(g, e, nu));
    }
    out.push_back(std::move(s));
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.theta < b.theta; });
  return out;
}

}  // namespace pd::validation
