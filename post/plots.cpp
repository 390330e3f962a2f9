#include "plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace pd::post {
namespace {

// Maps data coordinates of a rectangle of the canvas.
struct Frame {
  int left, top, width, height;
  double x0, x1, y0, y1;
  double px(double x) const { return left + (x - x0) / (x1 - x0) * width; }
  double py(double y) const { return top + height - (y - y0) / (y1 - y0) * height; }
};

std::string tick_label(double v, double step) {
  char buf[32];
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::abs(v) < 1e-12 * step ? 0.0 : v);
  return buf;
}

void draw_axes(Canvas& c, const Frame& f, const std::string& x_label, const std::string& y_label) {
  const auto xt = nice_ticks(f.x0, f.x1, 8), yt = nice_ticks(f.y0, f.y1, 6);
  const double xs = xt.size() > 1 ? xt[1] - xt[0] : 1, ys = yt.size() > 1 ? yt[1] - yt[0] : 1;
  for (double v : xt) {
    const int x = static_cast<int>(std::lround(f.px(v)));
    c.line(x, f.top + f.height, x, f.top + f.height + 6, black);
    const auto s = tick_label(v, xs);
    c.text(x - Canvas::text_width(s) / 2, f.top + f.height + 10, s, black);
  }
  for (double v : yt) {
    const int y = static_cast<int>(std::lround(f.py(v)));
    c.line(f.left - 6, y, f.left, y, black);
    const auto s = tick_label(v, ys);
    c.text(f.left - 10 - Canvas::text_width(s), y - Canvas::text_height() / 2, s, black);
  }
  // Frame drawn last so that the data never hides it.
  c.line(f.left, f.top, f.left + f.width, f.top, black);
  c.line(f.left, f.top + f.height, f.left + f.width, f.top + f.height, black);
  c.line(f.left, f.top, f.left, f.top + f.height, black);
  c.line(f.left + f.width, f.top, f.left + f.width, f.top + f.height, black);
  c.text(f.left + f.width / 2 - Canvas::text_width(x_label) / 2, f.top + f.height + 32, x_label, black);
  c.text_vertical(8, f.top + f.height / 2 + Canvas::text_width(y_label) / 2, y_label, black);
}

double colour_fraction(double v, const MapStyle& s) {
  if (s.log_scale) {
    const double lo = std::log10(s.vmax / 1000.0), hi = std::log10(s.vmax);
    return v <= 0 ? 0.0 : std::clamp((std::log10(v) - lo) / (hi - lo), 0.0, 1.0);
  }
  return std::clamp((v - s.vmin) / (s.vmax - s.vmin), 0.0, 1.0);
}

void draw_colour_bar(Canvas& c, int x, int top, int height, const MapStyle& s) {
  const int width = 20;
  for (int y = 0; y < height; ++y)
    c.fill_rect(x, top + y, x + width, top + y + 1, colormap(1.0 - static_cast<double>(y) / (height - 1)));
  c.line(x, top, x + width, top, black);
  c.line(x, top + height, x + width, top + height, black);
  c.line(x, top, x, top + height, black);
  c.line(x + width, top, x + width, top + height, black);
  std::vector<std::pair<double, std::string>> labels;  // (fraction, text)
  if (s.log_scale) {
    const int hi = static_cast<int>(std::floor(std::log10(s.vmax)));
    for (int e = hi; e > hi - 4; --e) {
      const double f = (e - std::log10(s.vmax / 1000.0)) / 3.0;
      if (f >= 0 && f <= 1) labels.emplace_back(f, "1e" + std::to_string(e));
    }
  } else {
    const auto ticks = nice_ticks(s.vmin, s.vmax, 5);
    const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1;
    for (double v : ticks) labels.emplace_back((v - s.vmin) / (s.vmax - s.vmin), tick_label(v, step));
  }
  for (const auto& [f, text] : labels) {
    const int y = static_cast<int>(std::lround(top + height - f * height));
    c.line(x + width, y, x + width + 5, y, black);
    c.text(x + width + 8, y - Canvas::text_height() / 2, text, black);
  }
  c.text(std::min(x, c.width() - Canvas::text_width(s.bar_label) - 4), top - 24, s.bar_label, black);
}

// Legend of branch colours: "b<id>" entries in one grid, filled row by row
// in increasing branch id, all cells as wide as the widest entry, as many
// columns as fit in the given width (so any number of branches is listed).
struct Legend {
  std::vector<int> branches;
  int columns = 1, rows = 0, cell_width = 0;
  static constexpr int row_height = 18;
  int width() const { return columns * cell_width; }
  int height() const { return rows * row_height; }
};

