#pragma once
// A linear-elastic, plane-stress CalculiX (ccx) run on a FEM mesh written by
// fem_mesh.hpp: clamped strips moved along x, one node held in y against the
// rigid-body translation, nodal displacements read back from the .frd file.
//
// Thickness: ccx expands plane-stress elements into one layer of 3D elements
// as deep as the section thickness, which behaves as plane stress only when
// the layer is thin next to the plate; we use 1e-6 m and scale the reaction
// forces back to the scene's thickness (docs/validation.md).
#include <string>
#include <vector>

#include "fem_mesh.hpp"

namespace pd::validation {

struct FemLoadCase {
  double youngs_modulus = 0;   // [Pa]
  double poisson_ratio = 1.0 / 3.0;  // PMB plane stress fixes 1/3
  double clamp_width = 0;      // nodes with x <= xmin + width (x >= xmax - width) are moved [m]
  double left_ux = 0, right_ux = 0;  // imposed u_x [m]
  double section_thickness = 1e-6;   // [m], thin: see above
  // Pulled along y instead: the nodes with y <= ymin + clamp_width
  // (y >= ymax - clamp_width) get u_y = bottom_uy (top_uy), u_x free; the
  // node nearest to the middle of the bottom edge holds u_x = 0.
  bool along_y = false;
  double bottom_uy = 0, top_uy = 0;  // imposed u_y [m]
};

struct FemSolution {
  std::vector<double> ux, uy;  // per node of the mesh [m]
  // Resultant on the first (left, or bottom with along_y) and second (right,
  // top) strip along the pull, per metre of thickness [N/m].
  double left_reaction_x = 0;
  double right_reaction_x = 0;
  double seconds = 0;          // wall time of ccx
};

// What a wait status of ccx (std::system's) says, for messages: "ccx exited
// with status 3", "ccx was killed by signal 9" (before 7 December 2026 the
// raw status, "exit status 768" for 3).
std::string ccx_status_text(int status);

// True if `ccx` is on the PATH.
bool calculix_available();

// Writes JOB.inp next to the mesh file (folder of mesh.inp_mesh_file), runs
// `ccx -i JOB` there and reads JOB.frd and JOB.dat. pd::Error names the file
// for a missing ccx, a failed run (with the tail of its log) or an unreadable result.
FemSolution run_calculix(const FemMesh& mesh, const PlateGeometry& geometry, const FemLoadCase& load,
                         const std::string& job_name);

}  // namespace pd::validation
