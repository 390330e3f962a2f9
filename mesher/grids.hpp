#pragma once
// The three grids of pd-mesh (docs/mesher.md):
//   nbnug   - dx squares everywhere except in bands along the boundaries that
//             are not on lattice lines (boxes around holes), meshed free;
//   uniform - dx squares whose centre lies in the material;
//   free    - one free mesh over the whole plate.
#include <functional>
#include <string>
#include <vector>

#include "boundary_sets.hpp"  // the sets every grid gets
#include "free_mesh.hpp"
#include "free_region.hpp"
#include "graded_spacing.hpp"
#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd {

class GmshSession;

class MeshWorker;

struct GridOptions {
  GridKind grid = GridKind::nbnug;
  double spacing = 0;  // dx [m]
  double padding = 0;  // NB-NUG band width around boundaries off the lattice [m]
  // Target size of the free cells [m]: dx / 2^k (box_spacing.hpp), 0 for dx.
  // The geometry's curve samples must be about this far apart (sample_plate).
  double free_cell_size = 0;
  // Meshes the free regions in child processes (byte-identical output, see
  // mesh_worker.hpp); null: in this process.
  const MeshWorker* worker = nullptr;
  // Global free grid only: the target size graded from the curved boundaries
  // (graded_spacing.hpp); not enabled: free_cell_size everywhere.
  GradedSpacing graded{};
  // Called with the lattice squares (the particles so far) before the free
  // regions are meshed: a check that refuses the grid (pd::Error) spares
  // gmsh's work, which may take minutes. Empty: none.
  std::function<void(const ParticleSet& squares)> before_meshing{};
};

struct GridReport {
  std::size_t squares = 0;
  std::size_t free_regions = 0;  // connected free regions (NB-NUG bands and boxes, or the whole plate)
  FreeMeshStats free;
  // Smallest distance from a particle's centroid to a curved boundary, and to
  // a straight boundary off the lattice lines [m] (infinite if there is none).
  double min_distance_to_curved = 1e300, min_distance_to_straight_off_lattice = 1e300;
  CellMap cells;  // what each lattice cell became
  GradedSpacing graded;  // the grading the free mesh followed, if any
};

// Builds the cells and particles (no families, no sets, horizon 0).
ParticleSet build_grid(GmshSession& session, const PlateGeometry& geometry, const GridOptions& options,
                       GridReport& report);

// Reorders particles by lattice row, then column, then position, so that
// neighbours are close in memory (deterministic).
void sort_particles_spatially(ParticleSet& particles);

}  // namespace pd
