#include "line_profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "arrival_data.hpp"
#include "atomic_file.hpp"
#include "cli.hpp"
#include "error.hpp"
#include "neighbor_search.hpp"
#include "units.hpp"

namespace pd::post {
namespace {

// Least-squares plane v = c0 + c1 a + c2 b through (a_i, b_i, v_i) for two
// fields at once; returns false when the points do not span a plane.
// Coordinates come scaled to about 1 (units of dx), so the 3 x 3 normal
// equations are well conditioned.
bool fit_plane(const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& v1,
               const std::vector<double>& v2, double& c1, double& c2) {
  const std::size_t n = a.size();
  if (n < 3) return false;
  double m[3][3] = {}, r1[3] = {}, r2[3] = {};
  for (std::size_t i = 0; i < n; ++i) {
    const double row[3] = {1.0, a[i], b[i]};
    for (int p = 0; p < 3; ++p) {
      for (int q = 0; q < 3; ++q) m[p][q] += row[p] * row[q];
      r1[p] += row[p] * v1[i];
      r2[p] += row[p] * v2[i];
    }
  }
  auto det3 = [](const double k[3][3]) {
    return k[0][0] * (k[1][1] * k[2][2] - k[1][2] * k[2][1]) - k[0][1] * (k[1][0] * k[2][2] - k[1][2] * k[2][0]) +
           k[0][2] * (k[1][0] * k[2][1] - k[1][1] * k[2][0]);
  };
  const double det = det3(m);
  // Collinear points: the determinant is round-off of n^3.
  if (std::abs(det) <= 1e-9 * static_cast<double>(n * n * n)) return false;
  // Cramer's rule for the constant term c0 only (the value at the sample).
  auto constant = [&](const double r[3]) {
    double k[3][3];
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) k[p][q] = q == 0 ? r[p] : m[p][q];
    return det3(k) / det;
  };
  c1 = constant(r1);
  c2 = constant(r2);
  return true;
}

}  // namespace

SampleLine parse_sample_line(const std::string& text, const std::string& option) {
  std::vector<double> v;
  for (const auto& item : comma_items(text)) v.push_back(parse_length(item, option));
  if (v.size() != 4)
    throw Error(option + ": expected x0,y0,x1,y1 with a unit on each, e.g. 10mm,12.5mm,40mm,12.5mm");
  SampleLine l{v[0], v[1], v[2], v[3]};
  if (std::hypot(l.x1 - l.x0, l.y1 - l.y0) <= 0) throw Error(option + ": the two end points are the same");
  return l;
}

