#include "graded_spacing.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cli.hpp"
#include "error.hpp"
#include "refinement.hpp"
#include "units.hpp"

namespace pd {

double GradedSpacing::size_at(double distance) const {
  return fine + (coarse - fine) * std::min(1.0, std::max(0.0, distance) / length);
}

GradedSpacing parse_graded_spacing(const std::string& text, double spacing, double horizon,
                                   const std::string& option) {
  // Split as every tool splits its lists (blanks around an item are not
  // part of it); an empty item is refused by its place. Before 7 December
  // 2026 split at the first comma: a trailing comma (`0.5mm,`) was dropped
  // without a word, and `0.5mm,,4mm` was "',4mm' is not a length".
  const std::vector<std::string> items = comma_items(text);
  const std::string given = option + " " + text;
  const std::string expected = "expected DXF or DXF,L with units (e.g. 0.05mm or 0.05mm,2mm)";
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].empty()) throw Error(given + ": item " + std::to_string(k + 1) + " is empty: " + expected);
  if (items.empty() || items.size() > 2) throw Error(given + ": " + expected);
  const std::string& fine_text = items[0];
  const std::string length_text = items.size() == 2 ? items[1] : "";
  GradedSpacing g;
  g.coarse = spacing;
  g.fine = parse_length(fine_text, option);
  if (!std::isfinite(g.fine) || !(g.fine > 0))
    throw Error(given + ": the fine size DXF " + fine_text + " must be a finite, positive length");
  if (!(g.fine < spacing * (1 - 1e-12)))
    throw Error(given + ": the fine size DXF " + format_mm(g.fine) + " is not smaller than the spacing " +
                format_mm(spacing) + " (a graded mesh grows from DXF at the curved boundaries to dx)");
  if (spacing / g.fine > max_refinement_factor * (1 + 1e-12))
    throw Error(given + ": the fine size DXF " + format_mm(g.fine) + " is below the spacing / " +
                std::to_string(max_refinement_factor) + " (" + format_mm(spacing / max_refinement_factor) +
                "), the finest cell a particle file holds");
  g.length = length_text.empty() ? default_grading_horizons * horizon : parse_length(length_text, option);
  if (!std::isfinite(g.length) || !(g.length > 0))
    throw Error(given + ": the grading length L " + length_text + " must be a finite, positive length");
  // Growth per unit length (dx - DXF) / L at most 1/2: a cell of size h is
  // followed by one of at most 1.5 h.
  const double shortest = 2 * (spacing - g.fine);
  if (g.length < shortest * (1 - 1e-12))
    throw Error(given + ": the grading length L " + format_mm(g.length) + " is too short; at least 2 (dx - DXF) = " +
                format_mm(shortest) + ", so that the cell size grows by at most half a cell per cell");
  return g;
}

CurvedBoundaryDistance::CurvedBoundaryDistance(const PlateGeometry& geometry) {
  for (const auto* loop : geometry.loops())
    for (const auto& c : loop->curves) {
      if (c.straight()) continue;
      const auto& s = c.samples;
      for (std::size_t k = 0; k < s.chords(); ++k) {
        Vec2 from = s.points[k];
        for (const Vec2 to : s.arc[k]) {
          a_.push_back(from), b_.push_back(to);
          from = to;
        }
        a_.push_back(from), b_.push_back(s.points[k + 1]);
      }
    }
  for (std::size_t k = 0; k < a_.size(); ++k) {
    mid_x_.push_back(0.5 * (a_[k].x + b_[k].x));
    mid_y_.push_back(0.5 * (a_[k].y + b_[k].y));
    half_longest_ = std::max(half_longest_, 0.5 * std::hypot(b_[k].x - a_[k].x, b_[k].y - a_[k].y));
  }
  search_ = std::make_unique<NeighborSearch>(mid_x_, mid_y_);
}

CurvedBoundaryDistance::~CurvedBoundaryDistance() = default;

double CurvedBoundaryDistance::distance(Vec2 p, double cap) const {
  if (a_.empty()) return cap;
  // Every segment within distance r - half_longest_ of p has its midpoint
  // within r: widen r until the nearest segment found is that close, or r
  // reaches the cap.
  std::vector<std::uint32_t> near;
  double radius = 8 * half_longest_;
  while (true) {
    const double reach = std::min(radius, cap + half_longest_);
    search_->within(p.x, p.y, reach, near);
    double best = cap;
    for (auto k : near) best = std::min(best, point_segment_distance(p, a_[k], b_[k]));
    if (best <= reach - half_longest_ || reach >= cap + half_longest_) return best;
    radius *= 4;
  }
}

std::size_t assign_graded_horizons(ParticleSet& p, const PlateGeometry& geometry, const GradedSpacing& graded) {
  const CurvedBoundaryDistance curves(geometry);
  const double m = p.horizon_nominal / p.spacing;
  std::size_t below = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.region[i] != static_cast<std::uint8_t>(Region::other)) continue;
    const double h = graded.size_at(curves.distance({p.x[i], p.y[i]}, graded.length));
    // h = dx beyond L: the nominal horizon to the last bit.
    p.horizon[i] = h >= graded.coarse ? p.horizon_nominal : m * h;
    below += p.horizon[i] < p.horizon_nominal;
  }
  return below;
}

bool has_curved_boundary(const PlateOutline& outline) {
  for (const auto& loop : outline.loops)
    for (const auto& c : loop)
      if (c.type != "Line") return true;
  return false;
}

double graded_extra_area(const PlateGeometry& geometry, const GradedSpacing& g) {
  double extra = 0;
  for (const auto* loop : geometry.loops()) {
    double curved_length = 0;
    for (const auto& c : loop->curves)
      if (!c.straight()) curved_length += c.length;
    if (curved_length == 0) continue;
    // Integral over d in [0, L] of (l + 2 pi d) ((dx / h(d))^2 - 1), midpoint rule.
    constexpr int steps = 256;
    const double step = g.length / steps;
    for (int s = 0; s < steps; ++s) {
      const double d = (s + 0.5) * step, h = g.size_at(d);
      extra += (curved_length + 2 * M_PI * d) * ((g.coarse / h) * (g.coarse / h) - 1) * step;
    }
  }
  // No more than the whole plate meshed at the fine size: a long L's bands
  // reach far past the plate (L = 1e6 mm estimated 1.7e12 particles).
  const double ratio = g.coarse / g.fine;
  return std::min(extra, geometry.exact_area() * (ratio * ratio - 1));
}

}  // namespace pd
