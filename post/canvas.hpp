#pragma once
// An RGB picture in memory with the few drawing operations the plots need,
// written as PNG. Pixel (0, 0) is the top-left corner.
#include <cstdint>
#include <string>
#include <vector>

namespace pd::post {

struct Color {
  std::uint8_t r = 0, g = 0, b = 0;
};
inline bool operator==(Color a, Color b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

inline constexpr Color white{255, 255, 255};
inline constexpr Color black{0, 0, 0};
inline constexpr Color light_grey{225, 225, 225};
inline constexpr Color mid_grey{150, 150, 150};

class Canvas {
public:
  Canvas(int width, int height, Color background = white);

  int width() const { return width_; }
  int height() const { return height_; }
  Color pixel(int x, int y) const;
  void set_pixel(int x, int y, Color c);  // ignores pixels outside

  // Filled rectangle covering columns [x0, x1) and rows [y0, y1).
  void fill_rect(int x0, int y0, int x1, int y1, Color c);
  // Straight line of the given thickness (pixels) between pixel centres.
  void line(double x0, double y0, double x1, double y1, Color c, int thickness = 1);
  void dashed_line(double x0, double y0, double x1, double y1, Color c, int dash = 6);
  void circle(double cx, double cy, double radius, Color c, int thickness = 1);
  void filled_circle(double cx, double cy, double radius, Color c);
  // Filled polygon (pixel coordinates, either orientation): every pixel whose
  // centre lies inside (even-odd rule).
  void fill_polygon(const std::vector<double>& px, const std::vector<double>& py, Color c);

  // Fills the pinholes of columns [x0, x1) and rows [y0, y1): patches of at
  // most `largest` background pixels (4-connected) that do not touch the
  // window's edge, each pixel with the mean of its covered neighbours. They
  // are the gaps left between cells drawn as squares that do not tile (free
  // mesh cells); a hole or a notch is a larger patch and stays.
  void fill_pinholes(int x0, int y0, int x1, int y1, std::size_t largest = 16, Color background = white);

  // Text with the built-in 5 x 7 font magnified `scale` times; (x, y) is the
  // top-left corner. Returns the width drawn.
  int text(int x, int y, const std::string& s, Color c, int scale = 2);
  // Text turned 90 degrees counter-clockwise (for y-axis labels), reading
  // upwards from (x, y) = its bottom-left corner.
  void text_vertical(int x, int y, const std::string& s, Color c, int scale = 2);
  static int text_width(const std::string& s, int scale = 2);
  static int text_height(int scale = 2);

  // Writes a PNG file atomically (vtkPNGWriter).
  void write_png(const std::string& path) const;

private:
  int width_, height_;
  std::vector<std::uint8_t> rgb_;
};

}  // namespace pd::post
