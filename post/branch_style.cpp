#include "branch_style.hpp"

#include <cmath>
#include <vector>

namespace pd::post {

BranchStyle branch_style(int branch) {
  // Distinct hues that stand out on the dark and the yellow end of the damage
  // colour scale and on white; none lighter than (250, 150, 190).
  static const Color palette[branch_colour_count] = {
      {230, 25, 75},  {0, 200, 255},   {255, 140, 0}, {255, 60, 255}, {60, 180, 75},
      {160, 120, 255}, {250, 150, 190}, {170, 110, 40}, {0, 150, 150}, {128, 128, 0}};
  static const Marker markers[marker_count] = {Marker::circle, Marker::square, Marker::triangle, Marker::diamond,
                                               Marker::inverted_triangle};
  const auto b = static_cast<unsigned>(branch < 0 ? -branch : branch);
  return {palette[b % branch_colour_count], markers[(b / branch_colour_count) % marker_count]};
}

void draw_marker(Canvas& c, double x, double y, Marker marker, double r, Color color, bool filled) {
  if (marker == Marker::circle) {
    if (filled) c.filled_circle(x, y, r, color);
    else c.circle(x, y, r - 0.5, color, 2);
    return;
  }
  std::vector<double> px, py;
  switch (marker) {
    case Marker::square:
      r *= 0.85;  // the same visual weight as the circle
      px = {x - r, x + r, x + r, x - r}, py = {y - r, y - r, y + r, y + r};
      break;
    case Marker::triangle:
      px = {x, x + r, x - r}, py = {y - r, y + 0.8 * r, y + 0.8 * r};
      break;
    case Marker::inverted_triangle:
      px = {x, x + r, x - r}, py = {y + r, y - 0.8 * r, y - 0.8 * r};
      break;
    default:  // diamond
      px = {x, x + r, x, x - r}, py = {y - r, y, y + r, y};
      break;
  }
  if (filled) {
    c.fill_polygon(px, py, color);
    return;
  }
  for (std::size_t k = 0; k < px.size(); ++k)
    c.line(px[k], py[k], px[(k + 1) % px.size()], py[(k + 1) % px.size()], color, 2);
}

}  // namespace pd::post
