#pragma once
// Which lattice cells become exact dx squares and which part of the plate is
// meshed free, and the boundary of that free part as loops of edges whose
// vertices are lattice nodes (where free cells meet squares) or samples on
// the boundary curves (docs/mesher.md, "The three grids").
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd {

// The dx lattice over the plate's bounding box: node (i, j) at
// (x0 + i dx, y0 + j dx), cell (i, j) between nodes (i, j) and (i + 1, j + 1).
struct Lattice {
  double x0 = 0, y0 = 0, dx = 0;
  long nx = 0, ny = 0;  // cells along x and y
  Vec2 node(long i, long j) const { return {x0 + i * dx, y0 + j * dx}; }
};

// The lattice of the plate's bounding box: whole cells between the sides
// along which straight curves lie, running past a side the plate touches
// only at a vertex or with a curve. pd::Error proposing the nearest spacing
// that divides the sides that must be lattice lines.
Lattice plate_lattice(const PlateGeometry& geometry, double spacing);

// A straight boundary curve lying on a lattice line: the cells on either side
// of it are whole squares, so it needs no free cells.
bool on_lattice_line(const BoundaryCurve& curve, const Lattice& lattice);

enum class CellKind : std::uint8_t {
  outside,  // no material in the cell (or, for uniform grids, its centre is not in the material)
  square,   // an exact dx square of material
  free,     // part of the free region (nbnug, free)
};

struct CellMap {
  Lattice lattice;
  std::vector<CellKind> kind;  // cell (i, j) at j * nx + i
  CellKind at(long i, long j) const { return kind[static_cast<std::size_t>(j * lattice.nx + i)]; }
};

// nbnug: a cell is free if it lies in the box, grown by `padding` and
// snapped outward to the lattice, of a boundary feature: a hole whose curves
// are all off the lattice (one box per hole, as in [Peng, Chen, Bobaru 2023,
// Sec. 3]), or a piece (about dx long) of any other curve off the lattice;
// boxes that overlap form one region. Any other cell is a square if its
// centre lies in the material: such a cell is then wholly material, since
// only boundaries on lattice lines come closer than the padding.
// uniform: the squares whose centre lies in the material; no free cells.
// free: every cell free.
CellMap classify_cells(const PlateGeometry& geometry, const Lattice& lattice, GridKind grid, double padding);

// A boundary edge of a free region. Edges on a curve off the lattice are its
// chords: the region lies on their left, the side of the curve's material.
struct RegionEdge {
  std::uint32_t from = 0, to = 0;          // vertices of FreeRegions::vertices
  const CurveSamples* samples = nullptr;  // the curve's samples, if the edge is one of its chords
  std::size_t chord = 0;                   // which chord (samples->points[chord] -> [chord + 1])
  bool curved = false;                     // the curve is not a straight line
};

// One connected free region: its outer loop (counter-clockwise) and its
// inner loops (clockwise), each a closed chain of edges.
struct FreeRegion {
  std::vector<std::vector<RegionEdge>> loops;  // loops[0] is the outer loop
};

struct FreeRegions {
  std::vector<Vec2> vertices;
  std::vector<FreeRegion> regions;
};

// The free regions of `cells` (cells of kind free intersected with the
// material). Every region has an even number of boundary edges (a free quad
// mesh needs it): where a count is odd, one curve gets its samples with one
// chord more, or one straight stretch of boundary one segment more.
// `edges_per_lattice_edge` (1, 2, 4, ...: dx over the free cells' target
// size, pd-mesh --box-spacing) cuts every lattice edge between a free cell
// and a square into that many boundary edges, and straight runs of boundary
// into pieces of about dx / edges_per_lattice_edge, so that the free mesh is
// as fine at its edges as inside; the curves' samples come from the geometry.
FreeRegions free_regions(const PlateGeometry& geometry, const CellMap& cells, int edges_per_lattice_edge = 1);

}  // namespace pd
