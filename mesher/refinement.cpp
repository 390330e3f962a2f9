#include "refinement.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <vector>

#include "cli.hpp"
#include "error.hpp"
#include "families.hpp"
#include "horizon_smoothing.hpp"
#include "lattice.hpp"
#include "units.hpp"

namespace pd {

RefinementRegion parse_refinement_region(const std::string& text, const std::string& factor_text,
                                         const std::string& option, const std::string& factor_option) {
  // Split as every tool splits its lists (blanks around an item are not
  // part of it); an empty item is refused by its place. Before 7 December
  // 2026 a trailing comma was dropped without a word, and a blank before a
  // comma was "characters after the length".
  const std::vector<std::string> parts = comma_items(text);
  const std::string expected = "expected X0,Y0,X1,Y1 with units (e.g. 10mm,0mm,20mm,5mm)";
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k].empty())
      throw Error(option + " '" + text + "': item " + std::to_string(k + 1) + " is empty: " + expected);
  if (parts.size() != 4) throw Error(option + " '" + text + "': " + expected);
  RefinementRegion r;
  r.x0 = parse_length(parts[0], option);
  r.y0 = parse_length(parts[1], option);
  r.x1 = parse_length(parts[2], option);
  r.y1 = parse_length(parts[3], option);
  if (!(r.x1 > r.x0 && r.y1 > r.y0))
    throw Error(option + " '" + text + "': the rectangle is empty (X1 > X0 and Y1 > Y0 are required)");
  // Read as typed: 2.5, abc or a count beyond an int got Boost's "the
  // argument ('2.5') for option '--refine-factor' is invalid" before 7
  // December 2026, which named no valid factor.
  int factor = 0;
  if (!factor_text.empty() && factor_text.size() <= 3 &&
      std::all_of(factor_text.begin(), factor_text.end(), [](unsigned char c) { return std::isdigit(c); }))
    factor = std::stoi(factor_text);
  bool power_of_two = factor >= 2 && factor <= max_refinement_factor && (factor & (factor - 1)) == 0;
  if (!power_of_two)
    throw Error(factor_option + " " + factor_text + ": expected a power of two from 2 to " +
                std::to_string(max_refinement_factor));
  r.factor = factor;
  return r;
}

SnappedRegion snap_to_lattice(const RefinementRegion& r, double dx, double xmin, double ymin, double xmax,
                              double ymax, const std::string& option) {
  // Outward to whole cells; a rectangle edge within 1e-9 dx of a lattice line is on it.
  // (In cells from the plate's corner, clamped to a cell beyond the plate
  // first: a coordinate of 1e300 m would overflow the conversion.)
  const long nx = std::lround((xmax - xmin) / dx), ny = std::lround((ymax - ymin) / dx);
  const auto cells = [&](double v, double origin, long n) {
    return std::clamp((v - origin) / dx, -1.0, static_cast<double>(n) + 1.0);
  };
  const auto below = [&](double v, double origin, long n) {
    return static_cast<long>(std::floor(cells(v, origin, n) + 1e-9));
  };
  const auto above = [&](double v, double origin, long n) {
    return static_cast<long>(std::ceil(cells(v, origin, n) - 1e-9));
  };
  SnappedRegion s;
  s.i0 = std::max(0L, below(r.x0, xmin, nx));
  s.i1 = std::min(nx, above(r.x1, xmin, nx));
  s.j0 = std::max(0L, below(r.y0, ymin, ny));
  s.j1 = std::min(ny, above(r.y1, ymin, ny));
  if (s.i1 <= s.i0 || s.j1 <= s.j0)
    throw Error(option + ": the rectangle [" + format_mm(r.x0) + ", " + format_mm(r.x1) + "] x [" + format_mm(r.y0) +
                ", " + format_mm(r.y1) + "] does not meet the plate's bounding box");
  return s;
}

namespace {

// Whether particle i is a lattice square of side dx in the snapped region:
// what refine_squares splits, and what region_squares counts.
bool square_in_region(const ParticleSet& p, std::size_t i, const SnappedRegion& s) {
  const double dx = p.spacing;
  if (p.region[i] != static_cast<std::uint8_t>(Region::uniform_square) || p.cell_size[i] != dx) return false;
  const long col = static_cast<long>(std::floor((p.x[i] - p.xmin) / dx));
  const long row = static_cast<long>(std::floor((p.y[i] - p.ymin) / dx));
  return col >= s.i0 && col < s.i1 && row >= s.j0 && row < s.j1;
}

}  // namespace

std::size_t region_squares(const ParticleSet& p, const RefinementRegion& region, const std::string& option) {
  const SnappedRegion s = snap_to_lattice(region, p.spacing, p.xmin, p.ymin, p.xmax, p.ymax, option);
  std::size_t count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) count += square_in_region(p, i, s) ? 1 : 0;
  return count;
}

std::size_t refine_squares(ParticleSet& p, const RefinementRegion& region, const std::string& option) {
  // Splitting renumbers the particles: sets and families come afterwards.
  if (!p.sets.empty() || !p.neighbors.empty())
    throw Error("refine_squares: refine before the families and boundary sets are built");
  const double dx = p.spacing;
  const SnappedRegion s = snap_to_lattice(region, dx, p.xmin, p.ymin, p.xmax, p.ymax, option);
  const auto inside = [&](std::size_t i) { return square_in_region(p, i, s); };
  ParticleSet q = empty_like(p);
  const int f = region.factor;
  const double fine = dx / f;
  std::size_t split = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (inside(i)) {
      // The fine cells of this coarse cell, on the fine lattice from the box corner.
      const long col = static_cast<long>(std::floor((p.x[i] - p.xmin) / dx));
      const long row = static_cast<long>(std::floor((p.y[i] - p.ymin) / dx));
      const std::size_t first = q.size();
      append_lattice_squares(q, p.xmin, p.ymin, fine, col * f, (col + 1) * f, row * f, (row + 1) * f,
                             [](long, long) { return true; }, Region::uniform_square);
      for (std::size_t k = first; k < q.size(); ++k) q.material[k] = p.material[i];
      ++split;
      continue;
    }
    append_particle(q, p, i);
  }
  q.provenance = std::move(p.provenance);
  p = std::move(q);
  return split;
}

void assign_horizons(ParticleSet& p, double nominal, double box_spacing) {
  p.horizon_nominal = nominal;
  const double box_horizon = box_spacing > 0 ? nominal * (box_spacing / p.spacing) : nominal;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto region = static_cast<Region>(p.region[i]);
    p.horizon[i] = region == Region::uniform_square  ? nominal * (p.cell_size[i] / p.spacing)
                   : region == Region::box_free_mesh ? box_horizon
                                                     : nominal;
  }
}

ParticleSet make_refined_rectangle_lattice(double width, double height, double dx, double nominal_horizon,
                                           const RefinementRegion& region, Quadrature quadrature,
                                           double smoothing_length) {
  // The coarse plate without families, then the split and the families of the result.
  ParticleSet p = make_rectangle_lattice(width, height, dx, nominal_horizon, quadrature);
  p.family_offsets.clear();
  p.neighbors.clear();
  p.partial_volume.clear();
  p.sets.clear();
  refine_squares(p, region, "refinement region");
  assign_horizons(p, nominal_horizon);
  smooth_horizons(p, region, smoothing_length, "refinement region");
  build_families(p, quadrature);
  add_rectangle_edge_sets(p, width, height, nominal_horizon);
  p.provenance = "{\"generator\": \"make_refined_rectangle_lattice\"}";
  return p;
}

}  // namespace pd
