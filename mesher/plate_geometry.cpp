#include "plate_geometry.hpp"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include "boundary_contacts.hpp"
#include "curve_sampling.hpp"
#include "error.hpp"
#include "geo_file_check.hpp"
#include "gmsh_session.hpp"
#include "graded_spacing.hpp"
#include "refinement.hpp"
#include "units.hpp"

namespace pd {

double PlateGeometry::exact_area() const {
  double area = outer.area;
  for (const auto& h : holes) area -= h.area;
  return area;
}

std::vector<const BoundaryLoop*> PlateGeometry::loops() const {
  std::vector<const BoundaryLoop*> all{&outer};
  for (const auto& h : holes) all.push_back(&h);
  return all;
}

int bounding_box_side(const BoundaryCurve& c, const PlateGeometry& g) {
  if (!c.straight()) return -1;
  const double tol = 1e-9 * std::max(g.xmax - g.xmin, g.ymax - g.ymin);
  const auto on_side = [&](Vec2 q, int side) {
    switch (side) {
      case 0: return std::fabs(q.x - g.xmin) <= tol;
      case 1: return std::fabs(q.x - g.xmax) <= tol;
      case 2: return std::fabs(q.y - g.ymin) <= tol;
      default: return std::fabs(q.y - g.ymax) <= tol;
    }
  };
  for (int side = 0; side < 4; ++side)
    if (on_side(c.start, side) && on_side(c.end, side)) return side;
  return -1;
}

std::vector<Vec2> BoundaryLoop::polyline() const {
  std::vector<Vec2> out;
  for (const auto& c : curves) out.insert(out.end(), c.polyline.begin(), c.polyline.end() - 1);
  return out;
}

namespace {

// A place in a message, in mm rounded to 0.1 um: a point found on a
// polyline carries the polyline's round-off (9.4e-07 mm for 0).
std::string at_mm(Vec2 p, double unit) {
  const auto rounded = [](double metres) { return std::round(metres * 1e7) / 1e4 + 0.0; };
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.10g, %.10g) mm", rounded(p.x * unit), rounded(p.y * unit));
  return buf;
}

// The curves of `loop` that pass through `where` (a crossing found on the
// loop's polyline, so within round-off of a curve's own polyline).
std::vector<const BoundaryCurve*> curves_through(const BoundaryLoop& loop, Vec2 where, double tolerance) {
  std::vector<const BoundaryCurve*> found;
  for (const auto& curve : loop.curves)
    for (std::size_t i = 0; i + 1 < curve.polyline.size(); ++i)
      if (point_segment_distance(where, curve.polyline[i], curve.polyline[i + 1]) <= tolerance) {
        found.push_back(&curve);
        break;
      }
  return found;
}

// " (curve 10)", " (curves 10 and 20)" (by tag), or nothing.
std::string curve_names(std::vector<const BoundaryCurve*> curves) {
  if (curves.empty()) return "";
  std::sort(curves.begin(), curves.end(), [](const BoundaryCurve* a, const BoundaryCurve* b) { return a->tag < b->tag; });
  std::string text = curves.size() == 1 ? " (curve " : " (curves ";
  for (std::size_t k = 0; k < curves.size(); ++k)
    text += (k == 0 ? "" : k + 1 == curves.size() ? " and " : ", ") + std::to_string(curves[k]->tag);
  return text + ")";
}

double signed_area(const std::vector<Vec2>& pts) {
  double twice = 0;
  for (std::size_t i = 0, j = pts.size() - 1; i < pts.size(); j = i++)
    twice += pts[j].x * pts[i].y - pts[i].x * pts[j].y;
  return 0.5 * twice;
}

// A curve end as seen from the vertex where it lies: which curve, which end,
// and the direction in which the curve leaves the vertex.
struct CurveEnd {
  std::size_t curve;
  bool at_start;
  double angle;
};

// Chains the boundary curves into closed loops. Curve ends closer than
// `tolerance` (file units) share a vertex. Where more than two curve ends
// meet (a hole touching the outer boundary), a loop turns to the angularly
// next curve, so that loops touch there without crossing.
void chain_loops(const std::vector<int>& tags, double tolerance, const std::string& file, double unit,
                 PlateOutline& outline) {
  struct RawCurve {
    int tag;
    std::string type;
    double t0, t1;
    Vec2 a, b;
    double angle_a, angle_b;  // leaving directions at a and at b
    std::size_t va = 0, vb = 0;
  };
  std::vector<RawCurve> curves;
  for (int tag : tags) {
    RawCurve c;
    c.tag = tag;
    std::vector<double> mn, mx;
    gmsh::model::getParametrizationBounds(1, tag, mn, mx);
    c.t0 = mn.at(0), c.t1 = mx.at(0);
    gmsh::model::getType(1, tag, c.type);
    // Directions towards points a little along the curve: unlike tangents
    // they tell a line from a circle that touches it.
    const double step = 1e-3 * (c.t1 - c.t0);
    const auto p = evaluate_curve(tag, {c.t0, c.t0 + step, c.t1 - step, c.t1, 0.5 * (c.t0 + c.t1)});
    c.a = p[0], c.b = p[3];
    c.angle_a = std::atan2(p[1].y - p[0].y, p[1].x - p[0].x);
    c.angle_b = std::atan2(p[2].y - p[3].y, p[2].x - p[3].x);
    // A curve between two points at the same place (a point defined twice)
    // has no direction: the loops would be chained through it at random.
    // (A closed curve, a whole circle, starts and ends at one point too,
    // but its middle lies elsewhere.)
    const auto near = [&](Vec2 u, Vec2 v) { return std::hypot(u.x - v.x, u.y - v.y) <= tolerance; };
    if (near(c.a, c.b) && (c.type == "Line" || near(c.a, p[4])))
      throw file_error(file, "curve " + std::to_string(tag) + " has zero length: it starts and ends at " +
                                 at_mm(c.a, unit) +
                                 " (two of the file's points lie there); leave it out of its curve loop");
    // A closed curve through points: gmsh joins its ends smoothly when it
    // ends on its first point's tag; ended on another point at that place it
    // draws a corner there, which changes the hole's outline and area without
    // a word. Said, with the angle (a leaving and an arriving direction that
    // are not opposite).
    const bool through_points = c.type == "Nurb" || c.type == "BSpline" || c.type == "Bezier";
    if (through_points && near(c.a, c.b)) {
      const double corner_degrees = std::fabs(std::remainder(c.angle_a - c.angle_b - M_PI, 2 * M_PI)) * 180 / M_PI;
      if (corner_degrees > 1) {
        std::vector<int> upward, ends;  // the curve's end points, first and last
        gmsh::model::getAdjacencies(1, tag, upward, ends);
        char text[400];
        const std::string corner = "a corner of " + shortest_text(std::round(corner_degrees * 10) / 10) + " degrees";
        if (ends.size() == 2 && ends[0] != ends[1])
          std::snprintf(text, sizeof text,
                        "curve %d ends on point %d, at the place of its first point %d: gmsh draws %s there; end "
                        "it on point %d for a smooth outline",
                        tag, ends[1], ends[0], corner.c_str(), ends[0]);
        else
          std::snprintf(text, sizeof text, "curve %d closes at %s with %s", tag, at_mm(c.a, unit).c_str(),
                        corner.c_str());
        outline.warnings.push_back(text);
      }
    }
    curves.push_back(c);
  }
  // Vertices: curve ends within the tolerance, merged (sorted by x).
  std::vector<std::pair<Vec2, std::size_t>> ends;  // point, 2 * curve + (0: start, 1: end)
  for (std::size_t c = 0; c < curves.size(); ++c) ends.push_back({curves[c].a, 2 * c}), ends.push_back({curves[c].b, 2 * c + 1});
  std::sort(ends.begin(), ends.end(), [](const auto& p, const auto& q) { return p.first.x < q.first.x; });
  std::vector<std::size_t> vertex_of(ends.size() * 2, SIZE_MAX);
  for (std::size_t e = 0; e < ends.size(); ++e) {
    std::size_t vertex = SIZE_MAX;
    for (std::size_t f = e; f-- > 0 && ends[e].first.x - ends[f].first.x <= tolerance;)
      if (std::hypot(ends[e].first.x - ends[f].first.x, ends[e].first.y - ends[f].first.y) <= tolerance) {
        vertex = vertex_of[ends[f].second];
        break;
      }
    if (vertex == SIZE_MAX) {
      vertex = outline.vertices.size();
      outline.vertices.push_back(ends[e].first);
    }
    vertex_of[ends[e].second] = vertex;
  }
  std::vector<std::vector<CurveEnd>> at_vertex(outline.vertices.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    curves[c].va = vertex_of[2 * c], curves[c].vb = vertex_of[2 * c + 1];
    at_vertex[curves[c].va].push_back({c, true, curves[c].angle_a});
    at_vertex[curves[c].vb].push_back({c, false, curves[c].angle_b});
  }
  // A vertex with an odd number of curve ends is a free end: name the first two.
  std::string free_ends;
  int free_count = 0;
  for (std::size_t v = 0; v < at_vertex.size(); ++v)
    if (at_vertex[v].size() % 2 == 1 && free_count++ < 2) {
      const auto& end = at_vertex[v].front();
      free_ends += std::string(free_ends.empty() ? "" : " and ") + "curve " + std::to_string(curves[end.curve].tag) +
                   (end.at_start ? " starts" : " ends") + " at " + at_mm(outline.vertices[v], unit);
    }
  if (free_count > 0)
    throw file_error(file, "open boundary: " + free_ends + (free_count == 1 ? "" : ",") +
                               " where no other curve meets " + (free_count == 1 ? "it" : "them") +
                               (free_count > 2 ? " (and " + std::to_string(free_count - 2) + " more free ends)" : ""));

  std::vector<bool> used(curves.size(), false);
  // A loop starts at a vertex of two curve ends where it can. Started where
  // more meet (a disk subtracted tangent to an edge, which OpenCASCADE splits
  // there), it closed on its first return there, before the angular rule
  // below could take it round the disk: the disk was left a hole touching
  // the outer loop, refused as "a hole lies outside the outer boundary" (its
  // first point lies on that boundary) or, probed elsewhere, failing inside
  // gmsh's NB-NUG meshing (before 7 December 2026). Passing through the
  // vertex, the loop takes the disk into the outer boundary, as it does
  // where the chaining starts elsewhere.
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < curves.size(); ++c)
    if (at_vertex[curves[c].va].size() == 2) order.push_back(c);
  for (std::size_t c = 0; c < curves.size(); ++c)
    if (at_vertex[curves[c].va].size() != 2) order.push_back(c);
  for (const std::size_t first : order) {
    if (used[first]) continue;
    std::vector<PlateOutline::Curve> loop;
    std::size_t c = first;
    bool forward = true;
    const std::size_t loop_start = curves[first].va;
    while (true) {
      used[c] = true;
      const auto& rc = curves[c];
      loop.push_back({rc.tag, rc.type, forward ? rc.t0 : rc.t1, forward ? rc.t1 : rc.t0, forward ? rc.va : rc.vb,
                      forward ? rc.vb : rc.va});
      const std::size_t v = loop.back().end_vertex;
      if (v == loop_start) break;
      // Arriving along curve c; its direction back from v:
      const double back = forward ? rc.angle_b : rc.angle_a;
      const CurveEnd* next = nullptr;
      double best = INFINITY;
      for (const auto& e : at_vertex[v]) {
        if (used[e.curve]) continue;
        // The first curve clockwise from the way back.
        double turn = std::fmod(back - e.angle, 2 * M_PI);
        if (turn <= 0) turn += 2 * M_PI;
        if (turn < best) best = turn, next = &e;
      }
      if (!next)
        throw file_error(file, "open boundary: curve " + std::to_string(rc.tag) + " ends at " +
                                   at_mm(outline.vertices[v], unit) + " where no other curve starts");
      c = next->curve;
      forward = next->at_start;
    }
    outline.loops.push_back(std::move(loop));
  }
}

