#include "loading_layer.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"
#include "lattice.hpp"
#include "units.hpp"

namespace pd {

namespace {

// Side k of the bounding box (the order of loading_layer_edges) and its outward normal.
constexpr int normal_x[4] = {-1, 1, 0, 0};
constexpr int normal_y[4] = {0, 0, -1, 1};

int side_index(const std::string& edge) {
  const auto it = std::find(loading_layer_edges.begin(), loading_layer_edges.end(), edge);
  return it == loading_layer_edges.end() ? -1 : static_cast<int>(it - loading_layer_edges.begin());
}

double side_tolerance(const PlateGeometry& g) { return 1e-9 * std::max(g.xmax - g.xmin, g.ymax - g.ymin); }

std::vector<bool> sides_of(const std::vector<std::string>& edges) {
  std::vector<bool> loaded(4, false);
  for (const auto& e : edges) {
    const int s = side_index(e);
    if (s < 0) throw Error("loading layer: unknown edge '" + e + "'");
    loaded[static_cast<std::size_t>(s)] = true;
  }
  return loaded;
}

}  // namespace

std::string loading_layer_set_name(const std::string& edge) { return "loading_layer_" + edge; }

std::vector<std::string> parse_loading_layer_edges(const std::string& text, const std::string& option) {
  std::vector<std::string> edges;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const auto end = std::min(text.find(',', begin), text.size());
    const auto edge = text.substr(begin, end - begin);
    if (side_index(edge) < 0)
      throw Error(option + ": '" + edge + "' in '" + text + "' is not an edge (use left, right, bottom, top, "
                  "comma-separated)");
    if (std::find(edges.begin(), edges.end(), edge) != edges.end())
      throw Error(option + ": the edge '" + edge + "' is given twice in '" + text + "'");
    edges.push_back(edge);
    begin = end + 1;
  }
  return edges;
}

long loading_layer_rows(double depth, double spacing) {
  // A depth that is a whole number of spacings up to round-off takes that many rows.
  return static_cast<long>(std::ceil(depth / spacing - 1e-9));
}

void append_loading_layers(ParticleSet& p, const PlateGeometry& g, const std::vector<std::string>& edges,
                           double depth, const std::string& option) {
  const double dx = p.spacing;
  if (!(depth > 0) || !std::isfinite(depth)) throw Error(option + ": the layer depth must be positive");
  const long rows = loading_layer_rows(depth, dx);
  // The plate's lattice: the particle set's box, which runs past a side
  // without a straight curve (free_region.hpp, plate_lattice).
  const double x0 = p.xmin, y0 = p.ymin;
  const long nx = std::lround((p.xmax - x0) / dx), ny = std::lround((p.ymax - y0) / dx);
  const double tol = side_tolerance(g);
  // Lattice index of a coordinate that must lie on a lattice line.
  const auto lattice_line = [&](double v, double origin, Vec2 at, const std::string& edge) {
    const double k = (v - origin) / dx;
    if (std::fabs(k - std::round(k)) * dx > tol)
      throw Error(option + " " + edge + ": " + g.file + " has a straight curve on the " + edge + " side ending at (" +
                  format_mm(at.x) + ", " + format_mm(at.y) + "), off the lattice lines of spacing " + format_mm(dx) +
                  ": its layer would not be whole squares");
    return std::lround(k);
  };
  for (const auto& edge : edges) {
    const int side = side_index(edge);
    if (side < 0) throw Error(option + ": unknown edge '" + edge + "'");
    bool any = false;
    for (const auto& c : g.outer.curves) {
      if (bounding_box_side(c, g) != side) continue;
      any = true;
      const bool vertical = side < 2;
      const double origin = vertical ? y0 : x0;
      long a = lattice_line(vertical ? c.start.y : c.start.x, origin, c.start, edge);
      long b = lattice_line(vertical ? c.end.y : c.end.x, origin, c.end, edge);
      if (a > b) std::swap(a, b);
      long i0 = a, i1 = b, j0 = a, j1 = b;  // along the side
      switch (side) {
        case 0: i0 = -rows, i1 = 0; break;
        case 1: i0 = nx, i1 = nx + rows; break;
        case 2: j0 = -rows, j1 = 0; break;
        default: j0 = ny, j1 = ny + rows; break;
      }
      append_lattice_squares(p, x0, y0, dx, i0, i1, j0, j1, [](long, long) { return true; },
                             Region::uniform_square);
    }
    if (!any)
      throw Error(option + " " + edge + ": " + g.file + " has no straight outer curve on the " + edge +
                  " side of its bounding box");
  }
  // The file's bounding box spans every particle; whole rows keep the lattice the same.
  const auto loaded = sides_of(edges);
  const double d = rows * dx;
  if (loaded[0]) p.xmin -= d;
  if (loaded[1]) p.xmax += d;
  if (loaded[2]) p.ymin -= d;
  if (loaded[3]) p.ymax += d;
}

