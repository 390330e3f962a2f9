#pragma once
// Meshing free regions in a child process.
//
// gmsh 4.8 makes some choices by memory address (ties in its frontal
// mesher's queue are broken by pointer), so the same region can mesh
// differently from one process to the next, and even between two runs of the
// same command (address-space randomisation). A child process started the
// same way every time - this program with fixed arguments, an empty
// environment, address randomisation switched off for it alone - sees the
// same addresses and gives the same mesh, so pd-mesh's output is byte for
// byte the same. The child only reads numbers that pd-mesh wrote (the
// region's vertices), never the user's geometry file. It also bounds gmsh's
// time cleanly (the child is killed) and turns a crash inside gmsh into an
// error message.
#include <string>

#include "free_mesh.hpp"

namespace pd {

// The argument that makes pd-mesh run as a mesh worker (internal).
inline constexpr const char* mesh_worker_argument = "--mesh-region-worker";

// What gmsh may take per expected cell on top of the time limit. gmsh's
// Frontal-Delaunay for quads takes 1 to 1.4 ms per cell on a quiet 2-core
// machine and 3 ms or more on a loaded one (docs/mesher.md, "Graded free
// meshes": C3-A's free grid at 0.1 mm, 124 s and 380 s): the allowance is
// several times that, so that a large grid is never refused for its size.
inline constexpr double gmsh_seconds_per_expected_cell = 10e-3;

// The time the mesh worker has for `shapes`: `seconds` plus
// gmsh_seconds_per_expected_cell for each cell of its target size expected
// (a region's area over its smallest target size squared).
double meshing_time_limit(double seconds, const std::vector<RegionShape>& shapes);

class MeshWorker {
public:
  // `executable`: a program that runs run_mesh_worker() when given
  // mesh_worker_argument (pd-mesh: /proc/self/exe). `seconds`: time limit,
  // plus the allowance per expected cell (meshing_time_limit); `option`
  // names it in messages.
  MeshWorker(std::string executable, double seconds, std::string option);

  // mesh_region for every shape, in one child process (in order, so that
  // the child's memory has the same history every time). Throws pd::Error
  // naming `file` if gmsh fails, crashes or runs out of time.
  std::vector<RegionMesh> mesh(const std::string& file, const std::vector<RegionShape>& shapes) const;

private:
  std::string executable_, option_;
  double seconds_;
};

// The child's side: reads the regions from standard input, meshes them,
// writes the meshes (or an error message) to standard output. Returns the
// exit status.
int run_mesh_worker();

}  // namespace pd
