#pragma once
// The Rayleigh wave speed of the elastic model that was simulated: the speed
// a brittle crack cannot exceed, used to normalise crack speeds.
//
// In-plane waves of a 2D model obey the plane-strain equations with an
// in-plane Poisson ratio nu' = nu (plane strain) or nu / (1 + nu) (plane
// stress: the plane-stress dilatational speed sqrt(E / (rho (1 - nu^2)))
// is the plane-strain one with nu replaced by nu / (1 + nu)). Then
//   c_s = sqrt(mu / rho),  mu = E / (2 (1 + nu)),
//   c_R = k c_s, k in (0, 1) the root of Rayleigh's equation
//   (2 - k^2)^2 = 4 sqrt(1 - k^2) sqrt(1 - a^2 k^2),  a^2 = (1 - 2 nu') / (2 (1 - nu'))
// [Rayleigh 1885, "On waves propagated along the plane surface of an
// elastic solid"]. For nu' = 1/4 it gives k = sqrt(2 - 2 / sqrt(3)) = 0.9194.
#include <string>
#include <vector>

#include "arrival_data.hpp"
#include "solver_summary.hpp"

namespace pd::post {

enum class Plane { stress, strain };
const char* to_string(Plane plane);

// The Poisson ratio the in-plane wave equations see: nu / (1 + nu) in plane stress.
double in_plane_poisson_ratio(double poisson_ratio, Plane plane);

// k = c_R / c_s, the root in (0, 1) of Rayleigh's equation for in-plane Poisson ratio nu'.
double rayleigh_ratio(double in_plane_poisson_ratio);

struct ElasticModel {
  double youngs_modulus = 0;  // [Pa]
  double density = 0;         // [kg/m^3]
  double poisson_ratio = 0;   // of the model that ran (PMB: 1/3 plane stress, 1/4 plane strain)
  Plane plane = Plane::stress;
  std::string poisson_ratio_source, plane_source;  // where each came from (for the summary)
};

struct RayleighSpeed {
  double speed = 0;                   // c_R [m/s]
  double shear_speed = 0;             // c_s [m/s]
  double ratio = 0;                   // k = c_R / c_s
  double in_plane_poisson_ratio = 0;  // nu'
};
RayleighSpeed rayleigh_speed(double youngs_modulus, double density, double poisson_ratio, Plane plane);
RayleighSpeed rayleigh_speed(const ElasticModel& model);

// The formula above as one line of text, for summary.json.
extern const char* const rayleigh_formula;

// The model that ran, from the outputs: the plane from summary.json (else
// plane stress, the scene default), the Poisson ratio from arrival.vtp's
// field `poisson_ratio` (else the PMB value of the plane: 1/3 plane stress,
// 1/4 plane strain). Each fallback adds a note.
ElasticModel simulated_model(const ArrivalData& data, const SolverSummary& summary,
                             std::vector<std::string>& notes);

}  // namespace pd::post