Legend make_legend(std::vector<int> branches, int max_width) {
  Legend g;
  std::sort(branches.begin(), branches.end());
  branches.erase(std::unique(branches.begin(), branches.end()), branches.end());
  g.branches = std::move(branches);
  if (g.branches.empty()) return g;
  // Swatch 12 px, 4 px to the name, 16 px to the next cell.
  g.cell_width = 32 + Canvas::text_width("b" + std::to_string(g.branches.back()));
  g.columns = std::clamp(max_width / g.cell_width, 1, static_cast<int>(g.branches.size()));
  g.rows = (static_cast<int>(g.branches.size()) + g.columns - 1) / g.columns;
  return g;
}

// Colour of a branch's speed curve: on the white plot, white is drawn black.
Color curve_color(int branch) {
  const Color col = branch_color(branch);
  return col == white ? black : col;
}

// The legend with its top-right corner at (right, top), on a white ground
// so that curves underneath do not cross the names; swatches are framed so
// that a white branch shows. `curves`: colours of the speed plot's curves.
void draw_legend(Canvas& c, const Legend& g, int right, int top, bool curves) {
  const int left = right - g.width();
  c.fill_rect(left - 4, top - 2, right, top + g.height(), white);
  for (std::size_t i = 0; i < g.branches.size(); ++i) {
    const int x = left + static_cast<int>(i) % g.columns * g.cell_width;
    const int y = top + static_cast<int>(i) / g.columns * Legend::row_height;
    c.fill_rect(x, y + 1, x + 12, y + 13, black);
    const int b = g.branches[i];
    c.fill_rect(x + 1, y + 2, x + 11, y + 12, curves ? curve_color(b) : branch_color(b));
    c.text(x + 16, y, "b" + std::to_string(g.branches[i]), black);
  }
}

}  // namespace

Color branch_color(int branch) {
  static const Color palette[] = {{230, 25, 75},  {0, 200, 255},   {255, 140, 0},  {255, 60, 255},
                                  {255, 255, 255}, {120, 255, 80}, {255, 190, 190}, {160, 120, 255}};
  return palette[static_cast<std::size_t>(branch) % (sizeof palette / sizeof palette[0])];
}

Color colormap(double f) {
  // Control points of the "viridis" scale (matplotlib), linearly interpolated.
  static const double stops[][3] = {{68, 1, 84},    {72, 40, 120},  {62, 74, 137},  {49, 104, 142},
                                    {38, 130, 142}, {31, 158, 137}, {53, 183, 121}, {110, 206, 88},
                                    {181, 222, 43}, {253, 231, 37}};
  constexpr int n = 10;
  f = std::clamp(f, 0.0, 1.0) * (n - 1);
  const int i = std::min(static_cast<int>(f), n - 2);
  const double w = f - i;
  auto mix = [&](int k) { return static_cast<std::uint8_t>(std::lround(stops[i][k] * (1 - w) + stops[i + 1][k] * w)); };
  return {mix(0), mix(1), mix(2)};
}

std::vector<double> nice_ticks(double lo, double hi, int count) {
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / std::max(1, count);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw) { step = m * magnitude; break; }
  std::vector<double> ticks;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) ticks.push_back(v);
  return ticks;
}

