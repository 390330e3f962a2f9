#pragma once
// The centre-cracked plate (docs/validation.md, "Crack opening"): a square
// plate with a central crack parallel to x, its bottom and top strips (the
// load sets, one horizon deep) moved apart along y by -U and +U, x free. PD:
// OSB quasi-static with the crack as a pre-crack, in any of its failure
// variants (theory.md Sec. 5.8). Reference: a plane-stress CalculiX solution
// on a gmsh mesh of the same plate with the crack as two faces
// (fem_mesh.hpp, write_cracked_plate_mesh), the same strips held.
//
// The opening compared is u_y of the particle just above the crack line minus
// that of the particle just below it (the same x), for every such pair over
// the crack, and the FEM field interpolated at the same two points: both
// include the same elastic strain between the points and the crack faces.
#include <string>
#include <vector>

#include "calculix.hpp"
#include "fem_mesh.hpp"
#include "load_steps.hpp"
#include "osb.hpp"
#include "particle_file.hpp"
#include "scene.hpp"

namespace pd::validation {

struct CrackCase {
  double youngs_modulus = 200e9;     // [Pa] steel
  double poisson_ratio = 0.25;
  double fracture_energy = 2.2e4;    // G0 [J/m^2], steel (as geometries/kalthoff_winkler.toml)
  double crack_half_length = 0.05;   // a [m]: the crack runs from xc - a to xc + a at the plate's mid-height
  double edge_displacement = 0.5e-3; // U [m]: bottom strip -U, top strip +U (at load factor 1)
};

// The crack of `c` in the plate of `geometry` (centred).
FemCrack crack_of(const PlateGeometry& geometry, const CrackCase& c);

// The PD scene in code (the keys a scene file would give, docs/scenes.md):
// OSB, plane stress, quasi-static with the given load factors, the crack as
// a pre-crack, displacement loads on the sets "bottom" and "top" (y only).
solver::Scene crack_scene(const PlateGeometry& geometry, const CrackCase& c, solver::OsbFailure failure, bool damage,
                          const std::vector<double>& load_factors);

// The FEM reference: mesh (under `folder`), ccx run. `strip_width`: the
// depth of the PD load sets (one horizon); `tip_size`: element size at the tips.
struct CrackFem {
  FemMesh mesh;
  FemSolution solution;
  double seconds = 0;  // mesh and ccx
};
CrackFem solve_crack_fem(const PlateGeometry& geometry, const CrackCase& c, double strip_width, double tip_size,
                         const std::string& folder, const std::string& job_name);

// The opening of the FEM crack faces at x [m]: u_y of the upper face node at
// x minus that of the lower one (nodes exist there only where the mesh has
// them: the nearest node pair of each face is used).
double fem_face_opening(const CrackFem& fem, const FemCrack& crack, double x);

// The pairs of particles straddling the crack line over the crack: `above`
// and `below` at (nearly) the same x, nearest to the line on each side.
struct CrackPairs {
  std::vector<std::uint32_t> above, below;  // sorted by x
};
CrackPairs crack_pairs(const ParticleSet& particles, const FemCrack& crack);

struct OpeningRow {
  double x = 0;                      // [m]
  double pd = 0, fem = 0;            // u_y above minus below [m]
  double damage_above = 0, damage_below = 0;
};
// The opening of the PD displacements (x block, then y block) and of the FEM
// field at the pairs.
std::vector<OpeningRow> opening_profile(const ParticleSet& particles, const CrackPairs& pairs,
                                        const std::vector<double>& u, const std::vector<double>& damage,
                                        const CrackFem& fem);

// A PD run of the scene: every load step's record and the final state.
struct CrackPdRun {
  std::vector<solver::LoadStepRecord> steps;
  std::vector<double> u, damage;
  std::size_t precrack_bonds = 0;  // directed bonds the pre-crack cut
  double seconds = 0;
};
CrackPdRun solve_crack_pd(const ParticleSet& particles, const solver::Scene& scene);

}  // namespace pd::validation
