#pragma once
// Case C1 (docs/validation.md; [Peng, Chen, Bobaru 2023, Sec. 4.1]): a plate
// with a hole pulled by opposite displacements u_x = -/+ U of its left and
// right strips (the particles within one horizon of each edge), top, bottom
// and hole free. The PD quasi-static solution is compared, particle by
// particle, with a plane-stress FEM solution of the same plate, the same
// clamped strips and the PMB model's Poisson ratio 1/3, interpolated to the
// particle positions with the elements' quadratic shape functions. With
// C1Loading::layers the plate is pulled through loading layers beyond its
// left and right edges instead, and the FEM through its edge nodes.
#include <string>
#include <vector>

#include "bond_weights.hpp"
#include "calculix.hpp"
#include "fem_interpolation.hpp"
#include "particle_file.hpp"
#include "plate_grid.hpp"
#include "scene.hpp"

namespace pd::validation {

struct C1Material {
  double youngs_modulus = 3.24e9;  // [Pa]
  double fracture_energy = 200;    // [J/m^2] (only for the scene; no damage in C1)
  double edge_displacement = 1e-7; // U [m] (0.0001 mm)
  // Plane stress. PMB fixes 1/3; the FEM reference and OSB (theory.md
  // Sec. 5) take this value.
  double poisson_ratio = 1.0 / 3.0;
};

// Where the edge displacements act (docs/scenes.md, "Which loading to use when").
enum class C1Loading {
  strips,  // the in-body sets "left" / "right" (one horizon deep); the FEM clamps the same strips
  layers,  // fictitious loading layers beyond the left and right edges; the FEM moves the edge nodes
};
const char* to_string(C1Loading loading);  // "strips", "layers"

struct PdOptions {
  // The PD model: PMB (the paper's), or OSB with the material's Poisson ratio
  // (plane stress; at nu = 1/3 the two share their bulk constants, theory.md
  // Sec. 5.2).
  solver::ModelType model = solver::ModelType::pmb;
  bool surface_correction = true;
  BondWeights bond_weights = BondWeights::distance_moment;
  double tolerance = 1e-9;  // relative residual of the NCG minimisation
  long max_iterations = 50000;
  C1Loading loading = C1Loading::strips;  // must match the particle set (c1_particles)
  // model.dual_horizon (theory.md Sec. 6), needed where the horizons vary:
  // solved by the linear dual-horizon solution (dual_horizon_statics.hpp),
  // without surface correction, instead of the NCG minimisation.
  bool dual_horizon = false;
};

// The C1 particle set: make_plate_grid, with loading layers one horizon deep
// beyond the left and right edges for C1Loading::layers.
ParticleSet c1_particles(const PlateGridSpec& spec, C1Loading loading, PlateGeometry* geometry);

struct PdSolution {
  std::vector<double> ux, uy;  // per particle [m]
  double reaction_x = 0;       // right strip or layer, per metre of thickness [N/m]
  std::vector<double> strain_energy_density;  // W_i per particle (theory.md Sec. 1.9) [J/m^3]
  long iterations = 0;
  double relative_residual = 0;
  double setup_seconds = 0, solve_seconds = 0;
};

// Solves C1 on the particle set (loads on its sets "left" and "right", or on
// its loading layers with options.loading = layers).
PdSolution solve_c1_pd(const ParticleSet& particles, const C1Material& material, const PdOptions& options);

// The particles of the plate itself (without loading layers), and the PD
// solution on them: what the FEM can be compared with.
struct PlateOnly {
  ParticleSet particles;            // positions, volumes, cells, regions (no families, no sets)
  PdSolution pd;                    // u and W of those particles
  std::vector<std::size_t> source;  // index of each in the full set
};
PlateOnly plate_only(const ParticleSet& particles, const PdSolution& pd, const PlateGeometry& geometry);

// The FEM reference: mesh (written under `folder`), ccx run, interpolator.
struct FemReference {
  FemMesh mesh;
  FemSolution solution;
  double mesh_size = 0;  // element size h at the hole [m]
  double mesh_seconds = 0;
};
// clamp_width 0: only the nodes on the left and right edges are moved (the
// counterpart of C1Loading::layers).
FemReference solve_c1_fem(const PlateGeometry& geometry, const C1Material& material, double clamp_width,
                          double hole_size, const std::string& folder, const std::string& job_name);

// FEM displacements at the particle positions.
struct FemAtParticles {
  std::vector<double> ux, uy;
};
FemAtParticles fem_at_particles(const FemReference& fem, const ParticleSet& particles);

// Differences PD - FEM over the particles. u_y is compared after removing
// the area-weighted mean difference (the rigid translation in y, which both
// models fix differently). "Relative" = divided by the largest |u_x| of the
// FEM field at the particles (= U up to round-off).
struct ErrorStats {
  double max_abs = 0, rms = 0;  // [m]
  double max_rel = 0, rms_rel = 0;
};
struct C1Errors {
  std::size_t particles = 0, near_hole_particles = 0;
  double reference = 0;  // largest |u_x^FEM| [m]
  ErrorStats ux, uy, ux_near_hole, uy_near_hole;
  std::vector<double> dux, duy;  // per particle, for maps [m]
};
// Near the hole: particles within `near_distance` of the circle (centre, radius).
C1Errors compare_with_fem(const ParticleSet& particles, const PdSolution& pd, const FemAtParticles& fem,
                          double hole_cx, double hole_cy, double hole_radius, double near_distance);

}  // namespace pd::validation
