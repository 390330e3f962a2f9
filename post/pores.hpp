#pragma once
// Pores (circular holes) of a perforated plate, and the times a crack tip
// spends trapped in them [Peng, Chen, Bobaru 2023, Sec. 5: "trapping time",
// from arriving at a pore to re-initiating on its other side].
#include <cstdint>
#include <string>
#include <vector>

#include "arrival_data.hpp"

namespace pd::post {

// A detected hole's own shape, for a hole far from round: its cells of the
// raster pd-post finds holes on (detect_pores).
struct PoreOutline {
  double x0 = 0, y0 = 0;  // corner of the raster window that holds the hole [m]
  double cell = 0;        // side of a raster cell [m]
  long nx = 0, ny = 0;    // the window's cells
  std::vector<std::uint8_t> inside;     // nx * ny, row by row: 1 for the hole's cells
  std::vector<double> edge_x, edge_y;   // centres of the hole's cells next to material [m]
  bool contains(double px, double py) const;
};

struct Pore {
  double x = 0, y = 0;  // centre [m] (detected: the hole's centroid)
  double radius = 0;    // [m] (detected: of the circle of equal area)
  int line = 0;         // of the pore file, for messages (0: detected)
  double reach = 0;     // detected: the farthest cell of the hole's outline (spurs removed) from its centre [m]
  PoreOutline outline;  // a detected hole far from round; empty: the circle stands for the pore

  bool has_outline() const { return !outline.inside.empty(); }
  // Distance [m] from (px, py) to the pore's edge; <= 0 inside the pore.
  double edge_distance(double px, double py) const;
  // Whether (px, py) lies within `ring` [m] of the pore's edge or inside it.
  bool within(double px, double py, double ring) const;
  // Radius [m] of the circle about (x, y) that holds the whole pore.
  double enclosing_radius() const;
  // Whether the pore's inside holds (px, py).
  bool contains(double px, double py) const;
  // Length [m] of the segment (x0, y0)-(x1, y1) inside the pore (an
  // outline: in steps of half a raster cell).
  double length_inside(double x0, double y0, double x1, double y1) const;
  double x_min() const;  // [m] the pore's extent along x
  double x_max() const;
};

// A pore given as a circle: centre (x, y) and radius [m].
inline Pore circle_pore(double x, double y, double radius) {
  Pore p;
  p.x = x, p.y = y, p.radius = radius;
  return p;
}

// Reads "x_m,y_m,r_m" lines (header line and '#' comments allowed).
std::vector<Pore> read_pores_csv(const std::string& path);

// The smallest radius of a pore file's circle, in sizes of the cells about
// it: a disk of a quarter of a cell takes pi / 16 of one, less than a fifth.
inline constexpr double smallest_pore_file_cells = 0.25;

// The circles of pore file `path` against the plate of `data`: refused
// (pd::Error naming the file, the line and the circle) when one lies off the
// plate, or when a particle centre lies closer than 0.8 r to its centre (a
// pore's cells are removed, so a circle in solid material would report
// made-up visits; 0.8 allows a slightly generous circle around a real hole),
// or when its centre lies in a particle's cell (within 0.8 of its half side:
// a circle smaller than a cell, which holds no centre).
// A circle whose radius is less than smallest_pore_file_cells of the cell
// of the particle nearest its centre is refused too (centred between cells,
// it passes the checks above, yet the particles cannot show it).
// Two circles whose centres are within a spacing of each other are a warning.
void check_pore_file(const std::string& path, const std::vector<Pore>& pores, const ArrivalData& data,
                     std::vector<std::string>& warnings);

// Finds the holes of the particle layout: cells not covered by any
// particle's square (side = cell_size), connected, and not touching the
// outer boundary. Each becomes the circle of the same area centred on its
// centroid; a hole whose outline (its raster cells less the spurs that gaps
// between free cells beside it add) reaches more than a cell beyond that
// circle (an ellipse, a slot, a traced pore with lobes, pores that touch)
// keeps its outline too, since a crack there lies outside the circle's
// ring. Holes smaller than `smallest_pore_cells` cell sizes in radius are
// ignored (gaps of irregular grids, not pores); those of at least 0.75 cell
// sizes (more than a gap between cells) go to `ignored`, for a note.
// A layout whose raster would exceed `max_pore_raster_cells` (a few
// particles far apart) is not searched: a warning saying so goes to
// `warnings`.
std::vector<Pore> detect_pores(const ArrivalData& data, std::vector<Pore>* ignored = nullptr,
                               std::vector<std::string>* warnings = nullptr);

// The most raster cells (of half the typical cell size, one byte each)
// detect_pores lays over the plate: 200 MB.
inline constexpr double max_pore_raster_cells = 2e8;

// The smallest radius of a detected pore, in cell sizes. The gaps between
// free cells measure below 0.75; a pore of 1.5 spacings (C3's at dx = 0.5 mm)
// rasterises to 1.47 to 1.49, so 1.5 counted some of a plate's identical
// pores and not others.
inline constexpr double smallest_pore_cells = 1.25;

struct CrackBranch;
struct TipPath;

struct PoreVisit {
  int pore = 0;
  int branch = 0;
  double enter_time = 0;    // [s] tip first within the pore's ring
  double enter_x = 0, enter_y = 0;
  double restart_time = -1; // [s] crack re-initiated beyond the pore; -1 = never
  double trapping_time = -1;  // restart_time - enter_time, -1 if never restarted
  bool jumped = false;        // restarted beyond the pore (not just grazing past)
};

// For every branch and pore: the tip enters when it comes within `ring` of
// the pore's edge, having started outside and been more than 2 `ring` from
// the edge before (a tip first seen just beyond the ring that steps into it
// belongs to a crack nucleated at the pore's edge); it restarts at the first of
//  - the first particle of the branch cracked later within the ring beyond
//    the pore (a round pore: its far half, more than 90 degrees around from
//    the entry point; an outlined one: the straight line from the entry
//    point crosses a cell size of it), or of another branch that starts
//    within the ring (the crack forking at the pore, or nucleating on its
//    far side while the tip waits),
//  - the first time the tip is outside the ring again (a crack grazing the pore).
// A pore that no tip enters from outside, but where a branch forks off its
// parent within the ring, is visited by the parent at the earliest such fork
// (entering at the fork's birth); it restarts at the first far-half particle
// of a branch born within the ring, or when one of those forks' tips first
// leaves the ring. A restart is always after the entry (trapping time > 0):
// particles cracked and tips that left the ring at or before it are no
// restart. Visits are listed by branch, then by pore.
std::vector<PoreVisit> find_pore_visits(const std::vector<CrackBranch>& branches,
                                        const std::vector<TipPath>& tips,
                                        const std::vector<Pore>& pores, const ArrivalData& data,
                                        double ring);

}  // namespace pd::post
