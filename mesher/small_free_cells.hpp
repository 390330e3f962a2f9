#pragma once
// Free cells much smaller than the size their horizon was chosen for. A
// hole or notch narrower than the spacing has a boundary of a few short
// chords (every loop gets at least 8), so gmsh meshes around it with cells
// of about that chord; each keeps the horizon m x its box's target size, and
// its family holds (target / cell)^2 times the usual count: bonds, memory
// and time blow up while the estimate from the area looks harmless. Found
// from the cells, said with the features narrower than the spacing and what
// to do.
#include <string>
#include <vector>

#include "feature_sizes.hpp"
#include "geometry.hpp"
#include "particle_file.hpp"
#include "resource_estimate.hpp"

namespace pd {

struct SmallFreeCells {
  std::size_t free_cells = 0;   // cells of free meshes (NB-NUG boxes and bands, the free grid)
  std::size_t small = 0;        // those below half the size their horizon assumes
  // sqrt(area) / (horizon / m), m = nominal horizon / dx: 1 for a cell of
  // its target size (dx, the box spacing, a graded mesh's local size).
  double median_ratio = 1, smallest_ratio = 1;  // over the free cells
  double median_small_size = 0;  // median sqrt(area) of the small cells [m]
  double target_size = 0;        // target size of the median small cell [m]
  Vec2 smallest_at;              // centroid of the cell of the smallest ratio [m]
  double small_family = 0;       // mean estimated family size of the small cells
  double usual_family = 0;       // a square's family far from boundaries, at m
  // Worth a warning: some cells are small, and the free cells' median is
  // small too or the small cells' families average over twice the usual
  // count (a lone small hole in a large box costs little and is not said).
  bool forced() const;
};

// From the cells and their estimated family sizes (family_size_estimate.hpp).
// A cell's target size is its horizon / m; a box cell's, with boxes meshed
// at `box_spacing` DXB > 0, is DXB (a smoothed horizon, grown towards the
// squares, is no smaller target).
SmallFreeCells find_small_free_cells(const ParticleSet& particles, const std::vector<double>& family_sizes,
                                     double box_spacing = 0);

// What pd-mesh offers for such cells, for messages: {"--box-spacing 0.25mm
// (...)", "a --spacing of 0.25 mm or less"}. `box_spacing`, `graded_fine`
// [m]: the options as given (0: not given).
std::vector<std::string> small_free_cells_remedies(const SmallFreeCells& cells, const ParticleSet& particles,
                                                   double box_spacing, double graded_fine);

// Why the bonds are many, for the refusal of a grid over the memory budget:
// "its free cells are 0.25 mm across (median of the small ones) and each
// keeps the horizon 3 mm".
std::string small_free_cells_cause(const SmallFreeCells& cells, const ParticleSet& particles);

// The warning line (without "pd-mesh: warning: "): the features narrower
// than the spacing among `narrow` that force the cells, their size, the
// bonds per particle there against the usual count, the bonds, memory and
// file of the whole grid (`grid`), and the remedies.
std::string small_free_cells_warning(const std::string& file, const SmallFreeCells& cells,
                                     const ParticleSet& particles, const std::vector<NarrowVoid>& narrow,
                                     const ResourceEstimate& grid, std::vector<std::string> remedies);

}  // namespace pd