// 64 points per curve, loop-wise, file units: enough for areas to 1e-6 and
// for telling the outer loop and the orientation.
std::vector<Vec2> coarse_polyline(const std::vector<PlateOutline::Curve>& loop) {
  std::vector<Vec2> out;
  for (const auto& c : loop) {
    const int n = c.type == "Line" ? 1 : 64;
    std::vector<double> t;
    for (int k = 0; k < n; ++k) t.push_back(c.t_start + (c.t_end - c.t_start) * k / n);
    const auto p = evaluate_curve(c.tag, t);
    out.insert(out.end(), p.begin(), p.end());
  }
  return out;
}

std::vector<Vec2> scaled(std::vector<Vec2> pts, double unit) {
  for (auto& p : pts) p = {p.x * unit, p.y * unit};
  return pts;
}

// Samples `curve` into `pieces` chords of equal length along its polyline
// (file units), with exact chord areas; the end points are the loop's shared vertices.
CurveSamples make_samples(const PlateOutline::Curve& curve, const CurvePolyline& polyline, int pieces, Vec2 start,
                          Vec2 end, double unit) {
  CurveSamples s;
  const auto t = equal_length_parameters(polyline, pieces);
  s.points = scaled(evaluate_curve(curve.tag, t), unit);
  s.points.front() = start, s.points.back() = end;
  const bool straight = curve.type == "Line";
  for (int k = 0; k < pieces; ++k) {
    s.bulge.push_back(straight ? 0.0 : bulge_area(curve.tag, t[k], t[k + 1]) * unit * unit);
    if (straight) continue;
    std::vector<double> params;
    const std::size_t m = CurveSamples::arc_points_per_chord;
    for (std::size_t a = 1; a <= m; ++a) params.push_back(t[k] + (t[k + 1] - t[k]) * a / (m + 1));
    s.arc.push_back(scaled(evaluate_curve(curve.tag, params), unit));
  }
  return s;
}

