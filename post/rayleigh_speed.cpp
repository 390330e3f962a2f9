#include "rayleigh_speed.hpp"

#include <cmath>

#include "error.hpp"

namespace pd::post {

const char* const rayleigh_formula =
    "c_R = k c_s, c_s = sqrt(E / (2 (1 + nu) rho)), k in (0, 1) the root of "
    "(2 - k^2)^2 = 4 sqrt(1 - k^2) sqrt(1 - k^2 (1 - 2 nu') / (2 (1 - nu'))), "
    "nu' = nu / (1 + nu) in plane stress, nu in plane strain; nu = the model's Poisson ratio "
    "[Rayleigh 1885]";

const char* to_string(Plane plane) { return plane == Plane::stress ? "stress" : "strain"; }

double in_plane_poisson_ratio(double poisson_ratio, Plane plane) {
  return plane == Plane::stress ? poisson_ratio / (1.0 + poisson_ratio) : poisson_ratio;
}

double rayleigh_ratio(double nu) {
  const double a2 = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
  // R(k) = (2 - k^2)^2 - 4 sqrt(1 - k^2) sqrt(1 - a^2 k^2) is 0 at k = 0 (a
  // root without meaning), negative just above it and 1 at k = 1; the one
  // root in between is the Rayleigh wave. Bisection on [0.5, 1]: R(0.5) < 0
  // for every nu in (-1, 0.5) (k lies in [0.69, 0.96] there).
  auto residual = [&](double k) {
    const double k2 = k * k;
    return (2.0 - k2) * (2.0 - k2) - 4.0 * std::sqrt(1.0 - k2) * std::sqrt(1.0 - a2 * k2);
  };
  double lo = 0.5, hi = 1.0;
  for (int i = 0; i < 100 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (residual(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

RayleighSpeed rayleigh_speed(double youngs_modulus, double density, double poisson_ratio, Plane plane) {
  RayleighSpeed r;
  r.shear_speed = std::sqrt(youngs_modulus / (2.0 * (1.0 + poisson_ratio)) / density);
  r.in_plane_poisson_ratio = in_plane_poisson_ratio(poisson_ratio, plane);
  r.ratio = rayleigh_ratio(r.in_plane_poisson_ratio);
  r.speed = r.ratio * r.shear_speed;
  return r;
}

RayleighSpeed rayleigh_speed(const ElasticModel& m) {
  return rayleigh_speed(m.youngs_modulus, m.density, m.poisson_ratio, m.plane);
}

ElasticModel simulated_model(const ArrivalData& data, const SolverSummary& summary,
                             std::vector<std::string>& notes) {
  ElasticModel m;
  m.youngs_modulus = data.youngs_modulus;
  m.density = data.density;
  // Both files are the solver's: a disagreement is an edit.
  if (!summary.plane.empty() && data.plane_strain && (summary.plane == "strain") != *data.plane_strain)
    throw file_error(summary.path, "\"plane\" is \"" + summary.plane + "\" but " + data.path +
                                       " has plane_strain = " + (*data.plane_strain ? "1" : "0") +
                                       ": the files are of different runs, or one was edited");
  if (!summary.plane.empty()) {
    m.plane = summary.plane == "strain" ? Plane::strain : Plane::stress;
    m.plane_source = summary.path + " \"plane\"";
  } else if (data.plane_strain) {
    m.plane = *data.plane_strain ? Plane::strain : Plane::stress;
    m.plane_source = data.path + " field \"plane_strain\"";
  } else {
    m.plane = Plane::stress;
    m.plane_source = "fallback: plane stress, the scene default";
    notes.push_back("no \"plane\" in " + (summary.present ? summary.path : std::string("summary.json (absent)")) +
                    ": plane stress assumed for the Rayleigh speed");
  }
  if (data.model_poisson_ratio) {
    m.poisson_ratio = *data.model_poisson_ratio;
    m.poisson_ratio_source = data.path + " field \"poisson_ratio\"";
  } else {
    // Every solver output without the field comes from the bond-based PMB
    // model, whose Poisson ratio is fixed by the plane.
    m.poisson_ratio = m.plane == Plane::stress ? 1.0 / 3.0 : 1.0 / 4.0;
    m.poisson_ratio_source = std::string("fallback: bond-based PMB in plane ") + to_string(m.plane);
    notes.push_back("no field \"poisson_ratio\" in " + data.path + ": the PMB model's " +
                    (m.plane == Plane::stress ? "1/3 (plane stress)" : "1/4 (plane strain)") +
                    " used for the Rayleigh speed");
  }
  return m;
}

}  // namespace pd::post
