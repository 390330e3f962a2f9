#include "curve_sampling.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace pd {

std::vector<Vec2> evaluate_curve(int tag, const std::vector<double>& params) {
  std::vector<double> xyz;
  gmsh::model::getValue(1, tag, params, xyz);
  std::vector<Vec2> out(params.size());
  for (std::size_t i = 0; i < params.size(); ++i) out[i] = {xyz[3 * i], xyz[3 * i + 1]};
  return out;
}

double CurvePolyline::length() const {
  double s = 0;
  for (std::size_t k = 1; k < points.size(); ++k)
    s += std::hypot(points[k].x - points[k - 1].x, points[k].y - points[k - 1].y);
  return s;
}

CurvePolyline curve_polyline(int tag, double t0, double t1, bool straight, double tolerance) {
  CurvePolyline p;
  // Start from 64 equal parameter steps (a curve's parametrisation is smooth),
  // then halve every chord whose middle is too far from the curve, one level
  // at a time so that each level is one gmsh call.
  const int start = straight ? 1 : 64;
  for (int k = 0; k <= start; ++k) p.params.push_back(t0 + (t1 - t0) * k / start);
  p.points = evaluate_curve(tag, p.params);
  if (straight) return p;
  for (int level = 0; level < 40; ++level) {
    std::vector<double> middles;
    for (std::size_t k = 0; k + 1 < p.params.size(); ++k) middles.push_back(0.5 * (p.params[k] + p.params[k + 1]));
    const auto mid_points = evaluate_curve(tag, middles);
    std::vector<double> params{p.params.front()};
    std::vector<Vec2> points{p.points.front()};
    bool refined = false;
    for (std::size_t k = 0; k + 1 < p.params.size(); ++k) {
      if (point_segment_distance(mid_points[k], p.points[k], p.points[k + 1]) > tolerance) {
        params.push_back(middles[k]);
        points.push_back(mid_points[k]);
        refined = true;
      }
      params.push_back(p.params[k + 1]);
      points.push_back(p.points[k + 1]);
    }
    p.params.swap(params);
    p.points.swap(points);
    if (!refined) break;
  }
  return p;
}

std::vector<double> equal_length_parameters(const CurvePolyline& polyline, int pieces) {
  const auto& t = polyline.params;
  const auto& p = polyline.points;
  std::vector<double> s(p.size(), 0.0);
  for (std::size_t k = 1; k < p.size(); ++k) s[k] = s[k - 1] + std::hypot(p[k].x - p[k - 1].x, p[k].y - p[k - 1].y);
  std::vector<double> out(static_cast<std::size_t>(pieces) + 1);
  for (int k = 0; k <= pieces; ++k) {
    const double target = s.back() * k / pieces;
    const auto it = std::lower_bound(s.begin(), s.end(), target);
    const auto hi = std::clamp<std::ptrdiff_t>(it - s.begin(), 1, static_cast<std::ptrdiff_t>(s.size()) - 1);
    const double span = s[hi] - s[hi - 1];
    const double w = span > 0 ? (target - s[hi - 1]) / span : 0.0;
    out[k] = t[hi - 1] + w * (t[hi] - t[hi - 1]);
  }
  out.front() = t.front();
  out.back() = t.back();
  return out;
}