// Two loops whose curves touch without a common point (a hole tangent to the
// plate's edge, or to another hole): the polylines, within the boundary
// tolerance of their curves, need not meet there, so find_boundary_contact
// may miss it, and what the grid then makes of the zero-width ligament
// depends on the spacing. A vertex of one loop's polyline closer than
// `touching` to the other's is a touch, unless it lies within a spacing of a
// point the two loops share (where they meet by design). Only segments near
// the other loop's bounding box are looked at.
std::optional<BoundaryContact> touch_without_common_point(const std::vector<BoundaryLoop>& loops, double touching,
                                                         double spacing) {
  std::vector<std::vector<Vec2>> polylines, ends(loops.size());
  for (const auto& loop : loops) polylines.push_back(loop.polyline());
  for (std::size_t l = 0; l < loops.size(); ++l)
    for (const auto& c : loops[l].curves) ends[l].push_back(c.start);
  const auto same = [](Vec2 p, Vec2 q) { return p.x == q.x && p.y == q.y; };
  const auto near_shared = [&](std::size_t a, std::size_t b, Vec2 p) {
    for (const Vec2 e : ends[a])
      if (std::hypot(p.x - e.x, p.y - e.y) <= spacing &&
          std::any_of(ends[b].begin(), ends[b].end(), [&](Vec2 f) { return same(e, f); }))
        return true;
    return false;
  };
  const auto in_box = [&](Vec2 p, const BoundaryLoop& box) {
    return p.x >= box.xmin - touching && p.x <= box.xmax + touching && p.y >= box.ymin - touching &&
           p.y <= box.ymax + touching;
  };
  // The vertices of loop `a` in b's box against the segments of loop `b` near a's box.
  const auto vertices_against = [&](std::size_t a, std::size_t b) -> std::optional<BoundaryContact> {
    std::vector<Vec2> candidates;
    for (const Vec2 p : polylines[a])
      if (in_box(p, loops[b])) candidates.push_back(p);
    const BoundaryLoop& box = loops[a];
    const auto& poly = polylines[b];
    for (std::size_t k = 0; k < poly.size() && !candidates.empty(); ++k) {
      const Vec2 u = poly[k], v = poly[(k + 1) % poly.size()];
      if (std::max(u.x, v.x) < box.xmin - touching || std::min(u.x, v.x) > box.xmax + touching ||
          std::max(u.y, v.y) < box.ymin - touching || std::min(u.y, v.y) > box.ymax + touching)
        continue;
      for (const Vec2 p : candidates)
        if (point_segment_distance(p, u, v) <= touching && !near_shared(a, b, p)) return BoundaryContact{a, b, p};
    }
    return std::nullopt;
  };
  for (std::size_t a = 1; a < loops.size(); ++a)
    for (std::size_t b = 0; b < loops.size(); ++b) {
      if (b == a || (b > 0 && b < a)) continue;  // each pair once
      if (b > 0 && (loops[a].xmax < loops[b].xmin - touching || loops[a].xmin > loops[b].xmax + touching ||
                    loops[a].ymax < loops[b].ymin - touching || loops[a].ymin > loops[b].ymax + touching))
        continue;
      if (auto touch = vertices_against(a, b)) return touch;
      if (auto touch = vertices_against(b, a)) return touch;
    }
  return std::nullopt;
}

// Where the file's curves leave a loop open, for gmsh's "Curve Loop N is
// wrong" (built-in kernel), which names no place: the free ends of all the
// file's curves, as chain_loops names them; "" when every end meets another.
std::string open_curve_ends(const std::string& file, double unit) {
  gmsh::vectorpair entities;
  gmsh::model::getEntities(entities, 1);
  std::vector<int> tags;
  for (const auto& [dim, tag] : entities) tags.push_back(tag);
  if (tags.empty()) return "";
  double bx0, by0, bz0, bx1, by1, bz1;
  gmsh::model::getBoundingBox(-1, -1, bx0, by0, bz0, bx1, by1, bz1);
  PlateOutline scratch;
  try {
    chain_loops(tags, 1e-7 * std::hypot(bx1 - bx0, by1 - by0) + 1e-9, file, unit, scratch);
  } catch (const Error& e) {
    const std::string what = e.what();
    const auto at = what.find("open boundary: ");
    if (at != std::string::npos) return what.substr(at + 15);
  } catch (const std::exception&) {
  }
  return "";
}

// For gmsh's "syntax error" on line N: the statement before it, when it
// does not end with ';' (gmsh then reads line N as its continuation and
// names line N, not the line that lacks the ';'): "\n  line M, 'TEXT', does
// not end with ';' ...", or "" when that is not the cause.
std::string missing_semicolon_hint(const std::string& file, const std::string& message) {
  const auto at = message.find("', line ");
  if (message.find("syntax error") == std::string::npos || at == std::string::npos) return "";
  const int error_line = std::atoi(message.c_str() + at + 8);
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; static_cast<int>(lines.size()) < error_line - 1 && std::getline(in, line);)
    lines.push_back(line);
  for (int k = static_cast<int>(lines.size()) - 1; k >= 0; --k) {
    std::string text = lines[static_cast<std::size_t>(k)];
    if (const auto comment = text.find("//"); comment != std::string::npos) text.erase(comment);
    const auto first = text.find_first_not_of(" \t\r"), last = text.find_last_not_of(" \t\r");
    if (first == std::string::npos) continue;  // blank or a comment
    text = text.substr(first, last - first + 1);
    // Lines that open or close a block end without ';'.
    for (const char* word : {"For", "If", "ElseIf", "Else", "EndFor", "EndIf", "Macro", "Function", "Return"})
      if (text.compare(0, std::string(word).size(), word) == 0 &&
          (text.size() == std::string(word).size() || !std::isalnum(static_cast<unsigned char>(text[std::string(word).size()]))))
        return "";
    // Only a line that could end a statement (not one ending in an operator,
    // a ',' or an opening bracket, which a statement continues after).
    const char end = text.back();
    if (!(std::isalnum(static_cast<unsigned char>(end)) || end == ')' || end == '}' || end == ']' || end == '"'))
      return "";
    return "\n  line " + std::to_string(k + 1) + ", '" + clipped(text) + "', does not end with ';': every "
           "statement ends with one, and gmsh reads the line after as its continuation";
  }
  return "";
}

}  // namespace

