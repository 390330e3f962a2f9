#include "free_region.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "error.hpp"
#include "units.hpp"

namespace pd {

Lattice plate_lattice(const PlateGeometry& g, double dx) {
  const double width = g.xmax - g.xmin, height = g.ymax - g.ymin;
  // A side bounded by a curve is known to the polylines' tolerance (1e-6 dx).
  const auto fits = [&](double length, double d, long& n) {
    n = std::lround(length / d);
    return n >= 1 && std::fabs(n * d - length) <= 1e-9 * length + 1e-5 * d;
  };
  // Which sides of the bounding box a straight outer curve lies along: those
  // must be lattice lines (their cells whole squares, loading layers
  // possible). A side that the plate only touches at a vertex or along a
  // curve (a rotated plate, a hexagon's corner, an arch) need not: the lattice
  // then runs past it by part of a cell, anchored at the opposite side.
  bool straight_side[4] = {false, false, false, false};
  for (const auto& c : g.outer.curves)
    if (const int side = bounding_box_side(c, g); side >= 0) straight_side[side] = true;
  Lattice lattice{g.xmin, g.ymin, dx, 0, 0};
  // Lays the lattice along one axis: whole cells from side to side, or
  // running past the side without a straight curve.
  const auto lay = [&](double low, double high, bool straight_low, bool straight_high, double& origin, long& n) {
    const double length = high - low;
    if (fits(length, lattice.dx, n)) return true;
    if (straight_low && straight_high) return false;
    n = static_cast<long>(std::ceil(length / lattice.dx - 1e-9));
    origin = straight_low || !straight_high ? low : high - static_cast<double>(n) * lattice.dx;
    return true;
  };
  const bool x_free = !(straight_side[0] && straight_side[1]), y_free = !(straight_side[2] && straight_side[3]);
  if (fits(width, dx, lattice.nx)) {
    // A spacing within the slack of dividing the width, but not to the
    // billionth of a spacing at which a straight side counts as lying on a
    // lattice line (on_lattice_line), is taken as the exact division: it is a
    // rounded print of it, such as the suggestion below (ten digits); else
    // the right side would be a free region's boundary that does not close.
    if (std::fabs(lattice.nx * dx - width) > 1e-10 * dx) lattice.dx = width / static_cast<double>(lattice.nx);
  }
  if (lay(g.xmin, g.xmax, straight_side[0], straight_side[1], lattice.x0, lattice.nx) &&
      lay(g.ymin, g.ymax, straight_side[2], straight_side[3], lattice.y0, lattice.ny))
    return lattice;
  // Nearest spacing that divides the sides along which straight curves lie
  // on both ends: dx = width / n for n near width / dx (or the height's).
  double best = 0;
  if (x_free || y_free) {
    const double length = x_free ? height : width;
    best = length / static_cast<double>(std::max(1L, std::lround(length / dx)));
  } else {
    const long n0 = std::max(1L, std::lround(width / dx));
    for (long d = 0; d < 100000 && best == 0; ++d)
      for (long n : {n0 - d, n0 + d}) {
        long m;
        if (n >= 1 && fits(height, width / n, m)) {
          best = width / n;
          break;
        }
      }
  }
  char buf[256];
  std::snprintf(buf, sizeof buf, "the plate's bounding box (%s x %s) is not an integer number of spacings %s",
                format_mm(width).c_str(), format_mm(height).c_str(), format_mm(dx).c_str());
  std::string message = buf;
  if (best > 0) {
    std::snprintf(buf, sizeof buf, "%.10gmm", best * 1e3);
    message += std::string("; the nearest spacing that fits ") +
               (x_free ? "its height" : y_free ? "its width" : "both sides") + " is " + format_mm(best) +
               " (--spacing " + buf + ")";
  }
  throw file_error(g.file, message);
}

namespace {

// Within a billionth of a spacing of a lattice line.
bool on_line(double v, double origin, double dx) {
  const double t = (v - origin) / dx;
  return std::fabs(t - std::round(t)) <= 1e-9;
}

bool horizontal(const BoundaryCurve& c, double dx) { return std::fabs(c.start.y - c.end.y) <= 1e-9 * dx; }

}  // namespace

bool on_lattice_line(const BoundaryCurve& c, const Lattice& l) {
  if (!c.straight()) return false;
  if (horizontal(c, l.dx)) return on_line(c.start.y, l.y0, l.dx);
  if (std::fabs(c.start.x - c.end.x) <= 1e-9 * l.dx) return on_line(c.start.x, l.x0, l.dx);
  return false;
}

namespace {

// For every cell row, whether the cell centres lie in the material (even-odd
// rule over all loops' polylines, crossings of the row's centre line counted
// half-open so that a vertex on the line counts once).
std::vector<std::uint8_t> centres_in_material(const PlateGeometry& g, const Lattice& l) {
  std::vector<std::pair<long, double>> crossings;  // (row, x)
  for (const auto* loop : g.loops()) {
    const auto pts = loop->polyline();
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const Vec2 p = pts[k], q = pts[(k + 1) % pts.size()];
      if (p.y == q.y) continue;
      const double lo = std::min(p.y, q.y), hi = std::max(p.y, q.y);
      // Rows whose centre y0 + (j + 1/2) dx lies in [lo, hi).
      const long j0 = std::max(0L, static_cast<long>(std::ceil((lo - l.y0) / l.dx - 0.5)));
      const long j1 = std::min(l.ny - 1, static_cast<long>(std::ceil((hi - l.y0) / l.dx - 0.5)) - 1);
      for (long j = j0; j <= j1; ++j) {
        const double y = l.y0 + (j + 0.5) * l.dx;
        if (y < lo || y >= hi) continue;
        crossings.push_back({j, p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y)});
      }
    }
  }
  std::sort(crossings.begin(), crossings.end());
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(l.nx * l.ny), 0);
  std::size_t c = 0;
  for (long j = 0; j < l.ny; ++j) {
    while (c < crossings.size() && crossings[c].first < j) ++c;
    std::size_t count = 0;
    for (long i = 0; i < l.nx; ++i) {
      const double x = l.x0 + (i + 0.5) * l.dx;
      while (c + count < crossings.size() && crossings[c + count].first == j && crossings[c + count].second < x)
        ++count;
      inside[static_cast<std::size_t>(j * l.nx + i)] = count % 2;
    }
  }
  return inside;
}

}  // namespace

