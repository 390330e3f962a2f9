#include "plate_geometry.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "error.hpp"
#include "gmsh_session.hpp"
#include "units.hpp"

namespace pd {

double PlateGeometry::exact_area() const {
  double area = (xmax - xmin) * (ymax - ymin);
  for (const auto& h : holes) area -= h.area;
  return area;
}

namespace {

// A curve of the surface boundary, oriented along its loop.
struct LoopCurve {
  int tag = 0;
  bool forward = true;  // loop runs from parameter min to max
  double tmin = 0, tmax = 0;
  Vec2 start, end;  // in loop direction (file units)
  std::string type;
};

std::string at_mm(Vec2 p, double unit) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g) mm", p.x * unit * 1e3, p.y * unit * 1e3);
  return buf;
}

std::vector<Vec2> evaluate(int tag, const std::vector<double>& params) {
  std::vector<double> xyz;
  gmsh::model::getValue(1, tag, params, xyz);
  std::vector<Vec2> out(params.size());
  for (std::size_t i = 0; i < params.size(); ++i) out[i] = {xyz[3 * i], xyz[3 * i + 1]};
  return out;
}

// Parameters splitting curve `c` into `pieces` pieces of equal arc length
// (in loop direction), from a dense polyline of the curve.
std::vector<double> equal_length_parameters(const LoopCurve& c, int pieces) {
  constexpr int dense = 512;
  std::vector<double> t(dense + 1);
  for (int k = 0; k <= dense; ++k) t[k] = c.tmin + (c.tmax - c.tmin) * k / dense;
  const auto p = evaluate(c.tag, t);
  std::vector<double> s(dense + 1, 0.0);
  for (int k = 1; k <= dense; ++k) s[k] = s[k - 1] + std::hypot(p[k].x - p[k - 1].x, p[k].y - p[k - 1].y);
  std::vector<double> out(pieces + 1);
  for (int k = 0; k <= pieces; ++k) {
    const double target = s[dense] * k / pieces;
    const auto it = std::lower_bound(s.begin(), s.end(), target);
    const auto hi = std::clamp<std::ptrdiff_t>(it - s.begin(), 1, dense);
    const double span = s[hi] - s[hi - 1];
    const double w = span > 0 ? (target - s[hi - 1]) / span : 0.0;
    out[k] = t[hi - 1] + w * (t[hi] - t[hi - 1]);
  }
  out.front() = c.tmin;
  out.back() = c.tmax;
  if (!c.forward) std::reverse(out.begin(), out.end());
  return out;
}

double curve_length(const LoopCurve& c) {
  constexpr int dense = 512;
  std::vector<double> params(dense + 1);
  for (int k = 0; k <= dense; ++k) params[k] = c.tmin + (c.tmax - c.tmin) * k / dense;
  const auto p = evaluate(c.tag, params);
  double s = 0;
  for (int k = 1; k <= dense; ++k) s += std::hypot(p[k].x - p[k - 1].x, p[k].y - p[k - 1].y);
  return s;
}

// Signed area between the chord p(t0) -> p(t1) and the curve, by Green's
// formula 1/2 ∫ (X dY - Y dX) with X, Y relative to p(t0) (the chord then
// contributes nothing). 8-point Gauss-Legendre: exact to round-off for the
// short, smooth arcs between two samples.
double bulge_area(int tag, double t0, double t1) {
  static const double nodes[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                  -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                  0.7966664774136267,  0.9602898564975363};
  static const double weights[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                    0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                    0.2223810344533745, 0.1012285362903763};
  std::vector<double> params(9);
  params[0] = t0;
  for (int g = 0; g < 8; ++g) params[g + 1] = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * nodes[g];
  std::vector<double> xyz, dxyz;
  gmsh::model::getValue(1, tag, params, xyz);
  gmsh::model::getDerivative(1, tag, std::vector<double>(params.begin() + 1, params.end()), dxyz);
  double sum = 0;
  for (int g = 0; g < 8; ++g) {
    const double X = xyz[3 * (g + 1)] - xyz[0], Y = xyz[3 * (g + 1) + 1] - xyz[1];
    sum += weights[g] * (X * dxyz[3 * g + 1] - Y * dxyz[3 * g]);
  }
  return 0.5 * sum * 0.5 * (t1 - t0);
}