PlateOutline read_plate_outline(GmshSession& session, const std::string& file, double unit) {
  namespace fs = std::filesystem;
  if (!fs::exists(file)) throw file_error(file, "geometry file not found");
  if (!std::ifstream(file)) throw file_error(file, "cannot read geometry file");
  // A scene given for its geometry reads as a page of gmsh syntax errors.
  if (fs::path(file).extension() == ".toml")
    throw file_error(file, "a scene (TOML), not a gmsh geometry: pd-mesh meshes the .geo file that the scene's "
                           "particle file comes from (the scene's first lines name it)");
  auto physical_curve_names = check_geometry_file_is_data(file);
  gmsh::model::add("plate");
  {
    const auto deadline = session.deadline(file, "reading the geometry");
    gmsh::open(file);
  }
  session.restore_options();
  try {
    session.throw_on_logged_errors(file, "reading the geometry");
    // A coordinate beyond the range of a double (1e400) is read as inf:
    // name the point, rather than a loop that does not close at a NaN.
    gmsh::vectorpair points;
    gmsh::model::getEntities(points, 0);
    for (const auto& [dim, tag] : points) {
      std::vector<double> xyz;
      gmsh::model::getValue(dim, tag, {}, xyz);
      if (std::all_of(xyz.begin(), xyz.end(), [](double v) { return std::isfinite(v); })) continue;
      std::string text;
      for (double v : xyz) text += (text.empty() ? "" : ", ") + shortest_text(v);
      throw file_error(file, "point " + std::to_string(tag) + " has a coordinate that is not a finite number (" +
                                 text + " in file units): a number beyond about 1.8e308, or an expression that "
                                        "overflows");
    }
  } catch (const Error& e) {
    const std::string what = e.what();
    if (const std::string hint = missing_semicolon_hint(file, what); !hint.empty()) throw Error(what + hint);
    if (what.find("Curve Loop") == std::string::npos || what.find("is wrong") == std::string::npos) throw;
    const std::string ends = open_curve_ends(file, unit);
    throw Error(what + "\n  a curve loop's curves must join, each one's end to the next one's start (a minus sign "
                       "reverses a curve)" +
                (ends.empty() ? std::string() : "; the loop is open: " + ends));
  }

  // A solid (a Box, a plate extruded to its thickness, a 3D CAD part): its
  // faces were counted as pieces of a plate, and the advice was to join
  // them with BooleanUnion (before 7 December 2026).
  gmsh::vectorpair volumes;
  gmsh::model::getEntities(volumes, 3);
  if (!volumes.empty()) {
    std::string tags;
    for (std::size_t k = 0; k < volumes.size() && k < 6; ++k) tags += (k ? ", " : "") + std::to_string(volumes[k].second);
    if (volumes.size() > 6) tags += ", ...";
    throw file_error(file, std::string("the geometry is a solid (volume") + (volumes.size() == 1 ? " " : "s ") + tags +
                               "): pd-mesh meshes a plate as its plane face, in 2D; give the face alone (e.g. "
                               "Rectangle instead of Box, or no Extrude), and the plate's thickness in the scene (material.thickness)");
  }
  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  if (surfaces.empty())
    throw file_error(file, "expected exactly one plane surface, found 0 (is there a 'Plane Surface' or an OCC surface?)");
  if (surfaces.size() > 1) {
    // A BooleanDifference without Delete keeps what it cut from, or what it
    // cut out, as surfaces of their own: joined, as the message below
    // advises for a plate in pieces, they would fill the holes (before 7
    // December 2026 that was the advice).
    const auto statements = geometry_statements(file);
    if (statements.difference_keeping_objects_line > 0 || statements.difference_keeping_tools_line > 0) {
      const bool objects = statements.difference_keeping_objects_line > 0;
      throw Error(file + ":" +
                  std::to_string(objects ? statements.difference_keeping_objects_line
                                         : statements.difference_keeping_tools_line) +
                  ": BooleanDifference without 'Delete;' in its " + (objects ? "first" : "second") +
                  " braces keeps " +
                  (objects ? "the surface it cuts from: the plate is there whole, and again with its holes"
                           : "the surfaces it cuts out: they fill the holes") +
                  " (" + std::to_string(surfaces.size()) +
                  " surfaces); delete both, BooleanDifference{ Surface{plate}; Delete; }{ Surface{holes}; Delete; }");
    }
    // Surfaces lying over the largest one (the plate) that share no point
    // with it were meant to be cut from it: OpenCASCADE disks left by a file
    // cut short before its BooleanDifference.
    const auto box_of = [](const std::pair<int, int>& s) {
      std::array<double, 6> b{};
      gmsh::model::getBoundingBox(s.first, s.second, b[0], b[1], b[2], b[3], b[4], b[5]);
      return b;
    };
    const auto points_of = [](const std::pair<int, int>& s) {
      gmsh::vectorpair out;
      gmsh::model::getBoundary({s}, out, false, false, true);
      std::set<int> tags;
      for (const auto& e : out) tags.insert(std::abs(e.second));
      return tags;
    };
    const auto box_area = [](const std::array<double, 6>& b) { return (b[3] - b[0]) * (b[4] - b[1]); };
    std::size_t plate = 0;
    for (std::size_t k = 1; k < surfaces.size(); ++k)
      if (box_area(box_of(surfaces[k])) > box_area(box_of(surfaces[plate]))) plate = k;
    const auto plate_box = box_of(surfaces[plate]);
    const auto plate_points = points_of(surfaces[plate]);
    const double small = 1e-9 * std::hypot(plate_box[3] - plate_box[0], plate_box[4] - plate_box[1]);
    std::vector<int> over;
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
      if (k == plate) continue;
      const auto b = box_of(surfaces[k]);
      const bool overlaps = std::min(b[3], plate_box[3]) - std::max(b[0], plate_box[0]) > small &&
                            std::min(b[4], plate_box[4]) - std::max(b[1], plate_box[1]) > small;
      const auto points = points_of(surfaces[k]);
      const bool shares = std::any_of(points.begin(), points.end(), [&](int p) { return plate_points.count(p) > 0; });
      if (overlaps && !shares) over.push_back(surfaces[k].second);
    }
    if (over.size() + 1 == surfaces.size()) {
      std::string tags;
      for (std::size_t k = 0; k < over.size() && k < 6; ++k) tags += (k ? ", " : "") + std::to_string(over[k]);
      if (over.size() > 6) tags += ", ...";
      const std::string plate_tag = std::to_string(surfaces[plate].second);
      throw file_error(file, std::to_string(over.size()) + " surface" + (over.size() == 1 ? " (" : "s (") + tags +
                                 (over.size() == 1 ? ") lies" : ") lie") + " on the plate (surface " + plate_tag +
                                 ") without being cut from it: was the file cut short before its "
                                 "BooleanDifference? To make them holes, subtract them: BooleanDifference{ Surface{" +
                                 plate_tag + "}; Delete; }{ Surface{...}; Delete; }");
    }
    // A plate split into pieces (for gmsh's own meshing, or a hole given a
    // surface of its own): pd-mesh meshes the plate from one surface's loops.
    std::string tags;
    for (std::size_t k = 0; k < surfaces.size() && k < 6; ++k) tags += (k ? ", " : "") + std::to_string(surfaces[k].second);
    if (surfaces.size() > 6) tags += ", ...";
    // Pieces left by a BooleanDifference (that deletes what it cuts, above):
    // what it subtracts runs across the plate, a notch or slot longer than
    // the plate. Before 7 December 2026 told to join the pieces with
    // BooleanUnion, which would fill the notch.
    if (statements.first_difference_line > 0)
      throw Error(file + ":" + std::to_string(statements.first_difference_line) +
                  ": BooleanDifference leaves the plate in " + std::to_string(surfaces.size()) + " pieces (surfaces " +
                  tags + "): what it subtracts runs across the plate (a notch or slot longer than the plate, or "
                  "coordinates in another unit?); pd-mesh meshes one plate: keep the cut within the plate, so that "
                  "it stays one piece");
    throw file_error(file, "expected exactly one plane surface, found " + std::to_string(surfaces.size()) + " (" +
                               tags + "): pd-mesh meshes one plate from its boundary loops; give it as one 'Plane "
                               "Surface' of the outer curve loop and the holes' loops (a hole is a loop of that "
                               "surface, not a surface of its own), or join the pieces with OpenCASCADE's "
                               "BooleanUnion");
  }
  gmsh::vectorpair boundary;
  gmsh::model::getBoundary({surfaces[0]}, boundary, false, false, false);
  std::set<int> tag_set;
  for (const auto& [dim, tag] : boundary)
    // A curve twice in the boundary: a hole loop listed twice in 'Plane
    // Surface' (gmsh meshes it once, so the file's surface is not the plate
    // meant), or a slit walked both ways (no area: a crack belongs to the scene).
    if (!tag_set.insert(std::abs(tag)).second)
      throw file_error(file, "curve " + std::to_string(std::abs(tag)) +
                                 " is twice in the surface's boundary: a curve loop listed twice in 'Plane Surface', "
                                 "or a curve walked there and back (a slit); list each hole's loop once, and give a "
                                 "crack as [[precracks]] in the scene (docs/scenes.md)");
  const std::vector<int> tags(tag_set.begin(), tag_set.end());
  if (tags.empty()) throw file_error(file, "the surface has no boundary curves");
  // Curves or points embedded in the surface ("Line{..} In Surface{..}"):
  // pd-mesh builds its grid from the boundary loops alone, so an embedded
  // crack would be dropped without a trace. Cracks belong to the scene.
  gmsh::vectorpair embedded;
  gmsh::model::mesh::getEmbedded(surfaces[0].first, surfaces[0].second, embedded);
  if (!embedded.empty()) {
    std::string curves, points;
    for (const auto& [dim, tag] : embedded)
      (dim == 1 ? curves : points) += std::string((dim == 1 ? curves : points).empty() ? "" : ", ") + std::to_string(tag);
    const std::string what = (curves.empty() ? "" : "curve " + curves) +
                             (!curves.empty() && !points.empty() ? " and " : "") +
                             (points.empty() ? "" : "point " + points);
    throw file_error(file, what + " embedded in the surface ('In Surface'): pd-mesh meshes the plate from its "
                                  "boundary loops and would ignore them; draw a crack as [[precracks]] in the scene "
                                  "(docs/scenes.md), a slit or notch as part of the boundary loop");
  }

  // Tolerances relative to the model size (file units).
  double bx0, by0, bz0, bx1, by1, bz1;
  gmsh::model::getBoundingBox(surfaces[0].first, surfaces[0].second, bx0, by0, bz0, bx1, by1, bz1);
  const double tolerance = 1e-7 * std::hypot(bx1 - bx0, by1 - by0) + 1e-9;
  // A plate lies in the xy plane: a tilted or warped surface would be meshed
  // as its projection, with the wrong areas. (OpenCASCADE pads its boxes by
  // about 1e-7 file units, hence the looser bound.)
  if (bz1 - bz0 > 1e-6 * std::hypot(bx1 - bx0, by1 - by0) + 1e-6) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "the surface is not flat in the xy plane: z runs from %g to %g (file units); pd-mesh meshes "
                  "plates at z = 0",
                  bz0, bz1);
    throw file_error(file, text);
  }

  PlateOutline outline;
  outline.file = file;
  gmsh::model::getCurrent(outline.gmsh_model);  // gmsh renames the model after the file
  outline.unit = unit;
  outline.physical_curve_names = std::move(physical_curve_names);
  chain_loops(tags, tolerance, file, unit, outline);
  // A named group of points or of the surface gives no set (sets are made of
  // curves: docs/mesher.md, "Boundary sets"); a scene that names it would
  // only be told by pd-solve that no such set exists.
  for (const int dim : {0, 2}) {
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, dim);
    for (const auto& group : groups) {
      std::string name;
      gmsh::model::getPhysicalName(group.first, group.second, name);
      if (name.empty()) continue;
      outline.warnings.push_back(
          std::string(dim == 0 ? "Physical Point" : "Physical Surface") + "(\"" + name +
          "\") makes no boundary set: pd-mesh makes sets of Physical Curve groups only (docs/mesher.md, \"Boundary "
          "sets\"); " +
          (dim == 0 ? "a scene acts on the particle nearest a point with nearest = [x, y] (docs/scenes.md)"
                    : "a scene's set = \"all\" is every particle of the plate"));
    }
  }

  // The outer loop encloses the largest area; it runs counter-clockwise, the
  // holes clockwise (material on the left of every loop).
  std::vector<double> areas;
  for (const auto& loop : outline.loops) areas.push_back(signed_area(coarse_polyline(loop)));
  const auto outer = static_cast<std::size_t>(
      std::max_element(areas.begin(), areas.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); }) -
      areas.begin());
  std::swap(outline.loops[0], outline.loops[outer]);
  std::swap(areas[0], areas[outer]);
  outline.area = 0;
  for (std::size_t l = 0; l < outline.loops.size(); ++l) {
    auto& loop = outline.loops[l];
    const bool counter_clockwise = areas[l] > 0;
    if (counter_clockwise != (l == 0)) {
      std::reverse(loop.begin(), loop.end());
      for (auto& c : loop) std::swap(c.t_start, c.t_end), std::swap(c.start_vertex, c.end_vertex);
    }
    outline.area += (l == 0 ? 1 : -1) * std::fabs(areas[l]) * unit * unit;
  }
  outline.xmin = outline.ymin = INFINITY;
  outline.xmax = outline.ymax = -INFINITY;
  for (const auto& p : coarse_polyline(outline.loops[0])) {
    outline.xmin = std::min(outline.xmin, p.x * unit), outline.xmax = std::max(outline.xmax, p.x * unit);
    outline.ymin = std::min(outline.ymin, p.y * unit), outline.ymax = std::max(outline.ymax, p.y * unit);
  }
  // Curves that close a loop inside the plate without bounding its surface
  // are a hole whose curve loop was left out of 'Plane Surface': meshed as
  // material, exit 0, before 7 December 2026. Open curves (a physical group
  // across the plate) and curves of a physical group stay allowed.
  {
    gmsh::vectorpair all_curves, groups;
    gmsh::model::getEntities(all_curves, 1);
    gmsh::model::getPhysicalGroups(groups, 1);
    std::set<int> grouped;
    for (const auto& [dim, group] : groups) {
      std::vector<int> members;
      gmsh::model::getEntitiesForPhysicalGroup(dim, group, members);
      for (int m : members) grouped.insert(std::abs(m));
    }
    std::map<int, std::vector<int>> ends;  // unused curve -> its end points
    for (const auto& [dim, tag] : all_curves) {
      if (tag_set.count(tag) || grouped.count(tag)) continue;
      std::vector<int> upward, downward;
      gmsh::model::getAdjacencies(dim, tag, upward, downward);
      ends[tag] = downward;
    }
    // Leave the closed chains: drop a curve with an end that no other
    // remaining curve shares, until none is left to drop.
    for (bool dropped = true; dropped;) {
      dropped = false;
      std::map<int, int> degree;
      for (const auto& [tag, points] : ends) {
        if (points.size() == 1) degree[points[0]] += 2;  // a whole circle: its one point, both ways
        for (int point : points) degree[point] += points.size() == 1 ? 0 : 1;
      }
      for (auto it = ends.begin(); it != ends.end();) {
        const bool open = it->second.empty() ||
                          std::any_of(it->second.begin(), it->second.end(), [&](int q) { return degree[q] < 2; });
        if (open) it = ends.erase(it), dropped = true;
        else ++it;
      }
    }
    const auto outer = coarse_polyline(outline.loops[0]);
    std::vector<int> inside;
    for (const auto& [tag, points] : ends) {
      std::vector<double> mn, mx;
      gmsh::model::getParametrizationBounds(1, tag, mn, mx);
      if (point_in_polygon(evaluate_curve(tag, {0.5 * (mn.at(0) + mx.at(0))})[0], outer)) inside.push_back(tag);
    }
    if (!inside.empty()) {
      std::string names;
      for (std::size_t k = 0; k < inside.size() && k < 8; ++k)
        names += (k == 0 ? "" : k + 1 == inside.size() ? " and " : ", ") + std::to_string(inside[k]);
      if (inside.size() > 8) names += ", ...";
      // (Before 7 December 2026 one curve was said to 'close a loop ... but bound no surface'.)
      throw file_error(file, std::string(inside.size() == 1 ? "curve " : "curves ") + names +
                                 (inside.size() == 1 ? " closes a loop inside the plate but bounds no surface: "
                                                     : " close a loop inside the plate but bound no surface: ") +
                                 "was a hole's curve loop left out of 'Plane Surface'? List it there (Plane "
                                 "Surface(1) = {outer loop, hole loops}), or delete " +
                                 (inside.size() == 1 ? "the curve" : "the curves"));
    }
  }
  // A plate without holes that the file meant to have them, which gmsh
  // reads without a word (before 7 December 2026 meshed as a plain plate,
  // exit 0): a file cut short after its outer boundary, whose numbers set for
  // the holes (their radius, their pitch) nothing reads; a BooleanDifference
  // whose tools miss the plate (in another unit, off by a sign), which leaves
  // it a plain four-sided plate.
  if (outline.loops.size() == 1) {
    const auto statements = geometry_statements(file);
    const auto& unread = statements.unread_names;
    // Only a plate made by OpenCASCADE can be cut short after its outer
    // boundary: with the built-in kernel alone the plate is the Plane
    // Surface of its loops, which comes after the holes' loops it lists.
    // There an unread name is the file's own (a thickness, a mesh size
    // pd-mesh does not use), not a sign of holes lost (before 7 December
    // 2026 a plain built-in plate that set one was warned about as cut short).
    if (!unread.empty() && statements.opencascade) {
      std::string names;
      const std::size_t shown = std::min<std::size_t>(unread.size(), 4);
      for (std::size_t k = 0; k < shown; ++k)
        names += (k == 0 ? "" : k + 1 == unread.size() ? " and " : ", ") +
                 ("'" + unread[k].first + "' (line " + std::to_string(unread[k].second) + ")");
      if (unread.size() > shown) names += ", ...";
      outline.warnings.push_back("the plate has no hole, yet the file sets " + names + " that no statement reads: "
                                 "was it cut short after line " + std::to_string(statements.last_statement_line) +
                                 ", its last statement? It is meshed as it stands, without holes; give the whole "
                                 "file, or leave out what it does not use");
    }
    const auto& loop = outline.loops[0];
    const bool four_lines = loop.size() == 4 && std::all_of(loop.begin(), loop.end(), [](const PlateOutline::Curve& c) {
                              return c.type == "Line";
                            });
    if (statements.first_difference_line > 0 && four_lines)
      outline.warnings.push_back("line " + std::to_string(statements.first_difference_line) +
                                 ": BooleanDifference leaves the plate four-sided and without a hole: what it "
                                 "subtracts lies off the plate (coordinates in another unit, or off by a sign?), "
                                 "and the plate is meshed whole; place the holes on the plate (" +
                                 shortest_text(outline.xmin / unit) + " to " + shortest_text(outline.xmax / unit) +
                                 " by " + shortest_text(outline.ymin / unit) + " to " +
                                 shortest_text(outline.ymax / unit) + " in file units)");
  }
  return outline;
}