CellMap classify_cells(const PlateGeometry& g, const Lattice& l, GridKind grid, double padding) {
  CellMap map{l, std::vector<CellKind>(static_cast<std::size_t>(l.nx * l.ny), CellKind::outside)};
  if (grid == GridKind::free) {
    std::fill(map.kind.begin(), map.kind.end(), CellKind::free);
    return map;
  }
  if (grid == GridKind::nbnug) {
    const double eps = 1e-9;  // a bound exactly on a lattice line stays there
    const auto mark = [&](double xmin, double ymin, double xmax, double ymax) {
      const long i0 = std::max(0L, static_cast<long>(std::floor((xmin - padding - l.x0) / l.dx + eps)));
      const long i1 = std::min(l.nx, static_cast<long>(std::ceil((xmax + padding - l.x0) / l.dx - eps)));
      const long j0 = std::max(0L, static_cast<long>(std::floor((ymin - padding - l.y0) / l.dx + eps)));
      const long j1 = std::min(l.ny, static_cast<long>(std::ceil((ymax + padding - l.y0) / l.dx - eps)));
      for (long j = j0; j < j1; ++j)
        for (long i = i0; i < i1; ++i) map.kind[static_cast<std::size_t>(j * l.nx + i)] = CellKind::free;
    };
    for (const auto* loop : g.loops()) {
      const bool all_off_lattice =
          std::none_of(loop->curves.begin(), loop->curves.end(), [&](const BoundaryCurve& c) { return on_lattice_line(c, l); });
      if (!loop->outer && all_off_lattice) {
        mark(loop->xmin, loop->ymin, loop->xmax, loop->ymax);
        continue;
      }
      for (const auto& c : loop->curves) {
        if (on_lattice_line(c, l)) continue;
        // Pieces of about dx along the curve, each with its own box: a band
        // along the curve rather than one box around it. First points no
        // more than dx apart (a straight line is one chord), then runs of
        // them about dx long.
        std::vector<Vec2> points{c.polyline.front()};
        for (std::size_t k = 0; k + 1 < c.polyline.size(); ++k) {
          const Vec2 a = c.polyline[k], b = c.polyline[k + 1];
          const long pieces = std::max(1L, static_cast<long>(std::ceil(std::hypot(b.x - a.x, b.y - a.y) / l.dx)));
          for (long s = 1; s <= pieces; ++s) points.push_back(a + (static_cast<double>(s) / pieces) * (b - a));
        }
        for (std::size_t k = 0; k + 1 < points.size();) {
          double xmin = points[k].x, xmax = xmin, ymin = points[k].y, ymax = ymin, length = 0;
          std::size_t e = k;
          while (e + 1 < points.size() && length < l.dx) {
            length += std::hypot(points[e + 1].x - points[e].x, points[e + 1].y - points[e].y);
            ++e;
            xmin = std::min(xmin, points[e].x), xmax = std::max(xmax, points[e].x);
            ymin = std::min(ymin, points[e].y), ymax = std::max(ymax, points[e].y);
          }
          mark(xmin, ymin, xmax, ymax);
          k = e;
        }
      }
    }
  }
  const auto inside = centres_in_material(g, l);
  for (std::size_t c = 0; c < map.kind.size(); ++c)
    if (map.kind[c] != CellKind::free && inside[c]) map.kind[c] = CellKind::square;
  return map;
}