// Chains the boundary curves of the surface into closed loops.
std::vector<std::vector<LoopCurve>> chain_loops(const std::vector<int>& tags, double tolerance,
                                                const std::string& file, double unit) {
  std::vector<LoopCurve> curves;
  for (int tag : tags) {
    LoopCurve c;
    c.tag = tag;
    std::vector<double> mn, mx;
    gmsh::model::getParametrizationBounds(1, tag, mn, mx);
    c.tmin = mn.at(0);
    c.tmax = mx.at(0);
    const auto ends = evaluate(tag, {c.tmin, c.tmax});
    c.start = ends[0];
    c.end = ends[1];
    gmsh::model::getType(1, tag, c.type);
    curves.push_back(c);
  }
  const auto close = [&](Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y) <= tolerance; };
  std::vector<bool> used(curves.size(), false);
  std::vector<std::vector<LoopCurve>> loops;
  for (std::size_t first = 0; first < curves.size(); ++first) {
    if (used[first]) continue;
    used[first] = true;
    std::vector<LoopCurve> loop{curves[first]};
    while (!close(loop.back().end, loop.front().start)) {
      bool extended = false;
      for (std::size_t k = 0; k < curves.size() && !extended; ++k) {
        if (used[k]) continue;
        LoopCurve c = curves[k];
        if (close(c.end, loop.back().end)) {
          std::swap(c.start, c.end);
          c.forward = false;
        }
        if (close(c.start, loop.back().end)) {
          used[k] = true;
          loop.push_back(c);
          extended = true;
        }
      }
      if (!extended)
        throw file_error(file, "open boundary: curve " + std::to_string(loop.back().tag) + " ends at " +
                                   at_mm(loop.back().end, unit) + " where no other curve starts");
    }
    loops.push_back(loop);
  }
  return loops;
}

double loop_signed_area(const std::vector<Vec2>& pts) {
  double twice = 0;
  for (std::size_t i = 0, j = pts.size() - 1; i < pts.size(); j = i++)
    twice += pts[j].x * pts[i].y - pts[i].x * pts[j].y;
  return 0.5 * twice;
}

// Samples a loop: `pieces_per_length` pieces per file unit, at least one per curve;
// with `even`, the total count is made even.
struct LoopSamples {
  std::vector<Vec2> points;
  std::vector<int> curve;  // curve of segment k
  std::vector<double> t0, t1;
};
LoopSamples sample_loop(const std::vector<LoopCurve>& loop, double spacing, bool even) {
  std::vector<int> pieces(loop.size());
  std::vector<double> lengths(loop.size());
  int total = 0;
  for (std::size_t c = 0; c < loop.size(); ++c) {
    lengths[c] = curve_length(loop[c]);
    pieces[c] = std::max(1, static_cast<int>(std::lround(lengths[c] / spacing)));
    total += pieces[c];
  }
  if (total < 8) {  // keep even a tiny hole a recognisable polygon
    const auto longest = std::max_element(lengths.begin(), lengths.end()) - lengths.begin();
    pieces[longest] += 8 - total;
    total = 8;
  }
  if (even && total % 2 == 1) ++pieces[std::max_element(lengths.begin(), lengths.end()) - lengths.begin()];
  LoopSamples s;
  for (std::size_t c = 0; c < loop.size(); ++c) {
    const auto t = equal_length_parameters(loop[c], pieces[c]);
    const auto p = evaluate(loop[c].tag, t);
    for (int k = 0; k < pieces[c]; ++k) {
      s.points.push_back(p[k]);
      s.curve.push_back(loop[c].tag);
      s.t0.push_back(t[k]);
      s.t1.push_back(t[k + 1]);
    }
  }
  return s;
}

std::vector<Vec2> scaled(const std::vector<Vec2>& pts, double unit) {
  std::vector<Vec2> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) out[i] = {pts[i].x * unit, pts[i].y * unit};
  return out;
}