std::string plate_unit_warning(const PlateOutline& outline, const std::string& geo_unit) {
  // Said first: the spacing or memory checks then fail with sizes that
  // only this explains.
  const double width = outline.xmax - outline.xmin, height = outline.ymax - outline.ymin;
  if (std::max(width, height) >= 1e-3 && std::max(width, height) <= 10) return "";
  char text[400];
  std::snprintf(text, sizeof text,
                "the plate is %g m x %g m, read with --geo-unit %s; if the file is written in another unit, give it "
                "(--geo-unit m, cm, mm or um)",
                width, height, geo_unit.c_str());
  return outline.file + ": " + text;
}

std::vector<std::string> check_lengths_against_plate(const PlateOutline& outline, const PlateSizedLengths& l) {
  const double width = outline.xmax - outline.xmin, height = outline.ymax - outline.ymin;
  const double larger = std::max(width, height);
  const bool padded = l.nbnug && !l.padding_text.empty();
  const bool region = l.refinement && l.refinement->factor > 1;
  const bool graded = l.graded && l.graded->enabled();
  // Boxes padded by ten plates are a padding in another unit (1e30 mm
  // overflowed the box arithmetic); boxes larger than the plate cover it
  // whole anyway, which a free mesh of the plate (--grid free) does.
  if (padded && l.padding > 10 * larger)
    throw Error("--padding " + format_mm(l.padding) + " is more than ten times the plate's larger side (" +
                format_mm(larger) + "): is it in another unit? Boxes as large as the plate cover it whole; for a "
                "free mesh of the whole plate use --grid free");
  if (region) snap_to_lattice(*l.refinement, l.spacing, outline.xmin, outline.ymin, outline.xmax, outline.ymax,
                              "--refine-region");
  if (graded && !has_curved_boundary(outline))
    throw Error(outline.file + ": --graded-spacing " + l.graded_spacing_text +
                " grades the cells from DXF at the curved boundaries (holes, arcs) to dx, and every boundary of "
                "this plate is straight; for a finer grid everywhere give a smaller --spacing");
  std::vector<std::string> warnings;
  // The options' texts are as typed, of any length: formatted to the size they need.
  const auto warn = [&](const char* format, auto... values) {
    std::string text(static_cast<std::size_t>(std::snprintf(nullptr, 0, format, values...)), '\0');
    std::snprintf(text.data(), text.size() + 1, format, values...);
    warnings.push_back(outline.file + ": " + text);
  };
  // A box is its curves' bounding box grown by the padding, clipped to the
  // plate's: from the plate's larger side on, every box is the whole plate,
  // and a larger padding changes nothing (the free mesh of the whole plate,
  // without the squares the NB-NUG grid is for).
  if (padded && l.padding > larger) {
    warn("--padding %s is more than the plate's larger side (the plate is %s x %s): every box around a "
         "curve off the lattice lines covers the whole plate, so the grid is a free mesh of all of it, "
         "without the squares the NB-NUG grid is for; a padding is a horizon (the default, %s) or a few; "
         "for a free mesh of the whole plate use --grid free",
         l.padding_text.c_str(), format_mm(width).c_str(), format_mm(height).c_str(),
         format_mm(l.horizon).c_str());
  }
  // A refinement region of ten plates is most likely in another unit
  // (0m,0m,5m,5m for 5 mm): clipped to the plate, it refines all of it,
  // which the summary alone would not explain.
  if (region && std::max(l.refinement->x1 - l.refinement->x0, l.refinement->y1 - l.refinement->y0) > 10 * larger) {
    warn("--refine-region %s is more than ten times the plate's larger side (%s) across: is it in another "
         "unit? Clipped to the plate it refines all the plate it covers; a region is the part of the plate "
         "to refine (the plate spans x %s to %s, y %s to %s)",
         l.refine_region_text.c_str(), format_mm(larger).c_str(), format_mm(outline.xmin).c_str(),
         format_mm(outline.xmax).c_str(), format_mm(outline.ymin).c_str(), format_mm(outline.ymax).c_str());
  }
  // A grading length of ten plates is most likely in another unit
  // (0.1mm,20m for 20 mm): across the plate the cells then grow by less
  // than a tenth of dx - DXF, a free mesh at about DXF everywhere, which
  // the summary's cell sizes alone would not explain.
  if (graded && l.graded->length > 10 * larger) {
    warn("--graded-spacing %s: the grading length L %s is more than ten times the plate's larger side (%s): "
         "is it in another unit? The cells grow by less than a tenth of the way from DXF %s to dx %s "
         "across the plate, a free mesh at about DXF everywhere; L is a few horizons (the default, %g "
         "horizons, is %s)",
         l.graded_spacing_text.c_str(), format_mm(l.graded->length).c_str(), format_mm(larger).c_str(),
         format_mm(l.graded->fine).c_str(), format_mm(l.spacing).c_str(), default_grading_horizons,
         format_mm(default_grading_horizons * l.horizon).c_str());
  }
  return warnings;
}

