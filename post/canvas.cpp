#include "canvas.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>

#include <algorithm>
#include <cmath>

#include "atomic_file.hpp"
#include "error.hpp"
#include "font.hpp"
#include "quiet_vtk.hpp"

namespace pd::post {

Canvas::Canvas(int width, int height, Color background)
    : width_(width), height_(height), rgb_(static_cast<std::size_t>(width) * height * 3) {
  fill_rect(0, 0, width, height, background);
}

Color Canvas::pixel(int x, int y) const {
  const std::size_t k = (static_cast<std::size_t>(y) * width_ + x) * 3;
  return {rgb_[k], rgb_[k + 1], rgb_[k + 2]};
}

void Canvas::set_pixel(int x, int y, Color c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const std::size_t k = (static_cast<std::size_t>(y) * width_ + x) * 3;
  rgb_[k] = c.r, rgb_[k + 1] = c.g, rgb_[k + 2] = c.b;
}

void Canvas::fill_polygon(const std::vector<double>& px, const std::vector<double>& py, Color c) {
  const std::size_t n = px.size();
  if (n < 3) return;
  double top = py[0], bottom = py[0];
  for (double y : py) top = std::min(top, y), bottom = std::max(bottom, y);
  // Coordinates clamped to just beyond the canvas before any cast to int:
  // a cell of a window far smaller than itself lies 1e15 px and more off it.
  const auto within = [](double v, int size) { return std::clamp(v, -2.0, size + 2.0); };
  const int row0 = std::max(0, static_cast<int>(std::ceil(within(top, height_) - 0.5)));
  const int row1 = std::min(height_ - 1, static_cast<int>(std::floor(within(bottom, height_) - 0.5)));
  std::vector<double> crossings;
  for (int row = row0; row <= row1; ++row) {
    const double y = row + 0.5;  // pixel centre
    crossings.clear();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++)
      if ((py[i] <= y) != (py[j] <= y)) crossings.push_back(px[j] + (y - py[j]) / (py[i] - py[j]) * (px[i] - px[j]));
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
      const int col0 = static_cast<int>(std::ceil(within(crossings[k], width_) - 0.5));
      const int col1 = static_cast<int>(std::floor(within(crossings[k + 1], width_) - 0.5));
      if (col1 >= col0) fill_rect(col0, row, col1 + 1, row + 1, c);
    }
  }
}

void Canvas::fill_pinholes(int x0, int y0, int x1, int y1, std::size_t largest, Color background) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, width_), y1 = std::min(y1, height_);
  const int w = x1 - x0, h = y1 - y0;
  if (w <= 0 || h <= 0) return;
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(w) * h, 0);
  std::vector<std::pair<int, int>> patch, stack;
  for (int sy = y0; sy < y1; ++sy)
    for (int sx = x0; sx < x1; ++sx) {
      if (seen[static_cast<std::size_t>(sy - y0) * w + (sx - x0)] || !(pixel(sx, sy) == background)) continue;
      // The 4-connected background patch of (sx, sy).
      patch.clear();
      stack.assign(1, {sx, sy});
      seen[static_cast<std::size_t>(sy - y0) * w + (sx - x0)] = 1;
      bool touches_edge = false;
      while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        patch.push_back({x, y});
        touches_edge |= x == x0 || y == y0 || x == x1 - 1 || y == y1 - 1;
        for (const auto& [nx, ny] : {std::pair{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}}) {
          if (nx < x0 || ny < y0 || nx >= x1 || ny >= y1) continue;
          auto& flag = seen[static_cast<std::size_t>(ny - y0) * w + (nx - x0)];
          if (!flag && pixel(nx, ny) == background) flag = 1, stack.push_back({nx, ny});
        }
      }
      if (touches_edge || patch.size() > largest) continue;
      // Each pixel from its covered neighbours, from the patch's rim inwards
      // (a pixel inside the patch takes the rim's colours once they are set).
      for (std::size_t left = patch.size(), before = 0; left > 0 && left != before;) {
        before = left;
        std::vector<std::pair<std::size_t, Color>> fill;
        for (std::size_t k = 0; k < patch.size(); ++k) {
          if (!(pixel(patch[k].first, patch[k].second) == background)) continue;
          int covered = 0, r = 0, g = 0, b = 0;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const Color n = pixel(patch[k].first + dx, patch[k].second + dy);
              if (!(n == background)) ++covered, r += n.r, g += n.g, b += n.b;
            }
          if (covered > 0)
            fill.push_back({k, Color{static_cast<std::uint8_t>(r / covered), static_cast<std::uint8_t>(g / covered),
                                     static_cast<std::uint8_t>(b / covered)}});
        }
        for (const auto& [k, c] : fill) set_pixel(patch[k].first, patch[k].second, c);
        left -= fill.size();
      }
    }
}

void Canvas::fill_rect(int x0, int y0, int x1, int y1, Color c) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, width_), y1 = std::min(y1, height_);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) set_pixel(x, y, c);
}