namespace {

std::int64_t lattice_key(long i, long j, const Lattice& l) { return static_cast<std::int64_t>(j) * (l.nx + 1) + i; }

// Builds the free regions' boundary edges from the boundary curves and the
// cell map, then traces them into loops. `one_more_curve` and
// `one_more_run` name the curves (loop, curve) and straight runs (loop, run
// number) that get one boundary segment more.
class RegionBuilder {
public:
  RegionBuilder(const PlateGeometry& g, const CellMap& cells, int edges_per_lattice_edge)
      : g_(g), cells_(cells), l_(cells.lattice), pieces_(edges_per_lattice_edge) {}

  std::set<std::pair<std::size_t, std::size_t>> one_more_curve, one_more_run;

  struct Built {
    FreeRegions regions;
    // Per region: its boundary edge count and the curves / runs in it that
    // could take one segment more, with their lengths.
    std::vector<std::size_t> edge_count;
    std::vector<std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>>> curves, runs;
  };

  Built build() {
    out_ = {};
    edges_.clear();
    edge_item_.clear();
    items_.clear();
    lattice_vertex_.clear();
    covered_.clear();
    const auto loops = g_.loops();
    for (std::size_t l = 0; l < loops.size(); ++l) add_loop(l, *loops[l]);
    add_interface_edges();
    return trace();
  }

private:
  const PlateGeometry& g_;
  const CellMap& cells_;
  const Lattice& l_;
  const int pieces_;  // boundary edges per lattice edge
  Built out_;
  std::vector<RegionEdge> edges_;
  // Per edge: -1 (lattice), or the index into items_ of the curve / run it belongs to.
  std::vector<long> edge_item_;
  struct Item {
    bool is_curve;
    std::pair<std::size_t, std::size_t> id;
    double length;
  };
  std::vector<Item> items_;
  std::unordered_map<std::int64_t, std::uint32_t> lattice_vertex_;
  std::unordered_set<std::int64_t> covered_;  // lattice edges on a boundary curve: 2 * key (+1 vertical)

  std::uint32_t new_vertex(Vec2 p) {
    out_.regions.vertices.push_back(p);
    return static_cast<std::uint32_t>(out_.regions.vertices.size() - 1);
  }
  std::uint32_t lattice_vertex(long i, long j) {
    const auto key = lattice_key(i, j, l_);
    const auto found = lattice_vertex_.find(key);
    if (found != lattice_vertex_.end()) return found->second;
    return lattice_vertex_[key] = new_vertex(l_.node(i, j));
  }
  // A point on the boundary: the lattice node if it is one, else a new vertex.
  std::uint32_t boundary_vertex(Vec2 p) {
    const double ti = (p.x - l_.x0) / l_.dx, tj = (p.y - l_.y0) / l_.dx;
    if (std::fabs(ti - std::round(ti)) <= 1e-9 && std::fabs(tj - std::round(tj)) <= 1e-9)
      return lattice_vertex(std::lround(ti), std::lround(tj));
    return new_vertex(p);
  }
  bool free_cell(long i, long j) const {
    return i >= 0 && j >= 0 && i < l_.nx && j < l_.ny && cells_.at(i, j) == CellKind::free;
  }
  void add_edge(RegionEdge e, long item) {
    edges_.push_back(e);
    edge_item_.push_back(item);
  }

