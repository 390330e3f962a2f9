#pragma once
// Free (unstructured, quad-dominant) gmsh mesh of one free region, for the
// bands and boxes of NB-NUG grids and for the global free grid: the region's
// shape, gmsh's mesh of it, and the cells (particles) made from that mesh.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "free_region.hpp"
#include "particle_file.hpp"

namespace pd {

class GmshSession;

// What gmsh needs to mesh one free region: its boundary loops (outer loop
// counter-clockwise first, then the inner loops) over a vertex list.
struct RegionShape {
  // Metres per gmsh model unit: mm, whatever the geometry file's unit
  // (free_mesh.cpp, mesh_region).
  double unit = 1e-3;
  double spacing = 0;     // target element size [m]
  std::vector<Vec2> vertices;                   // [m]
  std::vector<std::vector<std::uint32_t>> loops;  // vertex indices, in order
  // curved[l][k]: the edge loops[l][k] -> loops[l][k + 1] is a chord of a
  // curved boundary.
  std::vector<std::vector<std::uint8_t>> curved;
  // Graded meshes (graded_spacing.hpp): the target size grows linearly from
  // fine_size at the curved edges to `spacing` at grading_length from them.
  double fine_size = 0, grading_length = 0;  // [m]; 0: `spacing` everywhere
  // The smallest target size [m].
  double smallest_size() const { return fine_size > 0 ? fine_size : spacing; }
};

// Region `region` of `regions` as a RegionShape; `global_vertex[k]` is the
// index in regions.vertices of the shape's vertex k.
RegionShape region_shape(const FreeRegions& regions, std::size_t region, double spacing,
                         std::vector<std::uint32_t>& global_vertex);

// gmsh's mesh of a region. Each boundary edge is exactly one element edge, so
// the mesh meets the dx squares node to node and its nodes on the boundary
// curves are the curves' samples.
struct RegionMesh {
  std::vector<Vec2> nodes;                   // [m]; nodes inside rounded to 2^-20 model units
  std::vector<std::int64_t> vertex_of_node;  // the shape's vertex at this node, or -1
  std::vector<std::uint32_t> element_offsets{0}, element_nodes;  // CSR, 3 or 4 nodes per element
};

// Meshes the shape with gmsh in this process (Frontal-Delaunay for quads,
// target size = spacing, or graded by a gmsh Distance + Threshold size field), without a time limit and without the byte-for-byte
// repeatability of MeshWorker (mesh_worker.hpp). Throws pd::Error naming
// `file` if gmsh fails.
RegionMesh mesh_region(GmshSession& session, const std::string& file, const RegionShape& shape);

struct FreeMeshStats {
  std::size_t quads = 0, triangles = 0;
  double min_area = 1e300, max_area = 0, sum_area = 0;  // element areas [m^2]
  double worst_quality = 1;  // min over elements of (smallest angle / ideal angle)
  std::size_t curved_edges = 0;  // element edges on curved boundaries
};

// Each element of `mesh` becomes a particle: shoelace centroid, area
// corrected for edges on curved boundaries by the curves' bulges, and the
// cell polygon with the arc points of such edges.
void append_region_cells(const std::string& file, const FreeRegions& regions, std::size_t region,
                         const std::vector<std::uint32_t>& global_vertex, const RegionMesh& mesh, Region kind,
                         ParticleSet& particles, FreeMeshStats& stats);

}  // namespace pd
