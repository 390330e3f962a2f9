#include "boundary_sets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "neighbor_search.hpp"
#include "segment_sets.hpp"

namespace pd {

namespace {

struct Segments {
  std::vector<double> ax, ay, bx, by;
  void add(Vec2 a, Vec2 b) { ax.push_back(a.x), ay.push_back(a.y), bx.push_back(b.x), by.push_back(b.y); }
  void add_polyline(const std::vector<Vec2>& p) {
    for (std::size_t k = 0; k + 1 < p.size(); ++k) add(p[k], p[k + 1]);
  }
};

}  // namespace

std::vector<std::string> add_boundary_sets(ParticleSet& p, const PlateGeometry& g, double distance) {
  std::vector<BoundarySet> sets;
  std::vector<std::string> warnings;
  const NeighborSearch search(p.x, p.y);
  // Near a curve means seen from it through the material, not across a notch.
  const auto material = material_boundary(g, p.spacing, distance);
  const auto near = [&](const Segments& s) {
    return particles_near_segments(p, search, s.ax, s.ay, s.bx, s.by, distance, &material);
  };
  const auto add_set = [&](const std::string& name, const Segments& s) { sets.push_back({name, near(s)}); };
  // Sides of the bounding box: straight curves whose ends both lie on it.
  const char* side_names[] = {"left", "right", "bottom", "top"};
  for (int side = 0; side < 4; ++side) {
    Segments s;
    for (const auto& c : g.outer.curves)
      if (bounding_box_side(c, g) == side) s.add(c.start, c.end);
    if (!s.ax.empty()) add_set(side_names[side], s);
  }
  for (const auto& hole : g.holes) {
    Segments s;
    for (const auto& c : hole.curves) s.add_polyline(c.polyline);
    add_set(hole.name, s);
  }
  for (const auto& named : g.physical_curves) {
    Segments s;
    for (std::size_t k = 0; k < named.a.size(); ++k) s.add(named.a[k], named.b[k]);
    BoundarySet set{named.name, near(s)};
    // Curves beside the plate (or in another unit) give an empty set, which a
    // scene can only be refused for ("contains no particle"), without the cause.
    if (set.particles.empty() && !named.a.empty()) {
      double x0 = named.a[0].x, x1 = x0, y0 = named.a[0].y, y1 = y0;
      for (const auto* ends : {&named.a, &named.b})
        for (const auto& v : *ends)
          x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
      char text[400];
      std::snprintf(text, sizeof text,
                    "Physical Curve(\"%s\") holds no particle: its curves (x %.4g to %.4g mm, y %.4g to %.4g mm) "
                    "lie farther than %.4g mm (the horizon) from every particle that sees them through the "
                    "material; a scene that loads the set '%s' is refused",
                    set.name.c_str(), x0 * 1e3, x1 * 1e3, y0 * 1e3, y1 * 1e3, distance * 1e3, set.name.c_str());
      warnings.push_back(text);
    }
    auto same = std::find_if(sets.begin(), sets.end(), [&](const BoundarySet& t) { return t.name == set.name; });
    if (same != sets.end()) {
      // A group named after an automatic set is meant to be that part of the
      // boundary, or to redraw it: one that shares no particle with it is
      // most likely a name copied from another group.
      std::vector<std::uint32_t> common;
      std::set_intersection(same->particles.begin(), same->particles.end(), set.particles.begin(),
                            set.particles.end(), std::back_inserter(common));
      if (common.empty() && !set.particles.empty() && !same->particles.empty()) {
        double x0 = p.x[set.particles[0]], x1 = x0, y0 = p.y[set.particles[0]], y1 = y0;
        for (auto i : set.particles)
          x0 = std::min(x0, p.x[i]), x1 = std::max(x1, p.x[i]), y0 = std::min(y0, p.y[i]), y1 = std::max(y1, p.y[i]);
        char text[400];
        std::snprintf(text, sizeof text,
                      "Physical Curve(\"%s\") replaces the automatic set '%s' (%zu particles) and has no particle "
                      "in common with it: its %zu particles lie in x %.4g to %.4g mm, y %.4g to %.4g mm; a group "
                      "named after an automatic set is taken as given (another name keeps both)",
                      set.name.c_str(), set.name.c_str(), same->particles.size(), set.particles.size(), x0 * 1e3,
                      x1 * 1e3, y0 * 1e3, y1 * 1e3);
        warnings.push_back(text);
      }
      *same = std::move(set);
    } else {
      sets.push_back(std::move(set));
    }
  }
  p.sets = std::move(sets);
  return warnings;
}

}  // namespace pd