  // A straight stretch of boundary on a lattice line with free cells on its
  // material side: from vertex a to vertex b, cut into about dx segments.
  void add_run(std::uint32_t a, std::uint32_t b, std::size_t loop, std::size_t& run_number) {
    const Vec2 pa = out_.regions.vertices[a], pb = out_.regions.vertices[b];
    const double length = std::hypot(pb.x - pa.x, pb.y - pa.y);
    const std::pair<std::size_t, std::size_t> id{loop, run_number++};
    const long count = std::max(1L, std::lround(length * pieces_ / l_.dx)) + (one_more_run.count(id) ? 1 : 0);
    items_.push_back({false, id, length});
    const long item = static_cast<long>(items_.size() - 1);
    std::uint32_t from = a;
    for (long s = 1; s <= count; ++s) {
      const std::uint32_t to =
          s == count ? b : boundary_vertex({pa.x + (pb.x - pa.x) * s / count, pa.y + (pb.y - pa.y) * s / count});
      add_edge({from, to}, item);
      from = to;
    }
  }

  void add_loop(std::size_t loop_index, const BoundaryLoop& loop) {
    const auto& curves = loop.curves;
    const std::size_t n = curves.size();
    std::vector<std::uint32_t> junction(n);
    for (std::size_t k = 0; k < n; ++k) junction[k] = boundary_vertex(curves[k].start);
    // Start where no straight run can be under way: after a curve off the
    // lattice, or at a corner between two lattice-line curves.
    std::size_t first = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const auto& prev = curves[(k + n - 1) % n];
      if (!on_lattice_line(prev, l_) || !on_lattice_line(curves[k], l_) ||
          horizontal(prev, l_.dx) != horizontal(curves[k], l_.dx)) {
        first = k;
        break;
      }
    }
    std::size_t run_number = 0;
    bool run_open = false;
    std::uint32_t run_start = 0, run_end = 0;
    const auto close_run = [&] {
      if (run_open) add_run(run_start, run_end, loop_index, run_number);
      run_open = false;
    };
    for (std::size_t s = 0; s < n; ++s) {
      const std::size_t k = (first + s) % n;
      const auto& c = curves[k];
      const std::uint32_t start = junction[k], end = junction[(k + 1) % n];
      if (!on_lattice_line(c, l_)) {
        close_run();
        const bool more = one_more_curve.count({loop_index, k}) > 0;
        const CurveSamples& samples = more ? c.samples_one_more : c.samples;
        items_.push_back({true, {loop_index, k}, c.length});
        const long item = static_cast<long>(items_.size() - 1);
        std::uint32_t from = start;
        for (std::size_t q = 0; q < samples.chords(); ++q) {
          const std::uint32_t to = q + 1 == samples.chords() ? end : new_vertex(samples.points[q + 1]);
          add_edge({from, to, &samples, q, !c.straight()}, item);
          from = to;
        }
        continue;
      }
      if (s > 0 && horizontal(c, l_.dx) != horizontal(curves[(k + n - 1) % n], l_.dx)) close_run();
      // Cut the curve at the lattice nodes along it; keep the pieces with a
      // free cell on their material (left) side.
      const bool along_x = horizontal(c, l_.dx);
      const double a = along_x ? c.start.x : c.start.y, b = along_x ? c.end.x : c.end.y;
      const double origin = along_x ? l_.x0 : l_.y0;
      const long line = along_x ? std::lround((c.start.y - l_.y0) / l_.dx) : std::lround((c.start.x - l_.x0) / l_.dx);
      const double direction = b > a ? 1 : -1;
      std::vector<std::pair<double, std::uint32_t>> cuts{{a, start}};
      const double lo = std::min(a, b), hi = std::max(a, b);
      const long n0 = static_cast<long>(std::ceil((lo - origin) / l_.dx + 1e-9));
      const long n1 = static_cast<long>(std::floor((hi - origin) / l_.dx - 1e-9));
      std::vector<long> nodes;
      for (long m = n0; m <= n1; ++m) nodes.push_back(m);
      if (direction < 0) std::reverse(nodes.begin(), nodes.end());
      for (long m : nodes)
        cuts.push_back({origin + m * l_.dx, along_x ? lattice_vertex(m, line) : lattice_vertex(line, m)});
      cuts.push_back({b, end});
      for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
        const double mid = 0.5 * (cuts[p].first + cuts[p + 1].first);
        const long across = static_cast<long>(std::floor((mid - origin) / l_.dx));
        // Material on the left: above a +x edge, below a -x edge, left of a +y edge, right of a -y edge.
        const bool material_free = along_x ? free_cell(across, direction > 0 ? line : line - 1)
                                           : free_cell(direction > 0 ? line - 1 : line, across);
        // Whole lattice edges on the boundary are never edges between a free cell and a square.
        const double piece = std::fabs(cuts[p + 1].first - cuts[p].first);
        if (std::fabs(piece - l_.dx) <= 1e-9 * l_.dx)
          covered_.insert(2 * (along_x ? lattice_key(across, line, l_) : lattice_key(line, across, l_)) + (along_x ? 0 : 1));
        if (!material_free) {
          close_run();
          continue;
        }
        if (!run_open) run_start = cuts[p].second, run_open = true;
        run_end = cuts[p + 1].second;
      }
    }
    close_run();
  }

  // The lattice edge from node (i0, j0) to node (i1, j1) between a free cell
  // and a square, as pieces_ boundary edges: the nodes in between belong to
  // this edge alone (the square keeps its four corners and hanging nodes on
  // its side, which particles do not mind: cells need only tile the plate).
  void add_interface_edge(long i0, long j0, long i1, long j1) {
    const std::uint32_t a = lattice_vertex(i0, j0), b = lattice_vertex(i1, j1);
    const Vec2 pa = out_.regions.vertices[a], pb = out_.regions.vertices[b];
    std::uint32_t from = a;
    for (int s = 1; s <= pieces_; ++s) {
      const std::uint32_t to = s == pieces_ ? b : new_vertex(pa + (static_cast<double>(s) / pieces_) * (pb - pa));
      add_edge({from, to}, -1);
      from = to;
    }
  }

  // Lattice edges between a free cell and a square, the free cell on the left.
  void add_interface_edges() {
    for (long j = 0; j < l_.ny; ++j)
      for (long i = 0; i < l_.nx; ++i) {
        const CellKind here = cells_.at(i, j);
        if (i + 1 < l_.nx) {
          const CellKind right = cells_.at(i + 1, j);
          const bool covered = covered_.count(2 * lattice_key(i + 1, j, l_) + 1) > 0;
          if (here == CellKind::free && right == CellKind::square && !covered)
            add_interface_edge(i + 1, j, i + 1, j + 1);
          if (here == CellKind::square && right == CellKind::free && !covered)
            add_interface_edge(i + 1, j + 1, i + 1, j);
        }
        if (j + 1 < l_.ny) {
          const CellKind above = cells_.at(i, j + 1);
          const bool covered = covered_.count(2 * lattice_key(i, j + 1, l_)) > 0;
          if (here == CellKind::free && above == CellKind::square && !covered)
            add_interface_edge(i + 1, j + 1, i, j + 1);
          if (here == CellKind::square && above == CellKind::free && !covered)
            add_interface_edge(i, j + 1, i + 1, j + 1);
        }
      }
  }

  Built trace() {
    const auto& v = out_.regions.vertices;
    std::vector<std::vector<std::uint32_t>> leaving(v.size());
    for (std::uint32_t e = 0; e < edges_.size(); ++e) leaving[edges_[e].from].push_back(e);
    std::vector<bool> used(edges_.size(), false);
    std::vector<std::vector<std::uint32_t>> loops;
    for (std::uint32_t first = 0; first < edges_.size(); ++first) {
      if (used[first]) continue;
      std::vector<std::uint32_t> loop;
      std::uint32_t e = first;
      while (true) {
        used[e] = true;
        loop.push_back(e);
        const auto& edge = edges_[e];
        // The sharpest left turn keeps to the region on the left, so that two
        // regions touching at a corner are traced apart. The loop closes when
        // that turn leads back to its first edge.
        const Vec2 in = v[edge.to] - v[edge.from];
        std::uint32_t next = UINT32_MAX;
        double best = -INFINITY;
        for (auto f : leaving[edge.to]) {
          if (used[f] && f != first) continue;
          const Vec2 out = v[edges_[f].to] - v[edges_[f].from];
          double turn = std::atan2(cross(in, out), dot(in, out));
          if (edges_[f].to == edge.from) turn = -M_PI;  // straight back: only if nothing else
          if (turn > best) best = turn, next = f;
        }
        if (next == UINT32_MAX)
          throw Error(g_.file + ": internal error: a free region's boundary does not close near (" +
                      std::to_string(v[edge.to].x * 1e3) + ", " + std::to_string(v[edge.to].y * 1e3) + ") mm");
        if (next == first) break;
        e = next;
      }
      loops.push_back(std::move(loop));
    }
    // Counter-clockwise loops bound regions; clockwise ones are holes in them.
    struct LoopInfo {
      double area;
      double xmin, ymin, xmax, ymax;
    };
    std::vector<LoopInfo> info;
    for (const auto& loop : loops) {
      LoopInfo li{0, INFINITY, INFINITY, -INFINITY, -INFINITY};
      for (auto e : loop) {
        const Vec2 a = v[edges_[e].from], b = v[edges_[e].to];
        li.area += 0.5 * cross(a, b);
        li.xmin = std::min(li.xmin, a.x), li.xmax = std::max(li.xmax, a.x);
        li.ymin = std::min(li.ymin, a.y), li.ymax = std::max(li.ymax, a.y);
      }
      info.push_back(li);
    }
    Built built;
    built.regions.vertices = v;
    std::vector<long> region_of_loop(loops.size(), -1);
    for (std::size_t k = 0; k < loops.size(); ++k)
      if (info[k].area > 0) {
        region_of_loop[k] = static_cast<long>(built.regions.regions.size());
        built.regions.regions.push_back({});
      }
    const auto polygon_of = [&](std::size_t k) {
      std::vector<Vec2> p;
      for (auto e : loops[k]) p.push_back(v[edges_[e].from]);
      return p;
    };
    for (std::size_t k = 0; k < loops.size(); ++k) {
      if (info[k].area > 0) continue;
      const auto& e0 = edges_[loops[k].front()];
      const Vec2 probe = 0.5 * (v[e0.from] + v[e0.to]);
      long owner = -1;
      double owner_area = INFINITY;
      for (std::size_t o = 0; o < loops.size(); ++o) {
        if (info[o].area <= 0 || info[o].area >= owner_area || probe.x < info[o].xmin || probe.x > info[o].xmax ||
            probe.y < info[o].ymin || probe.y > info[o].ymax)
          continue;
        if (point_in_polygon(probe, polygon_of(o))) owner = static_cast<long>(o), owner_area = info[o].area;
      }
      if (owner < 0)
        throw Error(g_.file + ": internal error: an inner boundary of the free region lies in no region near (" +
                    std::to_string(probe.x * 1e3) + ", " + std::to_string(probe.y * 1e3) + ") mm");
      region_of_loop[k] = region_of_loop[static_cast<std::size_t>(owner)];
    }
    const std::size_t count = built.regions.regions.size();
    built.edge_count.assign(count, 0);
    built.curves.assign(count, {});
    built.runs.assign(count, {});
    std::vector<std::set<long>> items_seen(count);
    // Outer loop first in each region.
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t k = 0; k < loops.size(); ++k) {
        if ((pass == 0) != (info[k].area > 0)) continue;
        const auto r = static_cast<std::size_t>(region_of_loop[k]);
        std::vector<RegionEdge> chain;
        for (auto e : loops[k]) {
          chain.push_back(edges_[e]);
          const long item = edge_item_[e];
          if (item >= 0 && items_seen[r].insert(item).second) {
            const auto& it = items_[static_cast<std::size_t>(item)];
            (it.is_curve ? built.curves : built.runs)[r].push_back({it.length, it.id});
          }
        }
        built.edge_count[r] += chain.size();
        built.regions.regions[r].loops.push_back(std::move(chain));
      }
    return built;
  }
};

}  // namespace

FreeRegions free_regions(const PlateGeometry& g, const CellMap& cells, int edges_per_lattice_edge) {
  RegionBuilder builder(g, cells, edges_per_lattice_edge);
  auto built = builder.build();
  // An odd edge count: one segment more on the region's longest straight run
  // (its nodes need not be lattice nodes), else on its longest curve.
  bool changed = false;
  for (std::size_t r = 0; r < built.regions.regions.size(); ++r) {
    if (built.edge_count[r] % 2 == 0) continue;
    const auto longest = [](const auto& items) {
      return std::max_element(items.begin(), items.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    };
    if (!built.runs[r].empty()) {
      builder.one_more_run.insert(longest(built.runs[r])->second);
      changed = true;
    } else if (!built.curves[r].empty()) {
      builder.one_more_curve.insert(longest(built.curves[r])->second);
      changed = true;
    }
  }
  if (changed) built = builder.build();
  return std::move(built.regions);
}

}  // namespace pd