void Canvas::line(double x0, double y0, double x1, double y1, Color c, int thickness) {
  // Only the part on the canvas (with a margin of the thickness) is
  // stepped along (Liang-Barsky): an end 1e15 px away made a step count no
  // int holds, and as many steps.
  const double margin = thickness + 1.0;
  double t0 = 0, t1 = 1;
  const double dx = x1 - x0, dy = y1 - y0;
  for (const auto& [p, q] : {std::pair{-dx, x0 + margin}, {dx, width_ + margin - x0}, {-dy, y0 + margin},
                             {dy, height_ + margin - y0}}) {
    if (p == 0) {
      if (q < 0) return;  // parallel to this edge and beyond it
      continue;
    }
    const double r = q / p;
    if (p < 0) t0 = std::max(t0, r);
    else t1 = std::min(t1, r);
  }
  if (!(t0 <= t1)) return;
  const int lo = -(thickness - 1) / 2, hi = thickness / 2;
  const auto dot = [&](double px, double py) {
    const int x = static_cast<int>(std::lround(px)), y = static_cast<int>(std::lround(py));
    for (int oy = lo; oy <= hi; ++oy)
      for (int ox = lo; ox <= hi; ++ox) set_pixel(x + ox, y + oy, c);
  };
  // The whole line's samples, two per pixel of its length, those of the
  // clipped part only: its pixels are those of the same line on a canvas
  // that holds it whole (before 7 December 2026 the clipped part was
  // sampled afresh, and landed up to a pixel away). A sample outside
  // [t0, t1] lies more than the margin off the canvas and sets no pixel;
  // one more on either side keeps t0 and t1's round-off from dropping one.
  const double steps = std::max(1.0, std::ceil(std::hypot(dx, dy) * 2));
  // Up to 2^52 steps a sample's index is exact in a double; a longer line
  // (an end 1e15 px away) has no whole drawing to match: its clipped part
  // is sampled as a line of its own.
  if (steps <= 4503599627370496.0) {
    const auto first = static_cast<long long>(std::max(0.0, std::ceil(t0 * steps) - 1));
    const auto last = static_cast<long long>(std::min(steps, std::floor(t1 * steps) + 1));
    for (long long s = first; s <= last; ++s) {
      const double f = static_cast<double>(s) / steps;
      dot(x0 + f * dx, y0 + f * dy);
    }
    return;
  }
  const double ax = x0 + t0 * dx, ay = y0 + t0 * dy, bx = x0 + t1 * dx, by = y0 + t1 * dy;
  const int part_steps = std::max(1, static_cast<int>(std::ceil(std::hypot(bx - ax, by - ay) * 2)));
  for (int s = 0; s <= part_steps; ++s) {
    const double f = static_cast<double>(s) / part_steps;
    dot(ax + f * (bx - ax), ay + f * (by - ay));
  }
}

void Canvas::dashed_line(double x0, double y0, double x1, double y1, Color c, int dash) {
  const double length = std::hypot(x1 - x0, y1 - y0);
  for (double s = 0; s < length; s += 2 * dash) {
    const double e = std::min(s + dash, length);
    line(x0 + (x1 - x0) * s / length, y0 + (y1 - y0) * s / length, x0 + (x1 - x0) * e / length,
         y0 + (y1 - y0) * e / length, c);
  }
}

void Canvas::circle(double cx, double cy, double radius, Color c, int thickness) {
  const int steps = std::max(16, static_cast<int>(radius * 8));
  for (int s = 0; s < steps; ++s) {
    const double a0 = 2 * M_PI * s / steps, a1 = 2 * M_PI * (s + 1) / steps;
    line(cx + radius * std::cos(a0), cy + radius * std::sin(a0), cx + radius * std::cos(a1),
         cy + radius * std::sin(a1), c, thickness);
  }
}

void Canvas::filled_circle(double cx, double cy, double radius, Color c) {
  for (int y = static_cast<int>(cy - radius); y <= static_cast<int>(cy + radius) + 1; ++y)
    for (int x = static_cast<int>(cx - radius); x <= static_cast<int>(cx + radius) + 1; ++x)
      if (std::hypot(x - cx, y - cy) <= radius) set_pixel(x, y, c);
}

int Canvas::text_width(const std::string& s, int scale) {
  return s.empty() ? 0 : static_cast<int>(s.size()) * (glyph_width + 1) * scale - scale;
}

int Canvas::text_height(int scale) { return glyph_height * scale; }

int Canvas::text(int x, int y, const std::string& s, Color c, int scale) {
  int pen = x;
  for (char ch : s) {
    const auto rows = glyph(ch);
    for (int r = 0; r < glyph_height; ++r)
      for (int col = 0; col < glyph_width; ++col)
        if (rows[r] & (1 << (glyph_width - 1 - col)))
          fill_rect(pen + col * scale, y + r * scale, pen + (col + 1) * scale, y + (r + 1) * scale, c);
    pen += (glyph_width + 1) * scale;
  }
  return pen - x;
}

void Canvas::text_vertical(int x, int y, const std::string& s, Color c, int scale) {
  int pen = y;  // moves upwards
  for (char ch : s) {
    const auto rows = glyph(ch);
    for (int r = 0; r < glyph_height; ++r)
      for (int col = 0; col < glyph_width; ++col)
        if (rows[r] & (1 << (glyph_width - 1 - col))) {
          // Glyph column -> upward distance, glyph row -> rightward distance.
          const int px = x + r * scale, py = pen - (col + 1) * scale;
          fill_rect(px, py, px + scale, py + scale, c);
        }
    pen -= (glyph_width + 1) * scale;
  }
}

void Canvas::write_png(const std::string& path) const {
  vtkNew<vtkImageData> image;
  image->SetDimensions(width_, height_, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* dst = static_cast<std::uint8_t*>(image->GetScalarPointer());
  // VTK images start at the bottom row.
  for (int y = 0; y < height_; ++y)
    std::copy_n(&rgb_[static_cast<std::size_t>(height_ - 1 - y) * width_ * 3], width_ * 3,
                dst + static_cast<std::size_t>(y) * width_ * 3);
  write_atomically_via(path, [&](const std::string& tmp) {
    QuietVtk quiet;
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(image);
    writer->Write();
    if (quiet.failed() || writer->GetErrorCode() != 0)
      throw file_error(path, "PNG writer failed" + (quiet.failed() ? ": " + quiet.first_message() : std::string()));
  });
}

}  // namespace pd::post