// Any two non-adjacent segments of the closed polylines that meet?
void check_no_intersections(const std::vector<std::vector<Vec2>>& loops, const std::string& file, double unit) {
  struct Seg {
    Vec2 a, b;
    std::size_t loop, index, count;
  };
  std::vector<Seg> segs;
  for (std::size_t l = 0; l < loops.size(); ++l)
    for (std::size_t k = 0; k < loops[l].size(); ++k)
      segs.push_back({loops[l][k], loops[l][(k + 1) % loops[l].size()], l, k, loops[l].size()});
  // Sort by x so that only overlapping x-ranges are compared.
  std::sort(segs.begin(), segs.end(),
            [](const Seg& s, const Seg& t) { return std::min(s.a.x, s.b.x) < std::min(t.a.x, t.b.x); });
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const double right = std::max(segs[i].a.x, segs[i].b.x);
    for (std::size_t j = i + 1; j < segs.size() && std::min(segs[j].a.x, segs[j].b.x) <= right; ++j) {
      const auto& s = segs[i];
      const auto& t = segs[j];
      if (s.loop == t.loop) {
        const std::size_t d = (s.index > t.index) ? s.index - t.index : t.index - s.index;
        if (d == 1 || d == s.count - 1) continue;  // neighbours share an end point
      }
      if (segments_intersect(s.a, s.b, t.a, t.b)) {
        if (s.loop == t.loop)
          throw file_error(file, "a boundary curve intersects itself near " + at_mm(s.a, unit));
        throw file_error(file, "two boundary loops touch or cross near " + at_mm(s.a, unit) +
                                   " (holes must not touch each other or the plate edge)");
      }
    }
  }
}

}  // namespace