namespace {

// 1/2 the 8-point Gauss-Legendre sum of X Y' - Y X' over [t0, t1], with X, Y
// relative to `origin`.
double gauss_bulge(int tag, double t0, double t1, double origin_x, double origin_y) {
  static const double nodes[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                  -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                  0.7966664774136267,  0.9602898564975363};
  static const double weights[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                    0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                    0.2223810344533745, 0.1012285362903763};
  std::vector<double> params(8);
  for (int g = 0; g < 8; ++g) params[g] = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * nodes[g];
  std::vector<double> xyz, dxyz;
  gmsh::model::getValue(1, tag, params, xyz);
  gmsh::model::getDerivative(1, tag, params, dxyz);
  double sum = 0;
  for (int g = 0; g < 8; ++g) {
    const double X = xyz[3 * g] - origin_x, Y = xyz[3 * g + 1] - origin_y;
    sum += weights[g] * (X * dxyz[3 * g + 1] - Y * dxyz[3 * g]);
  }
  return 0.5 * sum * 0.5 * (t1 - t0);
}

// Polygon areas of n = 8, 16, 32, ... equal parameter steps between p(t0)
// and p(t1), extrapolated (Richardson) until two estimates agree to
// `tolerance`. Only the curve's points are used: gmsh's derivative of a
// spline is a finite difference (noise about 1e-8 of its size), which no
// Gauss rule over it can beat (docs/mesher.md, "Curved boundaries: exact
// volumes").
double polygon_bulge(int tag, double t0, double t1, Vec2 origin, Vec2 end, double tolerance) {
  // Points at parameters j / n of the interval relative to p(t0), in order;
  // each level adds the middles.
  std::vector<Vec2> ordered{{0, 0}, {end.x - origin.x, end.y - origin.y}};
  double previous_extrapolated = 0;
  double previous_area = 0;  // the chord alone encloses nothing
  for (int level = 1; level <= 10; ++level) {
    const std::size_t n = ordered.size() - 1;
    std::vector<double> middles(n);
    for (std::size_t j = 0; j < n; ++j) middles[j] = t0 + (t1 - t0) * (2.0 * j + 1) / (2.0 * n);
    const auto mid = evaluate_curve(tag, middles);
    std::vector<Vec2> finer(2 * n + 1);
    for (std::size_t j = 0; j < n; ++j) {
      finer[2 * j] = ordered[j];
      finer[2 * j + 1] = {mid[j].x - origin.x, mid[j].y - origin.y};
    }
    finer[2 * n] = ordered[n];
    ordered.swap(finer);
    // Shoelace sum of the fan from p(t0): the closing chord adds nothing.
    double twice_area = 0;
    for (std::size_t j = 1; j + 1 < ordered.size(); ++j)
      twice_area += ordered[j].x * ordered[j + 1].y - ordered[j + 1].x * ordered[j].y;
    const double area = 0.5 * twice_area;
    // The polygon misses the curve by c h^2 + O(h^4) (a spline's knots leave
    // the h^4 term rough, not the h^2 one): one extrapolation step.
    const double extrapolated = (4 * area - previous_area) / 3;
    if (level >= 3 && std::fabs(extrapolated - previous_extrapolated) <= tolerance) return extrapolated;
    previous_area = area;
    previous_extrapolated = extrapolated;
  }
  return previous_extrapolated;
}

}  // namespace

double bulge_area(int tag, double t0, double t1) {
  std::vector<double> ends;
  gmsh::model::getValue(1, tag, {t0, t1}, ends);
  // Conic arcs (circles, ellipses) are analytic in their parameter, and
  // gmsh's derivative of them too: one Gauss rule integrates the short arc
  // between two samples to round-off. X, Y relative to p(t0): the chord then
  // contributes nothing to the integral.
  std::string type;
  gmsh::model::getType(1, tag, type);
  if (type == "Circle" || type == "Ellipse") return gauss_bulge(tag, t0, t1, ends[0], ends[1]);
  // Other curves (splines: piecewise polynomials whose knots may fall inside
  // the chord) from their points alone. The round-off: the products are of
  // the chord's length, their differences of coordinates as large as the
  // curve's distance from the origin of the file.
  const double chord = std::hypot(ends[3] - ends[0], ends[4] - ends[1]);
  const double reach = std::max({std::fabs(ends[0]), std::fabs(ends[1]), std::fabs(ends[3]), std::fabs(ends[4]), chord});
  return polygon_bulge(tag, t0, t1, {ends[0], ends[1]}, {ends[3], ends[4]}, 1e-13 * chord * reach);
}

}  // namespace pd
