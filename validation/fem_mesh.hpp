#pragma once
// The FEM reference mesh of a plate with circular holes: 6-node triangles
// (CPS6) whose mid-side nodes lie on the true hole circles, graded from size
// h at the holes to 4h a few millimetres away (docs/validation.md), written by gmsh as a CalculiX .inp mesh.
//
// The plate and holes are read from the same .geo file the particle grids
// come from (mesher/plate_geometry.hpp). For the FEM model the plate is
// rebuilt with OpenCASCADE and split by the lines x = xmin + clamp_width and
// x = xmax - clamp_width, so that the clamped strips of the PD load sets (the
// particles within one horizon of the left and right edges) are exactly
// unions of elements. The mesh is refined to h around the holes and around the
// ends of those lines on the free edges (singular points of the elastic field).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "plate_geometry.hpp"

namespace pd::validation {

struct FemMeshOptions {
  double hole_size = 0;      // element size h at the holes [m]
  double far_size = 0;       // size far from the holes [m] (default 4 h)
  double grading_distance = 3e-3;  // distance over which the size grows from h to far_size [m]
  double clamp_width = 0;    // width of the left and right strips [m]; 0 = no split
};

struct FemMesh {
  std::vector<std::size_t> node_id;        // gmsh / CalculiX node number of each node
  std::vector<double> x, y;                // node coordinates [m]
  std::vector<std::array<std::uint32_t, 6>> triangles;  // 0-based node indices, gmsh/CalculiX order:
                                           // corners 0, 1, 2, then mid-sides 01, 12, 20
  std::string inp_mesh_file;               // the .inp gmsh wrote (nodes and CPS6 elements)
  std::string element_set;                 // name of the element set in that file
};

// Meshes the plate of `geometry` (circular holes only; pd::Error otherwise) and
// writes `inp_path` with gmsh (coordinates in metres).
FemMesh write_fem_mesh(const PlateGeometry& geometry, const FemMeshOptions& options, const std::string& inp_path);

// A straight crack parallel to x, from (x1, y) to (x2, y), x1 < x2 [m]: two
// faces on the same line that share only the tips.
struct FemCrack {
  double x1 = 0, x2 = 0, y = 0;
};

struct CrackedPlateMeshOptions {
  double tip_size = 0;          // element size h at the crack tips [m]
  double far_size = 0;          // size far from the tips [m] (default 20 h)
  double grading_distance = 0;  // distance over which the size grows from h to far_size [m] (default 10 far_size)
  // Height of the bottom and top strips (the load sets of the PD grid, one
  // horizon deep): the lines y = ymin + strip_width and y = ymax - strip_width
  // are element edges, so the strips are unions of elements [m]; > 0.
  double strip_width = 0;
};

// The plate and crack write_cracked_plate_mesh takes: a plate without holes,
// the crack inside it between the load strips `strip_width` wide; pd::Error
// naming the file otherwise. (pd-validate-crack checks it before it makes
// its output folder.)
void check_cracked_plate(const PlateGeometry& geometry, const FemCrack& crack, double strip_width);

// Meshes a rectangular plate without holes (the bounding box of `geometry`,
// pd::Error if it has holes) cut by `crack`, with the same 6-node triangles
// as write_fem_mesh, and writes `inp_path`. The plate is built with gmsh's
// built-in kernel as four surfaces (bottom strip, lower half, upper half, top
// strip); the two halves share the ligament curves beside the crack but each
// has its own crack face, so the nodes on the crack are doubled except at the
// tips (docs/validation.md, crack opening).
FemMesh write_cracked_plate_mesh(const PlateGeometry& geometry, const FemCrack& crack,
                                 const CrackedPlateMeshOptions& options, const std::string& inp_path);

}  // namespace pd::validation
