#pragma once
// The three grids of pd-mesh (docs/mesher.md):
//   nbnug   - dx squares everywhere except in boxes around holes, which are meshed free;
//   uniform - dx squares everywhere, squares whose centroid is in a hole removed;
//   free    - one free mesh over the whole plate.
#include <string>
#include <vector>

#include "free_mesh.hpp"
#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd {

class GmshSession;

// A box of the NB-NUG grid in lattice cells: [i0, i1) x [j0, j1), with the
// holes it contains (indices into PlateGeometry::holes).
struct LatticeBox {
  long i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  std::vector<std::size_t> holes;
};

// Each hole's bounding box grown by `padding`, snapped outward to the dx
// lattice, clipped to the plate; boxes that overlap or touch are merged.
// nx, ny: lattice cells along x and y.
std::vector<LatticeBox> nbnug_boxes(const PlateGeometry& geometry, double spacing, double padding, long nx,
                                    long ny);

struct GridOptions {
  GridKind grid = GridKind::nbnug;
  double spacing = 0;  // dx [m]
  double padding = 0;  // NB-NUG box padding around each hole [m]
};

struct GridReport {
  std::size_t squares = 0;
  std::vector<LatticeBox> boxes;
  FreeMeshStats free;
  double min_centroid_distance_to_curve = 1e300;  // [m]
};

// Builds the cells and particles (no families, no sets, horizon 0).
ParticleSet build_grid(GmshSession& session, const PlateGeometry& geometry, const GridOptions& options,
                       GridReport& report);

// Adds boundary sets: left, right, bottom, top (plate edges), hole_1.. (hole
// curves) and every named physical curve group of the geometry file (a group
// with the name of an automatic set replaces it): particles within `distance`.
void add_boundary_sets(ParticleSet& particles, const PlateGeometry& geometry, double distance);

// Reorders particles by lattice row, then column, then position, so that
// neighbours are close in memory (deterministic).
void sort_particles_spatially(ParticleSet& particles);

// Lattice size for the plate, or pd::Error proposing the nearest spacing that
// divides both sides.
void lattice_cells(const PlateGeometry& geometry, double spacing, long& nx, long& ny);

}  // namespace pd
