#include "horizon_smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "error.hpp"
#include "neighbor_search.hpp"
#include "units.hpp"

namespace pd {

double parse_smoothing_length(const std::string& text, const std::string& option) {
  const double length = parse_length(text, option);
  if (!(std::isfinite(length) && length >= 0))
    throw Error(option + " '" + text + "': expected a length >= 0 (e.g. 0.5mm)");
  return length;
}

double smoothed_horizon(double fine_horizon, double coarse_horizon, double distance, double smoothing_length) {
  if (!(smoothing_length > 0)) return fine_horizon;
  return fine_horizon + (coarse_horizon - fine_horizon) * std::max(0.0, 1.0 - distance / smoothing_length);
}

namespace {

// The region's edges that face other cells of the bounding box, as lattice
// lines: x = xmin + i dx for the left/right ones, y = ymin + j dx for the others.
struct InterfaceEdges {
  bool left = false, right = false, bottom = false, top = false;
};

InterfaceEdges interface_edges(const SnappedRegion& s, long columns, long rows) {
  return {s.i0 > 0, s.i1 < columns, s.j0 > 0, s.j1 < rows};
}

// Particle i at `distance` from the coarse side: its horizon by the rule,
// counted in `report`.
void smooth_one(ParticleSet& p, std::size_t i, double distance, double smoothing_length, SmoothingReport& report) {
  const double smoothed = smoothed_horizon(p.horizon[i], p.horizon_nominal, distance, smoothing_length);
  if (smoothed < report.smallest_horizon) {
    report.smallest_horizon = smoothed;
    report.fine_horizon = p.horizon[i];
  }
  if (smoothed > p.horizon[i]) {
    p.horizon[i] = smoothed;
    ++report.grown;
  }
}

}  // namespace

SmoothingReport smooth_horizons(ParticleSet& p, const RefinementRegion& region, double smoothing_length,
                                const std::string& option) {
  SmoothingReport report;
  if (!(smoothing_length > 0)) return report;
  const double dx = p.spacing;
  const SnappedRegion s = snap_to_lattice(region, dx, p.xmin, p.ymin, p.xmax, p.ymax, option);
  const long columns = std::lround((p.xmax - p.xmin) / dx), rows = std::lround((p.ymax - p.ymin) / dx);
  const InterfaceEdges faces = interface_edges(s, columns, rows);
  const double x0 = p.xmin + s.i0 * dx, x1 = p.xmin + s.i1 * dx;
  const double y0 = p.ymin + s.j0 * dx, y1 = p.ymin + s.j1 * dx;
  report.smallest_horizon = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool refined_square =
        p.region[i] == static_cast<std::uint8_t>(Region::uniform_square) && p.cell_size[i] < dx * (1 - 1e-9);
    if (!refined_square || p.x[i] < x0 || p.x[i] > x1 || p.y[i] < y0 || p.y[i] > y1) continue;
    // Inside the rectangle the nearest coarse cell beyond an edge is straight across it.
    double distance = std::numeric_limits<double>::infinity();
    if (faces.left) distance = std::min(distance, p.x[i] - x0);
    if (faces.right) distance = std::min(distance, x1 - p.x[i]);
    if (faces.bottom) distance = std::min(distance, p.y[i] - y0);
    if (faces.top) distance = std::min(distance, y1 - p.y[i]);
    ++report.finer_cells;
    if (std::isfinite(distance)) ++report.facing_coarse;
    report.deepest = std::max(report.deepest, distance);
    smooth_one(p, i, distance, smoothing_length, report);
  }
  return report;
}

SmoothingReport smooth_box_horizons(ParticleSet& p, double smoothing_length) {
  SmoothingReport report;
  if (!(smoothing_length > 0)) return report;
  const double dx = p.spacing, half = 0.5 * dx;
  // The squares at the nominal horizon.
  std::vector<double> square_x, square_y;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.region[i] == static_cast<std::uint8_t>(Region::uniform_square) && p.cell_size[i] > dx * (1 - 1e-9))
      square_x.push_back(p.x[i]), square_y.push_back(p.y[i]);
  const auto fine_box_cell = [&](std::size_t i) {
    return p.region[i] == static_cast<std::uint8_t>(Region::box_free_mesh) &&
           p.horizon[i] < p.horizon_nominal * (1 - 1e-9);
  };
  for (std::size_t i = 0; i < p.size(); ++i) report.finer_cells += fine_box_cell(i);
  if (square_x.empty()) return report;
  report.facing_coarse = report.finer_cells;  // some square of side dx is at a finite distance
  const NeighborSearch squares(square_x, square_y);
  std::vector<std::uint32_t> near;
  report.smallest_horizon = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!fine_box_cell(i)) continue;
    // A square whose nearest point is within L_s has its centre within L_s
    // plus half its diagonal.
    squares.within(p.x[i], p.y[i], smoothing_length + std::sqrt(2.0) * half, near);
    double distance = std::numeric_limits<double>::infinity();
    for (auto k : near) {
      const double ex = std::max(std::fabs(p.x[i] - square_x[k]) - half, 0.0);
      const double ey = std::max(std::fabs(p.y[i] - square_y[k]) - half, 0.0);
      distance = std::min(distance, std::hypot(ex, ey));
    }
    report.deepest = std::max(report.deepest, std::min(distance, smoothing_length));
    smooth_one(p, i, distance, smoothing_length, report);
  }
  return report;
}

double smoothing_band_area(const SnappedRegion& s, double dx, long columns, long rows, double smoothing_length) {
  const InterfaceEdges faces = interface_edges(s, columns, rows);
  const double width = (s.i1 - s.i0) * dx, height = (s.j1 - s.j0) * dx;
  const double inner_width = std::max(0.0, width - smoothing_length * (faces.left + faces.right));
  const double inner_height = std::max(0.0, height - smoothing_length * (faces.bottom + faces.top));
  return width * height - inner_width * inner_height;
}

}  // namespace pd
