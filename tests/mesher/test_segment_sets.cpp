// The particles near segments (boundary sets), against the rule computed
// directly: each particle against every segment, in order, its nearest point
// the first of the least distance (std::hypot), kept if within the distance
// and, with a material boundary, if the line to that point stays in the
// material. The segments: a hole's polyline of a thousand chords far shorter
// than the distance (searched in runs), long edges (searched in pieces), an
// edge notch's faces and the side beside it, whose particles across the
// notch the material leaves out; lattice particles tie exactly at shared
// vertices.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "geometry.hpp"
#include "material_boundary.hpp"
#include "neighbor_search.hpp"
#include "particle_file.hpp"
#include "segment_sets.hpp"

namespace {

struct Segments {
  std::vector<double> ax, ay, bx, by;
  void add(pd::Vec2 a, pd::Vec2 b) { ax.push_back(a.x), ay.push_back(a.y), bx.push_back(b.x), by.push_back(b.y); }
  void add_loop(const std::vector<pd::Vec2>& loop) {
    for (std::size_t k = 0; k < loop.size(); ++k) add(loop[k], loop[(k + 1) % loop.size()]);
  }
};

std::vector<std::uint32_t> near_by_the_rule(const pd::ParticleSet& p, const Segments& s, double distance,
                                            const pd::MaterialBoundary& material) {
  std::vector<std::uint32_t> near;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const pd::Vec2 q{p.x[i], p.y[i]};
    bool found = false;
    double nearest = 0;
    pd::Vec2 nearest_point;
    for (std::size_t k = 0; k < s.ax.size(); ++k) {
      const pd::Vec2 a{s.ax[k], s.ay[k]}, d = pd::Vec2{s.bx[k], s.by[k]} - a;
      const double t = dot(d, d) > 0 ? std::clamp(dot(q - a, d) / dot(d, d), 0.0, 1.0) : 0.0;
      const pd::Vec2 foot = a + t * d;
      const double gap = std::hypot(q.x - foot.x, q.y - foot.y);
      if (gap <= distance && (!found || gap < nearest)) found = true, nearest = gap, nearest_point = foot;
    }
    if (found && !material.segment_leaves_material(q, nearest_point)) near.push_back(i);
  }
  return near;
}

}  // namespace

TEST_CASE("the particles near a hole's many chords, long edges and a notch's faces follow the rule",
          "[mesher][sets]") {
  const double dx = 1e-3, side = 20 * dx;
  // A 20 dx square with a notch from the right edge (0.2 dx wide, 6 dx deep)
  // and a hole of radius 0.3 dx in 1200 chords (clockwise: material on the left).
  const double notch_y0 = 11.9 * dx, notch_y1 = 12.1 * dx, notch_tip = 14 * dx;
  const std::vector<pd::Vec2> outer = {{0, 0},         {side, 0},          {side, notch_y0}, {notch_tip, notch_y0},
                                       {notch_tip, notch_y1}, {side, notch_y1}, {side, side},     {0, side}};
  const pd::Vec2 centre{7.5 * dx, 8.5 * dx};
  const double radius = 0.3 * dx;
  std::vector<pd::Vec2> hole;
  for (int k = 0; k < 1200; ++k) {
    const double angle = -2 * M_PI * k / 1200;
    hole.push_back({centre.x + radius * std::cos(angle), centre.y + radius * std::sin(angle)});
  }
  const pd::MaterialBoundary material({outer, hole}, 1e-9 * dx, 3 * dx);

  // The lattice's centres and random points, in the material.
  pd::ParticleSet p;
  const auto in_material = [&](pd::Vec2 q) {
    const bool in_notch = q.x >= notch_tip && q.y >= notch_y0 && q.y <= notch_y1;
    return !in_notch && std::hypot(q.x - centre.x, q.y - centre.y) > radius;
  };
  const auto add_particle = [&](pd::Vec2 q) {
    if (in_material(q)) p.x.push_back(q.x), p.y.push_back(q.y);
  };
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) add_particle({(i + 0.5) * 0.5 * dx, (j + 0.5) * 0.5 * dx});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(0, side);
  for (int k = 0; k < 3000; ++k) add_particle({coordinate(rng), coordinate(rng)});
  const pd::NeighborSearch search(p.x, p.y);

  Segments hole_set, bottom, notch, right_above_notch, everything;
  hole_set.add_loop(hole);
  bottom.add({0, 0}, {side, 0});
  for (std::size_t k = 2; k < 5; ++k) notch.add(outer[k], outer[k + 1]);
  right_above_notch.add(outer[5], outer[6]);
  everything.add_loop(outer);
  everything.add_loop(hole);
  for (const double distance : {3 * dx, 0.75 * dx, 0.5 * dx}) {
    INFO("distance " << distance);
    for (const Segments* s : {&hole_set, &bottom, &notch, &right_above_notch, &everything}) {
      const auto near = pd::particles_near_segments(p, search, s->ax, s->ay, s->bx, s->by, distance, &material);
      CHECK(near == near_by_the_rule(p, *s, distance, material));
      CHECK_FALSE(near.empty());
    }
  }
  // The side above the notch reaches across it to particles below, which
  // see its end through the notch: the material leaves them out.
  const Segments& s = right_above_notch;
  const auto across = pd::particles_near_segments(p, search, s.ax, s.ay, s.bx, s.by, 3 * dx, nullptr);
  const auto seen = pd::particles_near_segments(p, search, s.ax, s.ay, s.bx, s.by, 3 * dx, &material);
  CHECK(across.size() > seen.size() + 10);
}