std::vector<LineSample> sample_line(const ParticleFields& f, const SampleLine& line, double dx, double d) {
  const double length = std::hypot(line.x1 - line.x0, line.y1 - line.y0);
  const double tx = (line.x1 - line.x0) / length, ty = (line.y1 - line.y0) / length;
  const double nx = -ty, ny = tx;
  // (check_line_reach keeps a line within reach; this keeps the cast defined whatever the caller.)
  const double count = std::ceil(length / dx - 1e-9);
  if (!(count < 1e9))
    throw Error("--line: " + shortest_text(length) + " m sampled every " + shortest_text(dx) + " m is more samples "
                "than can be taken");
  const int intervals = std::max(1, static_cast<int>(count));
  NeighborSearch search(f.x, f.y);
  std::vector<std::uint32_t> near;
  std::vector<LineSample> out;
  struct Side {
    std::vector<double> a, b, ux, uy;
    void clear() { a.clear(), b.clear(), ux.clear(), uy.clear(); }
  } on_line, plus, minus;
  for (int k = 0; k <= intervals; ++k) {
    LineSample s;
    s.s = length * k / intervals;
    s.x = line.x0 + s.s * tx;
    s.y = line.y0 + s.s * ty;
    on_line.clear(), plus.clear(), minus.clear();
    search.within(s.x, s.y, std::hypot(dx, 2 * d) * (1 + 1e-9), near);
    double nearest = 1e300;
    for (auto i : near) {
      const double ex = f.x[i] - s.x, ey = f.y[i] - s.y;
      const double a = ex * tx + ey * ty, b = ex * nx + ey * ny;
      const double r = std::hypot(ex, ey);
      if (r < nearest) nearest = r, s.damage = f.damage[i];
      if (std::abs(a) > dx * (1 + 1e-9)) continue;
      Side* side = nullptr;
      if (std::abs(b) <= dx * (1 + 1e-9)) side = &on_line;
      for (Side* target : {side, b >= d * (1 - 1e-9) && b <= 2 * d * (1 + 1e-9) ? &plus : nullptr,
                           -b >= d * (1 - 1e-9) && -b <= 2 * d * (1 + 1e-9) ? &minus : nullptr}) {
        if (!target) continue;
        target->a.push_back(a / dx);
        target->b.push_back(b / dx);
        target->ux.push_back(f.ux[i]);
        target->uy.push_back(f.uy[i]);
      }
    }
    // A point inside any cell is within half a diagonal (0.71 dx) of its
    // centre; one spacing also keeps samples in gaps narrower than a cell.
    // Farther out (a hole, beside the plate) no particle's damage is the
    // sample's: it is written empty, not that of a particle a horizon away.
    s.on_plate = nearest <= dx * (1 + 1e-9);
    if (!s.on_plate) s.damage = 0;
    s.has_u = fit_plane(on_line.a, on_line.b, on_line.ux, on_line.uy, s.ux, s.uy);
    double px, py, mx, my;
    if (fit_plane(plus.a, plus.b, plus.ux, plus.uy, px, py) &&
        fit_plane(minus.a, minus.b, minus.ux, minus.uy, mx, my)) {
      s.has_jump = true;
      s.opening = (px - mx) * nx + (py - my) * ny;
      s.sliding = (px - mx) * tx + (py - my) * ty;
    }
    out.push_back(s);
  }
  return out;
}

std::string check_line_on_plate(const std::vector<LineSample>& samples, const SampleLine& line,
                                const std::vector<double>& x, const std::vector<double>& y, double dx,
                                const std::string& option) {
  if (x.empty()) return "";
  const auto [x_min, x_max] = std::minmax_element(x.begin(), x.end());
  const auto [y_min, y_max] = std::minmax_element(y.begin(), y.end());
  // Beyond the particles' extent by more than a spacing is off the plate;
  // a sample in a hole is not counted (a line across a hole is meant).
  std::size_t on = 0, outside = 0;
  for (const auto& s : samples) {
    on += s.on_plate ? 1 : 0;
    outside += s.x < *x_min - dx || s.x > *x_max + dx || s.y < *y_min - dx || s.y > *y_max + dx ? 1 : 0;
  }
  char extent[160];
  std::snprintf(extent, sizeof extent, "the plate's particles span x %g to %g mm, y %g to %g mm", *x_min * 1e3,
                *x_max * 1e3, *y_min * 1e3, *y_max * 1e3);
  char text[400];
  if (on == 0) {
    std::snprintf(text, sizeof text,
                  "%s: the line from (%g, %g) mm to (%g, %g) mm meets no particle (%s): give a line across the "
                  "plate, lengths with their unit (e.g. %s 10mm,12.5mm,40mm,12.5mm)",
                  option.c_str(), line.x0 * 1e3, line.y0 * 1e3, line.x1 * 1e3, line.y1 * 1e3, extent,
                  option.c_str());
    throw Error(text);
  }
  if (outside == 0) return "";
  std::snprintf(text, sizeof text,
                "%s: %zu of the %zu samples of the line from (%g, %g) mm to (%g, %g) mm lie off the plate (%s): "
                "their values in line_profile.csv are empty",
                option.c_str(), outside, samples.size(), line.x0 * 1e3, line.y0 * 1e3, line.x1 * 1e3, line.y1 * 1e3,
                extent);
  return text;
}

