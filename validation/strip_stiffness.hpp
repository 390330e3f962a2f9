#pragma once
// The stiffness of a plain strip (docs/validation.md, "Strip stiffness"): how
// the surface correction (theory.md Sec. 3) and the loads (rigid strips, or
// the loading layer of docs/mesher.md) change what a tensile test measures.
// Reference: the continuum, plane stress with the model's Poisson ratio
// (1/3 for PMB): uniaxial stress sigma = E eps, energy density E eps^2 / 2.
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::validation {

// A scene in code for the strip measures: PMMA-like E, no damage, quasi-static
// with one load step; `loads` as given.
solver::Scene strip_scene(bool surface_correction, const std::vector<solver::LoadSpec>& loads = {});

// Imposes the homogeneous uniaxial-stress field u = eps (x, -nu y) (stress
// along x) or eps (-nu x, y) (along y) on every particle and compares the
// strain energy of the particles whose centres lie in the middle half of the
// strip's length (|x - x_mid| <= L / 4; L along x) with the continuum's,
// E eps^2 / 2 per unit area: E_eff / E - 1. On a strip whose long edges run
// along x, "along" loads the edges along their direction, "across" normal to
// it. The imposed field is not relaxed: this is the first-order (energy)
// measure of the stiffness, the one the surface correction calibrates.
struct ImposedStrainModuli {
  double along = 0, across = 0;
};
ImposedStrainModuli imposed_strain_moduli(const ParticleSet& strip, const solver::Scene& scene);

// A quasi-static tensile test along x: the scene's displacement loads pull the
// particle set; measured on the particles of the body [body_xmin, body_xmax]
// x [ymin, ymax] (the set's bounding box in y) within its middle half:
// the strains (least-squares slopes of u_x over x and u_y over y), and the
// stress = reaction of load `reaction_load` / (width x thickness).
struct TensileTest {
  double strain = 0;          // eps_xx in the middle
  double lateral_strain = 0;  // eps_yy in the middle
  double stress = 0;          // [Pa]
  double reaction = 0;        // [N]
  long iterations = 0;        // NCG
  double modulus() const { return stress / strain; }
  double poisson_ratio() const { return -lateral_strain / strain; }
};
TensileTest tensile_test(const ParticleSet& particles, const solver::Scene& scene, const std::string& reaction_load,
                         double body_xmin, double body_xmax);

// x-displacement load of a boundary set.
solver::LoadSpec x_displacement(const std::string& set, double value);

}  // namespace pd::validation
