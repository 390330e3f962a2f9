#pragma once
// Stresses at a hole boundary from a PD and an FEM displacement field
// (docs/validation.md, "C1: stress at the hole per grid"): the PD strain is
// the least-squares gradient of the family's displacements
// (displacement_gradient.hpp, docs/theory.md Sec. 10.1), the FEM strain the
// derivative of the element's shape functions; both go through the same
// plane-stress Hooke law and are turned into the hoop component
// sigma_thetatheta about the hole centre (theory.md Sec. 10.2).
#include <vector>

#include "c1_comparison.hpp"
#include "displacement_gradient.hpp"
#include "fem_interpolation.hpp"

namespace pd::validation {

struct PlaneStress {
  double xx = 0, yy = 0, xy = 0;  // [Pa]
};
// Plane-stress Hooke law of the small strain sym(G) (theory.md Sec. 10.2).
PlaneStress plane_stress(const DisplacementGradient& g, double youngs_modulus, double poisson_ratio);
// sigma_thetatheta at polar angle theta [rad] (theta from the +x axis about the hole centre).
double hoop_component(const PlaneStress& s, double theta);
// 1/2 sigma : eps [J/m^3].
double elastic_energy_density(const DisplacementGradient& g, double youngs_modulus, double poisson_ratio);

// The FEM displacement gradient at a point.
DisplacementGradient fem_displacement_gradient(const FemInterpolator& interpolate, const FemSolution& solution,
                                               double x, double y);

struct HoleCircle {
  double cx = 0, cy = 0, radius = 0;  // [m]
};

// One particle of the first ring around the hole, and the fields there.
struct HoleStressSample {
  std::size_t particle = 0;            // index in the particle set
  double theta = 0, distance = 0;      // polar angle [rad] in [0, 2 pi), r - R [m]
  double pd_hoop = 0;                  // sigma_thetatheta from the PD gradient [Pa]
  double pd_energy_density = 0;        // W_i of the PD model (theory.md Sec. 1.9) [J/m^3]
  std::vector<double> fem_hoop, fem_energy_density;  // per FEM reference, at the particle's position
};

// The particles whose centroid lies within `depth` of the hole circle (r - R
// <= depth; depth = dx takes the first ring on every grid), with the PD
// fields of `pd` (on all of `particles`, layers included) and every FEM
// solution of `fems` sampled at the same points. Sorted by theta.
std::vector<HoleStressSample> hole_stress_samples(const ParticleSet& particles, const PdSolution& pd,
                                                  const HoleCircle& hole, double depth,
                                                  const std::vector<const FemReference*>& fems,
                                                  double youngs_modulus, double poisson_ratio);

}  // namespace pd::validation