void check_line_reach(const SampleLine& line, double offset, const std::vector<double>& x, const std::vector<double>& y,
                      double dx, const std::string& option) {
  if (x.empty()) return;
  const auto [x_min, x_max] = std::minmax_element(x.begin(), x.end());
  const auto [y_min, y_max] = std::minmax_element(y.begin(), y.end());
  const double size = std::max({*x_max - *x_min, *y_max - *y_min, dx});
  // How far a point lies beyond the particles' extent, in plate sizes.
  const auto beyond = [&](double px, double py) {
    return std::max({*x_min - px, px - *x_max, *y_min - py, py - *y_max, 0.0}) / size;
  };
  const double far = std::max(beyond(line.x0, line.y0), beyond(line.x1, line.y1));
  char text[480];
  if (far > max_plate_sizes_away) {
    std::snprintf(text, sizeof text,
                  "%s: the line from (%g, %g) mm to (%g, %g) mm reaches %.3g times the plate's size (%g mm) beyond "
                  "its particles (x %g to %g mm, y %g to %g mm), more than the %g a line may: give a line across "
                  "the plate, lengths with their unit (e.g. %s 10mm,12.5mm,40mm,12.5mm)",
                  option.c_str(), line.x0 * 1e3, line.y0 * 1e3, line.x1 * 1e3, line.y1 * 1e3, far, size * 1e3,
                  *x_min * 1e3, *x_max * 1e3, *y_min * 1e3, *y_max * 1e3, max_plate_sizes_away, option.c_str());
    throw Error(text);
  }
  if (offset > max_plate_sizes_away * size) {
    std::snprintf(text, sizeof text,
                  "--line-offset %g mm is %.3g times the plate's size (%g mm), more than the %g it may be: the "
                  "one-sided fits %g to %g mm from the line would find no particle; give it with its unit (e.g. "
                  "--line-offset 1mm)",
                  offset * 1e3, offset / size, size * 1e3, max_plate_sizes_away, offset * 1e3, 2 * offset * 1e3);
    throw Error(text);
  }
}

LineProfile line_profile(const ParticleFields& fields, const SampleLine& line, double spacing, double offset,
                         double horizon) {
  LineProfile p;
  p.offset = offset > 0 ? offset : horizon;
  // Before any sample: a line 1e300 m long has more samples than an int
  // counts (before 7 December 2026 the count was a double cast to int, and
  // the line was said to meet no particle).
  check_line_reach(line, offset, fields.x, fields.y, spacing, "--line");
  p.samples = sample_line(fields, line, spacing, p.offset);
  const std::string off_plate = check_line_on_plate(p.samples, line, fields.x, fields.y, spacing, "--line");
  if (!off_plate.empty()) p.warnings.push_back(off_plate);
  // No sample with material in both bands (an offset wider than the plate
  // around the line, or a line along an edge): the jump columns are empty
  // throughout, which before 7 December 2026 was written without a word.
  if (std::none_of(p.samples.begin(), p.samples.end(), [](const LineSample& s) { return s.has_jump; })) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "--line: no sample of the line has particles on both sides between %g and %g mm from it (%s %g "
                  "mm): opening_m and sliding_m in line_profile.csv are empty; the one-sided fits need material "
                  "there (a smaller --line-offset, or a line farther from the plate's edges)",
                  p.offset * 1e3, 2 * p.offset * 1e3, offset > 0 ? "--line-offset" : "the offset, one horizon,",
                  p.offset * 1e3);
    p.warnings.push_back(text);
  }
  return p;
}

void write_line_profile(const std::string& path, const std::vector<LineSample>& samples) {
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v == 0 ? 0.0 : v);
    return std::string(buf);
  };
  write_atomically(path, [&](std::ofstream& out) {
    out << "s_m,x_m,y_m,u_x_m,u_y_m,damage,opening_m,sliding_m\n";
    for (const auto& s : samples) {
      out << num(s.s) << ',' << num(s.x) << ',' << num(s.y) << ',';
      out << (s.has_u ? num(s.ux) + ',' + num(s.uy) : std::string(",")) << ','
          << (s.on_plate ? num(s.damage) : std::string()) << ',';
      out << (s.has_jump ? num(s.opening) + ',' + num(s.sliding) : std::string(",")) << '\n';
    }
  });
}

}  // namespace pd::post