Canvas draw_particle_map(const ArrivalData& data, const std::vector<double>& values,
                         const MapStyle& style, const std::vector<TipPath>& tips,
                         double tips_until, const std::vector<Pore>& pores) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double h = 0.5 * data.cell_size[i];
    xmin = std::min(xmin, data.x[i] - h), xmax = std::max(xmax, data.x[i] + h);
    ymin = std::min(ymin, data.y[i] - h), ymax = std::max(ymax, data.y[i] + h);
  }
  int plot_w = 1000, plot_h = static_cast<int>(std::lround(1000 * (ymax - ymin) / (xmax - xmin)));
  if (plot_h > 500) plot_w = static_cast<int>(std::lround(500 * (xmax - xmin) / (ymax - ymin))), plot_h = 500;
  plot_h = std::max(plot_h, 100);
  // Legend of every drawn branch right of the title; the top margin grows
  // by a row for each further row of the legend.
  std::vector<int> drawn;
  for (const auto& tip : tips)
    if (!tip.time.empty() && tip.time[0] <= tips_until) drawn.push_back(tip.branch);
  const int left = 80, right = 120, bottom = 60;
  const Legend legend = make_legend(drawn, plot_w - Canvas::text_width(style.title) - 24);
  const int top = 40 + std::max(0, legend.rows - 1) * Legend::row_height;
  Canvas c(left + plot_w + right, top + plot_h + bottom);
  // Axes in mm: the frame works in mm, particles are placed through it.
  const Frame f{left, top, plot_w, plot_h, xmin * 1e3, xmax * 1e3, ymin * 1e3, ymax * 1e3};
  const double px_per_m = plot_w / (xmax - xmin);

  std::vector<std::size_t> order(data.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  for (auto i : order) {
    const double cx = f.px(data.x[i] * 1e3), cy = f.py(data.y[i] * 1e3);
    const double h = std::max(0.5, 0.5 * data.cell_size[i] * px_per_m);
    c.fill_rect(static_cast<int>(std::floor(cx - h)), static_cast<int>(std::floor(cy - h)),
                static_cast<int>(std::ceil(cx + h)), static_cast<int>(std::ceil(cy + h)),
                colormap(colour_fraction(values[i], style)));
  }
  for (const auto& p : pores) c.circle(f.px(p.x * 1e3), f.py(p.y * 1e3), p.radius * px_per_m, mid_grey);

  // Tip paths: a thin line with a marker every tenth of the path, so the
  // damage underneath stays visible.
  for (auto it = tips.rbegin(); it != tips.rend(); ++it) {
    const auto& tip = *it;
    const Color col = branch_color(tip.branch);
    std::size_t last = 0;
    while (last + 1 < tip.time.size() && tip.time[last + 1] <= tips_until) ++last;
    if (tip.time.empty() || tip.time[0] > tips_until) continue;
    for (std::size_t k = 1; k <= last; ++k)
      if (tip.x[k] != tip.x[k - 1] || tip.y[k] != tip.y[k - 1])
        c.line(f.px(tip.x[k - 1] * 1e3), f.py(tip.y[k - 1] * 1e3), f.px(tip.x[k] * 1e3), f.py(tip.y[k] * 1e3), col);
    const std::size_t every = std::max<std::size_t>(1, (last + 1) / 10);
    for (std::size_t k = 0; k <= last; k += every) c.circle(f.px(tip.x[k] * 1e3), f.py(tip.y[k] * 1e3), 3, col);
    c.filled_circle(f.px(tip.x[last] * 1e3), f.py(tip.y[last] * 1e3), 4, col);
  }
  draw_axes(c, f, "x (mm)", "y (mm)");
  c.text(left, 12, style.title, black);
  draw_legend(c, legend, left + plot_w, 12, false);
  draw_colour_bar(c, left + plot_w + 25, top, plot_h, style);
  return c;
}

Canvas draw_speed_plot(const std::vector<SpeedSample>& samples, double rayleigh, SpeedAxis axis,
                       const std::vector<Pore>& pores, const std::vector<PoreVisit>& visits,
                       const std::string& title) {
  const int left = 90, top = 40, plot_w = 880, plot_h = 400;
  Canvas c(1000, 500);
  auto abscissa = [&](const SpeedSample& s) { return axis == SpeedAxis::time ? s.time * 1e6 : s.tip_x * 1e3; };
  double x0 = 1e300, x1 = -1e300, top_speed = 0;
  // Time axis from shortly before the first crack growth: the quiet loading
  // phase would squeeze the interesting part into a corner.
  double first_growth = 1e300, last = -1e300;
  for (const auto& s : samples) {
    if (s.speed > 0) first_growth = std::min(first_growth, abscissa(s));
    last = std::max(last, abscissa(s));
  }
  for (const auto& s : samples) {
    if (axis == SpeedAxis::time && first_growth < last && abscissa(s) < first_growth - 0.1 * (last - first_growth))
      continue;
    x0 = std::min(x0, abscissa(s)), x1 = std::max(x1, abscissa(s));
    if (s.is_growth()) top_speed = std::max(top_speed, s.speed / rayleigh);
  }
  if (samples.empty()) x0 = 0, x1 = 1;
  if (axis == SpeedAxis::tip_x)
    for (const auto& p : pores) x0 = std::min(x0, (p.x - p.radius) * 1e3), x1 = std::max(x1, (p.x + p.radius) * 1e3);
  if (x1 <= x0) x1 = x0 + 1;
  const double pad = 0.02 * (x1 - x0);
  const double y1 = std::max(1.2, std::ceil(std::min(top_speed, 3.0) * 5 + 0.5) / 5);
  const Frame f{left, top, plot_w, plot_h, x0 - pad, x1 + pad, 0.0, y1};

  auto shade = [&](double a, double b) {
    const int l = std::max(left, static_cast<int>(f.px(a))), r = std::min(left + plot_w, static_cast<int>(f.px(b)) + 1);
    c.fill_rect(l, top, r, top + plot_h, light_grey);
  };
  if (axis == SpeedAxis::tip_x)
    for (const auto& p : pores) shade((p.x - p.radius) * 1e3, (p.x + p.radius) * 1e3);
  else
    for (const auto& v : visits)
      if (v.restart_time > v.enter_time) shade(v.enter_time * 1e6, v.restart_time * 1e6);
  c.dashed_line(left, f.py(1.0), left + plot_w, f.py(1.0), mid_grey);
  c.text(left + 6, static_cast<int>(f.py(1.0)) - 20, "c_R", mid_grey);

  std::vector<int> branches;
  for (const auto& s : samples)
    if (std::find(branches.begin(), branches.end(), s.branch) == branches.end()) branches.push_back(s.branch);
  for (int b : branches) {
    const SpeedSample* prev = nullptr;
    const Color col = curve_color(b);
    for (const auto& s : samples) {
      if (s.branch != b || abscissa(s) < x0) continue;
      if (!s.is_growth()) { prev = nullptr; continue; }  // gap: the tip jumped over a pore or a gap
      const double y = std::min(s.speed / rayleigh, y1);
      if (prev) c.line(f.px(abscissa(*prev)), f.py(std::min(prev->speed / rayleigh, y1)), f.px(abscissa(s)), f.py(y), col, 2);
      prev = &s;
    }
  }
  // Legend of every branch with a curve, top right inside the plot.
  draw_legend(c, make_legend(branches, plot_w - 90), left + plot_w - 8, top + 8, true);
  draw_axes(c, f, axis == SpeedAxis::time ? "time (us)" : "tip x (mm)", "speed / c_R");
  c.text(left, 12, title, black);
  return c;
}

