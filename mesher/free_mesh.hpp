#pragma once
// Free (unstructured, quad-dominant) gmsh mesh of a rectangle minus the holes
// inside it. Used for the boxes of NB-NUG grids and for the global free grid.
#include <cstddef>
#include <vector>

#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd {

class GmshSession;

struct FreeMeshStats {
  std::size_t quads = 0, triangles = 0;
  double min_area = 1e300, max_area = 0, sum_area = 0;  // element areas [m^2]
  double worst_quality = 1;  // min over elements of (smallest angle / ideal angle)
  std::size_t curved_edges = 0;
};

// Meshes [x0, x1] x [y0, y1] (metres) minus the listed holes with target
// element size `spacing`. The rectangle's sides get exactly nx (bottom, top)
// and ny (left, right) equal segments, so the mesh meets neighbouring dx
// squares node to node. Each element becomes a particle (shoelace centroid,
// area corrected for edges on curved hole boundaries by the holes' bulges).
void append_free_mesh(GmshSession& session, const PlateGeometry& geometry, double x0, double y0, double x1,
                      double y1, long nx, long ny, const std::vector<std::size_t>& holes, double spacing,
                      Region region, ParticleSet& particles, FreeMeshStats& stats);

}  // namespace pd