MaterialBoundary material_boundary_with_layers(const PlateGeometry& g, double spacing, double horizon,
                                               const std::vector<std::string>& edges, double depth) {
  const auto loaded = sides_of(edges);
  const double d = loading_layer_rows(depth, spacing) * spacing;
  const auto& curves = g.outer.curves;
  const std::size_t n = curves.size();
  const auto layered = [&](std::size_t k) {
    const int s = bounding_box_side(curves[k], g);
    return s >= 0 && loaded[static_cast<std::size_t>(s)] ? s : -1;
  };
  // The outer loop with each run of layered curves on one side replaced by
  // start -> start + d n -> end + d n (n the outward normal); the end is the
  // next curve's start. Consecutive curves of one side share one detour, so
  // that no slit separates their layers.
  std::vector<Vec2> outer;
  for (std::size_t k = 0; k < n; ++k) {
    const auto& c = curves[k];
    const int s = layered(k);
    if (s < 0) {
      outer.insert(outer.end(), c.polyline.begin(), c.polyline.end() - 1);
      continue;
    }
    const Vec2 off{d * normal_x[s], d * normal_y[s]};
    if (layered((k + n - 1) % n) != s) outer.push_back(c.start), outer.push_back({c.start.x + off.x, c.start.y + off.y});
    if (layered((k + 1) % n) != s) outer.push_back({c.end.x + off.x, c.end.y + off.y});
  }
  std::vector<std::vector<Vec2>> loops{outer};
  for (const auto& hole : g.holes) loops.push_back(hole.polyline());
  return MaterialBoundary(loops, 1e-9 * spacing, horizon);
}

bool in_loading_layer(const ParticleSet& p, const PlateGeometry& g, std::size_t i) {
  return p.x[i] < g.xmin || p.x[i] > g.xmax || p.y[i] < g.ymin || p.y[i] > g.ymax;
}

void add_loading_layer_sets(ParticleSet& p, const PlateGeometry& g, const std::vector<std::string>& edges) {
  for (auto& set : p.sets) {
    auto& v = set.particles;
    v.erase(std::remove_if(v.begin(), v.end(), [&](std::uint32_t i) { return in_loading_layer(p, g, i); }), v.end());
  }
  for (const auto& edge : edges) {
    const auto name = loading_layer_set_name(edge);
    if (p.find_set(name))
      throw Error(g.file + ": a physical curve group is named '" + name + "', the name of the loading layer's set");
    const int side = side_index(edge);
    BoundarySet set{name, {}};
    // The layers lie beyond different sides and leave the corners empty, so the side decides.
    for (std::size_t i = 0; i < p.size(); ++i) {
      const bool beyond = side == 0 ? p.x[i] < g.xmin : side == 1 ? p.x[i] > g.xmax : side == 2 ? p.y[i] < g.ymin
                                                                                                 : p.y[i] > g.ymax;
      if (beyond) set.particles.push_back(static_cast<std::uint32_t>(i));
    }
    p.sets.push_back(std::move(set));
  }
}

}  // namespace pd
