#pragma once
// Plane geometry shared by the mesher, the solver and the tests.
// All functions are exact up to floating-point round-off.
#include <cstddef>
#include <vector>

namespace pd {

struct Vec2 {
  double x = 0, y = 0;
};
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// Signed area of a polygon (shoelace; positive when counter-clockwise; 0 for
// fewer than 3 vertices).
double polygon_signed_area(const double* vx, const double* vy, std::size_t n);

// Centroid of a polygon's area (shoelace first moments). Not the vertex average.
Vec2 polygon_centroid(const double* vx, const double* vy, std::size_t n);

// Exact area of (polygon ∩ disk(center, radius)) for any simple polygon,
// either orientation (the result is always >= 0). Sum over the edges of the
// signed areas of triangle(center, edge) ∩ disk: each piece is a triangle
// where the edge is inside the disk and a circular sector where it is outside.
// (Used for the analytical partial-volume factors, docs/theory.md Sec. 2.)
double polygon_disk_intersection_area(const double* vx, const double* vy, std::size_t n,
                                      Vec2 center, double radius);

// Largest distance from `from` to any vertex of the polygon.
double polygon_max_vertex_distance(const double* vx, const double* vy, std::size_t n, Vec2 from);

// std::hypot(dx, dy) <= limit, the same answer bit for bit, mostly without
// hypot: squares decide unless they are within 1e-12 (relative) of each
// other, far above their round-off, and hypot decides that band.
bool hypot_at_most(double dx, double dy, double limit);

// polygon_max_vertex_distance(vx, vy, n, from) <= limit, the same answer, by
// hypot_at_most's squares.
bool polygon_within_distance(const double* vx, const double* vy, std::size_t n, Vec2 from, double limit);

// std::hypot(u.x, u.y) < std::hypot(v.x, v.y), the same answer bit for bit,
// mostly without hypot: as hypot_at_most, the squares decide outside a band
// of 1e-12 (relative) about each other.
bool hypot_less(Vec2 u, Vec2 v);

// Distance from p to the segment [a, b].
double point_segment_distance(Vec2 p, Vec2 a, Vec2 b);

// True if the closed segments [a, b] and [c, d] share at least one point.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

// True if the open segments cross at a single interior point of both
// (touching at an end point or collinear overlap does not count).
bool segments_cross_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

// Point in a closed polygon by the winding number; points on the boundary
// may go either way.
bool point_in_polygon(Vec2 p, const double* vx, const double* vy, std::size_t n);

// Same for a polygon given as a vector of vertices.
bool point_in_polygon(Vec2 p, const std::vector<Vec2>& polygon);

// HHB partial-volume factor [004:(12)-(14)] for a bond of length `distance`,
// horizon `horizon` and cell size `cell_size` (dx for squares, sqrt(V_j) otherwise).
double hhb_factor(double distance, double horizon, double cell_size);

}  // namespace pd
