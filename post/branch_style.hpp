#pragma once
// How a crack branch is drawn on every picture: a colour and a marker shape.
// Colours cycle every 10 branches and markers every 50, so branches 0 to 49
// each have their own style, and consecutive branches (the children of one
// branching event, often mirror images) always differ in colour. No colour
// is white or near it: every style shows on the white legend ground.
#include "canvas.hpp"

namespace pd::post {

enum class Marker { circle, square, triangle, diamond, inverted_triangle };

inline constexpr int branch_colour_count = 10;
inline constexpr int marker_count = 5;

struct BranchStyle {
  Color color;
  Marker marker = Marker::circle;
};
inline bool operator==(const BranchStyle& a, const BranchStyle& b) { return a.color == b.color && a.marker == b.marker; }

BranchStyle branch_style(int branch);
inline Color branch_color(int branch) { return branch_style(branch).color; }

// A marker centred at (x, y) reaching `radius` pixels from the centre: filled,
// or outlined two pixels thick.
void draw_marker(Canvas& canvas, double x, double y, Marker marker, double radius, Color color, bool filled);

}  // namespace pd::post
