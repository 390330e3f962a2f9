#include "box_spacing.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"
#include "plate_geometry.hpp"
#include "refinement.hpp"
#include "units.hpp"

namespace pd {

int box_edges_per_lattice_edge(double box_spacing, double spacing) {
  return static_cast<int>(std::lround(spacing / box_spacing));
}

double parse_box_spacing(const std::string& text, double spacing, const std::string& option) {
  const double box = parse_length(text, option);
  const std::string given = option + " " + text + " (" + format_mm(box) + ")";
  if (!std::isfinite(box) || !(box > 0)) throw Error(given + ": expected a finite, positive length");
  if (box > spacing * (1 + 1e-12))
    throw Error(given + ": larger than the spacing " + format_mm(spacing) +
                "; the boxes can be as fine as the squares or finer, not coarser");
  // dx / DXB within round-off of a power of two up to the finest refinement.
  const double ratio = spacing / box;
  const long k = std::lround(ratio);
  const bool power_of_two = k >= 1 && k <= max_refinement_factor && (k & (k - 1)) == 0 &&
                            std::fabs(ratio - static_cast<double>(k)) <= 1e-9 * ratio;
  if (!power_of_two)
    throw Error(given + ": expected the spacing " + format_mm(spacing) + " divided by 1, 2, 4, ... or " +
                std::to_string(max_refinement_factor) + " (e.g. " + format_mm(spacing / 2) + " or " +
                format_mm(spacing / 4) + ")");
  // The exact quotient, so that cells and horizons see dx / 2^k to the last bit.
  return spacing / static_cast<double>(k);
}

FinerBoxesEstimate finer_boxes_estimate(const PlateGeometry& geometry, double spacing, double box_spacing,
                                        double padding, double horizon_smoothing) {
  FinerBoxesEstimate e;
  if (!(box_spacing > 0 && box_spacing < spacing)) return e;
  const double k = spacing / box_spacing, grow = 2 * (padding + spacing);
  double box_area = 0, box_band = 0;
  for (const auto& hole : geometry.holes) {
    box_area += (hole.xmax - hole.xmin + grow) * (hole.ymax - hole.ymin + grow) - hole.area;
    box_band += 2 * ((hole.xmax - hole.xmin + grow) + (hole.ymax - hole.ymin + grow)) * horizon_smoothing;
  }
  e.extra_area = box_area * (k * k - 1);
  e.smoothed_extra_bond_area = std::min(box_band, box_area) * k * k * ((k * k + k + 1) / 3 - 1);
  return e;
}

}  // namespace pd