PlateGeometry sample_plate(GmshSession&, const PlateOutline& outline, double spacing, double curved_spacing) {
  gmsh::model::setCurrent(outline.gmsh_model);
  const double unit = outline.unit;
  const std::string& file = outline.file;
  PlateGeometry g;
  g.file = file;
  g.unit = unit;
  // Polylines within a millionth of a spacing of the curves: what decides
  // whether a bond crosses a void (docs/mesher.md).
  g.boundary_tolerance = 1e-6 * spacing;
  const double tolerance_units = g.boundary_tolerance / unit, spacing_units = spacing / unit;
  const double curved_units = (curved_spacing > 0 ? curved_spacing : spacing) / unit;

  std::map<int, const BoundaryCurve*> curve_by_tag;
  std::vector<BoundaryLoop> loops;
  for (std::size_t l = 0; l < outline.loops.size(); ++l) {
    const auto& raw = outline.loops[l];
    BoundaryLoop loop;
    loop.outer = l == 0;
    std::vector<CurvePolyline> polylines;
    std::vector<int> pieces;
    for (const auto& c : raw) {
      polylines.push_back(curve_polyline(c.tag, c.t_start, c.t_end, c.type == "Line", tolerance_units));
      const double piece_units = c.type == "Line" ? spacing_units : curved_units;
      pieces.push_back(std::max(1, static_cast<int>(std::lround(polylines.back().length() / piece_units))));
    }
    // Keep even a tiny hole a recognisable polygon.
    const int total = std::accumulate(pieces.begin(), pieces.end(), 0);
    if (!loop.outer && total < 8) {
      std::size_t longest = 0;
      for (std::size_t c = 0; c < raw.size(); ++c)
        if (polylines[c].length() > polylines[longest].length()) longest = c;
      pieces[longest] += 8 - total;
    }
    std::set<std::string> types;
    double twice_area = 0, bulges = 0;
    for (std::size_t k = 0; k < raw.size(); ++k) {
      const auto& c = raw[k];
      BoundaryCurve curve;
      curve.tag = c.tag;
      curve.type = c.type;
      curve.start = scaled({outline.vertices[c.start_vertex]}, unit)[0];
      curve.end = scaled({outline.vertices[c.end_vertex]}, unit)[0];
      curve.polyline = scaled(polylines[k].points, unit);
      curve.polyline.front() = curve.start, curve.polyline.back() = curve.end;
      curve.length = polylines[k].length() * unit;
      curve.samples = make_samples(c, polylines[k], pieces[k], curve.start, curve.end, unit);
      curve.samples_one_more = make_samples(c, polylines[k], pieces[k] + 1, curve.start, curve.end, unit);
      types.insert(c.type);
      // Enclosed area: the polygon of the samples plus the bulges (signed with the loop).
      const auto& pts = curve.samples.points;
      for (std::size_t i = 0; i + 1 < pts.size(); ++i) twice_area += pts[i].x * pts[i + 1].y - pts[i + 1].x * pts[i].y;
      for (double b : curve.samples.bulge) bulges += b;
      loop.curves.push_back(std::move(curve));
    }
    // Signed polygon area plus the bulges (both signed with the loop's
    // direction): the area enclosed by the true curves.
    loop.area = std::fabs(0.5 * twice_area + bulges);
    loop.curve_types.assign(types.begin(), types.end());
    loop.xmin = loop.ymin = INFINITY;
    loop.xmax = loop.ymax = -INFINITY;
    for (const auto& p : loop.polyline()) {
      loop.xmin = std::min(loop.xmin, p.x), loop.xmax = std::max(loop.xmax, p.x);
      loop.ymin = std::min(loop.ymin, p.y), loop.ymax = std::max(loop.ymax, p.y);
    }
    loops.push_back(std::move(loop));
  }

  // Simple, apart, and holes where holes belong.
  std::vector<std::vector<Vec2>> polylines;
  for (const auto& loop : loops) polylines.push_back(loop.polyline());
  if (const auto contact = find_boundary_contact(polylines)) {
    const std::string where = at_mm(contact->where, 1.0);
    // Which curves meet there: among 20 traced pores the place alone leaves
    // the file to be searched.
    auto curves = curves_through(loops[contact->loop_a], contact->where, g.boundary_tolerance);
    if (contact->loop_b != contact->loop_a)
      for (const auto* c : curves_through(loops[contact->loop_b], contact->where, g.boundary_tolerance))
        curves.push_back(c);
    if (contact->loop_a == contact->loop_b) {
      // A curve through points (gmsh calls a built-in Spline "Nurb") loops
      // where they double back; a Spline (Catmull-Rom) also where a point is
      // given twice in a row: it leaves and re-enters it in two directions.
      const bool through_points =
          curves.size() == 1 && (curves[0]->type == "Nurb" || curves[0]->type == "BSpline" || curves[0]->type == "Bezier");
      throw file_error(file, std::string(curves.size() > 1 ? "a boundary loop" : "a boundary curve") +
                                 " intersects itself near " + where + curve_names(curves) +
                                 (through_points ? ": a Spline through the same point twice in a row, or a spline "
                                                   "through points that double back, loops there"
                                                 : ""));
    }
    const std::string which = curve_names(curves);
    if (contact->loop_a == 0 || contact->loop_b == 0)
      throw file_error(file, "a hole touches or crosses the outer boundary near " + where + which +
                                 " without sharing a point with it (to cut a notch, subtract the hole from the "
                                 "plate, e.g. with OpenCASCADE's BooleanDifference)");
    throw file_error(file, "two holes touch or cross near " + where + which +
                               " without sharing a point (merge them, e.g. with OpenCASCADE's BooleanUnion)");
  }
  if (const auto touch = touch_without_common_point(loops, 4 * g.boundary_tolerance, spacing)) {
    const std::string where = at_mm(touch->where, 1.0);
    // The curves that meet there, as for a crossing.
    auto curves = curves_through(loops[touch->loop_a], touch->where, 4 * g.boundary_tolerance);
    for (const auto* c : curves_through(loops[touch->loop_b], touch->where, 4 * g.boundary_tolerance))
      curves.push_back(c);
    const std::string which = curve_names(curves);
    if (touch->loop_a == 0 || touch->loop_b == 0)
      throw file_error(file, "a hole touches the outer boundary near " + where + which +
                                 " without sharing a point with it (to cut a notch, subtract the hole from the "
                                 "plate, e.g. with OpenCASCADE's BooleanDifference; to keep a ligament, move the "
                                 "hole off the edge)");
    throw file_error(file, "two holes touch near " + where + which +
                               " without sharing a point (merge them, e.g. with OpenCASCADE's BooleanUnion, or move "
                               "them apart)");
  }
  // A loop whose curves run along each other (two arcs the same way between
  // two points) encloses nothing: the uniform grid took it for a void 0 mm
  // wide and the other grids failed inside gmsh. Its mean width 2 A / P is
  // compared with the tolerance that decides whether a bond crosses a void.
  // (After the crossings: a bow-tie's lobes cancel too.)
  for (const auto& loop : loops) {
    double perimeter = 0;
    for (const auto& c : loop.curves) perimeter += c.length;
    if (2 * loop.area / perimeter >= g.boundary_tolerance) continue;
    std::vector<const BoundaryCurve*> curves;
    for (const auto& c : loop.curves) curves.push_back(&c);
    throw file_error(file, std::string(loop.outer ? "the outer boundary" : "a hole") + curve_names(curves) +
                               " encloses no area: its curves run along each other (a hole must enclose area; "
                               "a crack is a pre-crack of the scene, docs/scenes.md)");
  }
  for (std::size_t a = 1; a < loops.size(); ++a) {
    const Vec2 probe = loops[a].curves[0].samples.points[0];
    if (!point_in_polygon(probe, polylines[0]))
      throw file_error(file, "a hole lies outside the outer boundary near " + at_mm(probe, 1.0));
    for (std::size_t b = 1; b < loops.size(); ++b) {
      if (a == b || loops[a].xmin < loops[b].xmin || loops[a].xmax > loops[b].xmax || loops[a].ymin < loops[b].ymin ||
          loops[a].ymax > loops[b].ymax)
        continue;
      if (point_in_polygon(probe, polylines[b]))
        throw file_error(file, "a hole lies inside another hole near " + at_mm(probe, 1.0));
    }
  }

  g.outer = std::move(loops[0]);
  g.outer.name = "outer";
  g.holes.assign(std::make_move_iterator(loops.begin() + 1), std::make_move_iterator(loops.end()));
  g.xmin = g.outer.xmin, g.xmax = g.outer.xmax, g.ymin = g.outer.ymin, g.ymax = g.outer.ymax;
  // Stable names: order by centre x, then y.
  std::sort(g.holes.begin(), g.holes.end(), [](const BoundaryLoop& a, const BoundaryLoop& b) {
    const double ax = a.xmin + a.xmax, bx = b.xmin + b.xmax;
    if (ax != bx) return ax < bx;
    return a.ymin + a.ymax < b.ymin + b.ymax;
  });
  for (std::size_t k = 0; k < g.holes.size(); ++k) g.holes[k].name = "hole_" + std::to_string(k + 1);

  // User-named curve groups: the boundary's polylines where the curve is on
  // the boundary, a polyline of their own otherwise.
  for (const auto* loop : g.loops())
    for (const auto& c : loop->curves) curve_by_tag[c.tag] = &c;
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 1);
  std::set<std::string> group_names;
  for (const auto& [dim, group] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, group, name);
    group_names.insert(name);
  }
  for (const auto& [name, line] : outline.physical_curve_names)
    if (!group_names.count(name))
      throw Error(file + ":" + std::to_string(line) + ": physical curve group '" + name +
                  "' holds no curve of the geometry (gmsh drops a curve number that names no curve)");
  for (const auto& [dim, group] : groups) {
    NamedCurves named;
    gmsh::model::getPhysicalName(dim, group, named.name);
    if (named.name.empty()) named.name = "physical_" + std::to_string(group);
    // The loading layers' sets have these names (docs/mesher.md, "Loading
    // layers"), and a run leaves their particles out of the body's energy:
    // a group of the plate's own curves under such a name would pass for one.
    if (named.name.rfind("loading_layer_", 0) == 0)
      throw file_error(file, "physical curve group '" + named.name +
                                 "': names starting with 'loading_layer_' are those of the loading layers' sets "
                                 "(pd-mesh --loading-layer); give the group another name");
    // A scene's set = "all" means every particle (docs/scenes.md): a group of
    // that name could never be loaded.
    if (named.name == "all")
      throw file_error(file, "physical curve group 'all': a scene's set = \"all\" means every particle of the "
                             "plate, so a set of this name could not be used; give the group another name");
    std::vector<int> curve_tags;
    gmsh::model::getEntitiesForPhysicalGroup(dim, group, curve_tags);
    for (int tag : curve_tags) {
      std::vector<Vec2> pts;
      if (const auto found = curve_by_tag.find(tag); found != curve_by_tag.end()) {
        pts = found->second->polyline;
      } else {
        std::string type;
        gmsh::model::getType(1, tag, type);
        std::vector<double> mn, mx;
        gmsh::model::getParametrizationBounds(1, tag, mn, mx);
        pts = scaled(curve_polyline(tag, mn.at(0), mx.at(0), type == "Line", tolerance_units).points, unit);
      }
      for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
        named.a.push_back(pts[k]);
        named.b.push_back(pts[k + 1]);
      }
    }
    g.physical_curves.push_back(std::move(named));
  }
  return g;
}

MaterialBoundary material_boundary(const PlateGeometry& g, double spacing, double horizon) {
  std::vector<std::vector<Vec2>> loops;
  for (const auto* loop : g.loops()) loops.push_back(loop->polyline());
  return MaterialBoundary(loops, 1e-9 * spacing, horizon);
}

PlateGeometry load_plate_geometry(GmshSession& session, const std::string& file, double unit, double spacing) {
  return sample_plate(session, read_plate_outline(session, file, unit), spacing);
}

}  // namespace pd