Canvas draw_cell_map(const ParticleSet& p, const std::vector<Color>& fill, std::vector<double> window,
                     const std::string& title, const MapStyle* bar,
                     const std::vector<std::pair<Color, std::string>>& legend) {
  if (window.size() != 4) window = {p.xmin, p.xmax, p.ymin, p.ymax};
  const double xmin = window[0], xmax = window[1], ymin = window[2], ymax = window[3];
  int plot_w = 1000, plot_h = static_cast<int>(std::lround(1000 * (ymax - ymin) / (xmax - xmin)));
  if (plot_h > 700) plot_w = static_cast<int>(std::lround(700 * (xmax - xmin) / (ymax - ymin))), plot_h = 700;
  plot_h = std::max(plot_h, 100);
  const int left = 80, top = 40, right = bar ? 120 : 200, bottom = 60;
  Canvas c(left + plot_w + right, top + plot_h + bottom);
  const Frame f{left, top, plot_w, plot_h, xmin * 1e3, xmax * 1e3, ymin * 1e3, ymax * 1e3};
  const double px_per_m = plot_w / (xmax - xmin);
  const bool outline = p.spacing * px_per_m >= 6;
  std::vector<double> vx, vy;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto b = p.cell_offsets[i], e = p.cell_offsets[i + 1];
    double cx0 = 1e300, cx1 = -1e300, cy0 = 1e300, cy1 = -1e300;
    for (auto k = b; k < e; ++k) {
      cx0 = std::min(cx0, p.cell_vx[k]), cx1 = std::max(cx1, p.cell_vx[k]);
      cy0 = std::min(cy0, p.cell_vy[k]), cy1 = std::max(cy1, p.cell_vy[k]);
    }
    if (cx1 < xmin || cx0 > xmax || cy1 < ymin || cy0 > ymax) continue;
    vx.clear(), vy.clear();
    for (auto k = b; k < e; ++k) vx.push_back(f.px(p.cell_vx[k] * 1e3)), vy.push_back(f.py(p.cell_vy[k] * 1e3));
    c.fill_polygon(vx, vy, fill[i]);
    if (outline)
      for (std::size_t k = 0; k < vx.size(); ++k)
        c.line(vx[k], vy[k], vx[(k + 1) % vx.size()], vy[(k + 1) % vx.size()], mid_grey);
  }
  // Blank the margins the cells spilled into, then draw the frame.
  c.fill_rect(0, 0, c.width(), top, white);
  c.fill_rect(0, top + plot_h + 1, c.width(), c.height(), white);
  c.fill_rect(0, 0, left, c.height(), white);
  c.fill_rect(left + plot_w + 1, 0, c.width(), c.height(), white);
  draw_axes(c, f, "x (mm)", "y (mm)");
  c.text(left, 12, title, black);
  if (bar) draw_colour_bar(c, left + plot_w + 25, top, plot_h, *bar);
  int ly = top;
  for (const auto& [colour, label] : legend) {
    c.fill_rect(left + plot_w + 20, ly + 2, left + plot_w + 36, ly + 14, colour);
    c.text(left + plot_w + 42, ly, label, black);
    ly += 22;
  }
  return c;
}

}  // namespace pd::post