PlateGeometry load_plate_geometry(GmshSession& session, const std::string& file, double unit, double spacing) {
  namespace fs = std::filesystem;
  if (!fs::exists(file)) throw file_error(file, "geometry file not found");
  if (!std::ifstream(file)) throw file_error(file, "cannot read geometry file");
  gmsh::model::add("plate");
  gmsh::open(file);
  session.throw_on_logged_errors(file, "reading the geometry");

  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  if (surfaces.size() != 1)
    throw file_error(file, "expected exactly one plane surface, found " + std::to_string(surfaces.size()) +
                               (surfaces.empty() ? " (is there a 'Plane Surface' or an OCC surface?)" : ""));
  gmsh::vectorpair boundary;
  gmsh::model::getBoundary({surfaces[0]}, boundary, false, false, false);
  std::vector<int> tags;
  for (const auto& [dim, tag] : boundary) tags.push_back(std::abs(tag));
  if (tags.empty()) throw file_error(file, "the surface has no boundary curves");

  // Tolerances relative to the model size (file units).
  double bx0, by0, bz0, bx1, by1, bz1;
  gmsh::model::getBoundingBox(surfaces[0].first, surfaces[0].second, bx0, by0, bz0, bx1, by1, bz1);
  const double size = std::hypot(bx1 - bx0, by1 - by0);
  const double tolerance = 1e-7 * size + 1e-9;
  const double spacing_units = spacing / unit;

  auto loops = chain_loops(tags, tolerance, file, unit);

  // Dense polylines of every loop for checks and areas.
  std::vector<LoopSamples> fine(loops.size());
  std::vector<double> area(loops.size());
  for (std::size_t l = 0; l < loops.size(); ++l) {
    fine[l] = sample_loop(loops[l], spacing_units / 16, false);
    area[l] = loop_signed_area(fine[l].points);
  }
  const auto outer = static_cast<std::size_t>(
      std::max_element(area.begin(), area.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); }) -
      area.begin());

  PlateGeometry g;
  g.file = file;
  g.unit = unit;
  {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto& p : fine[outer].points) {
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
    for (const auto& c : loops[outer]) {
      if (c.type != "Line")
        throw file_error(file, "the outer boundary must be an axis-aligned rectangle of straight lines; curve " +
                                   std::to_string(c.tag) + " is of type " + c.type);
    }
    for (const auto& p : fine[outer].points) {
      const bool on_edge = std::fabs(p.x - x0) <= tolerance || std::fabs(p.x - x1) <= tolerance ||
                           std::fabs(p.y - y0) <= tolerance || std::fabs(p.y - y1) <= tolerance;
      if (!on_edge)
        throw file_error(file, "the outer boundary is not an axis-aligned rectangle (point " + at_mm(p, unit) +
                                   " is not on its bounding box)");
    }
    g.xmin = x0 * unit, g.xmax = x1 * unit, g.ymin = y0 * unit, g.ymax = y1 * unit;
  }

  // Holes: sample at the grid spacing, measure bulges.
  std::vector<std::vector<Vec2>> all_fine{scaled(fine[outer].points, unit)};
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (l == outer) continue;
    HoleLoop h;
    const auto s = sample_loop(loops[l], spacing_units, true);
    h.points = scaled(s.points, unit);
    h.bulge.resize(s.points.size());
    h.arc.resize(s.points.size());
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      h.bulge[k] = bulge_area(s.curve[k], s.t0[k], s.t1[k]) * unit * unit;
      std::vector<double> params;
      const std::size_t m = HoleLoop::arc_points_per_segment;
      for (std::size_t a = 1; a <= m; ++a) params.push_back(s.t0[k] + (s.t1[k] - s.t0[k]) * a / (m + 1));
      h.arc[k] = scaled(evaluate(s.curve[k], params), unit);
    }
    h.fine = scaled(fine[l].points, unit);
    h.xmin = h.ymin = 1e300;
    h.xmax = h.ymax = -1e300;
    for (const auto& p : h.fine) {
      h.xmin = std::min(h.xmin, p.x), h.xmax = std::max(h.xmax, p.x);
      h.ymin = std::min(h.ymin, p.y), h.ymax = std::max(h.ymax, p.y);
    }
    double bulges = 0;
    for (double b : h.bulge) bulges += b;
    // Area enclosed by the true curve: polygon of the samples plus the bulges
    // (both signed with the loop orientation).
    h.area = std::fabs(loop_signed_area(h.points) + bulges);
    std::set<std::string> types;
    for (const auto& c : loops[l]) types.insert(c.type);
    h.curve_types.assign(types.begin(), types.end());
    const double margin = tolerance * unit;
    if (h.xmin <= g.xmin + margin || h.xmax >= g.xmax - margin || h.ymin <= g.ymin + margin ||
        h.ymax >= g.ymax - margin)
      throw file_error(file, "a hole touches or crosses the plate edge (hole bounding box " +
                                 format_mm(h.xmin) + " .. " + format_mm(h.xmax) + " x " + format_mm(h.ymin) +
                                 " .. " + format_mm(h.ymax) + ")");
    all_fine.push_back(h.fine);
    g.holes.push_back(std::move(h));
  }
  check_no_intersections(all_fine, file, 1.0);
  // Nested holes: a hole inside another one.
  for (std::size_t a = 0; a < g.holes.size(); ++a)
    for (std::size_t b = 0; b < g.holes.size(); ++b) {
      if (a == b) continue;
      if (point_in_polygon(g.holes[a].fine[0], g.holes[b].fine))
        throw file_error(file, "a hole lies inside another hole near " + at_mm(g.holes[a].fine[0], 1.0));
    }

  // Stable names: order by centre x, then y.
  std::sort(g.holes.begin(), g.holes.end(), [](const HoleLoop& a, const HoleLoop& b) {
    const double ax = a.xmin + a.xmax, bx = b.xmin + b.xmax;
    if (ax != bx) return ax < bx;
    return a.ymin + a.ymax < b.ymin + b.ymax;
  });
  for (std::size_t k = 0; k < g.holes.size(); ++k) g.holes[k].name = "hole_" + std::to_string(k + 1);

  // User-named curve groups.
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 1);
  for (const auto& [dim, group] : groups) {
    NamedCurves named;
    gmsh::model::getPhysicalName(dim, group, named.name);
    if (named.name.empty()) named.name = "physical_" + std::to_string(group);
    std::vector<int> curve_tags;
    gmsh::model::getEntitiesForPhysicalGroup(dim, group, curve_tags);
    for (int tag : curve_tags) {
      LoopCurve c;
      c.tag = tag;
      std::vector<double> mn, mx;
      gmsh::model::getParametrizationBounds(1, tag, mn, mx);
      c.tmin = mn.at(0), c.tmax = mx.at(0);
      const auto s = sample_loop({c}, spacing_units / 4, false);
      auto pts = scaled(s.points, unit);
      pts.push_back(scaled(evaluate(tag, {c.tmax}), unit)[0]);
      for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
        named.a.push_back(pts[k]);
        named.b.push_back(pts[k + 1]);
      }
    }
    g.physical_curves.push_back(std::move(named));
  }
  return g;
}

}  // namespace pd
