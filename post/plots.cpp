#include "plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <utility>

#include "legend.hpp"

namespace pd::post {
namespace {

// Maps data coordinates of a rectangle of the canvas. Differences are
// taken of halves, the same numbers to the last bit, so that values near the
// largest double (a table's 1.7e308 and -1.7e308) do not overflow to an
// infinity whose quotient is a NaN pixel (before 7 December 2026 such a
// curve was not drawn, and its markers were cast to int from NaN).
struct Frame {
  int left, top, width, height;
  double x0, x1, y0, y1;
  double px(double x) const { return left + (0.5 * x - 0.5 * x0) / (0.5 * x1 - 0.5 * x0) * width; }
  double py(double y) const { return top + height - (0.5 * y - 0.5 * y0) / (0.5 * y1 - 0.5 * y0) * height; }
};

// An axis range [lo, hi] widened by `fraction` of itself at each end, within the doubles.
std::pair<double, double> padded(double lo, double hi, double fraction) {
  const double pad = 2 * fraction * (0.5 * hi - 0.5 * lo);
  constexpr double largest = std::numeric_limits<double>::max();
  return {std::max(lo - pad, -largest), std::min(hi + pad, largest)};
}

std::string tick_label(double v, double step) {
  char buf[32];
  // Beyond 1e15 fixed notation outgrows the buffer: three digits and an exponent.
  if (std::abs(v) >= 1e15 || step >= 1e15) {
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
  }
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::abs(v) < 1e-12 * step ? 0.0 : v);
  return buf;
}

void draw_axes(Canvas& c, const Frame& f, const std::string& x_label, const std::string& y_label) {
  // About one tick label per 80 px (x) and 60 px (y): narrow plots of tall
  // plates get fewer, so that the labels do not run into each other.
  const auto xt = nice_ticks(f.x0, f.x1, std::clamp(f.width / 80, 2, 8));
  const auto yt = nice_ticks(f.y0, f.y1, std::clamp(f.height / 60, 2, 6));
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

}  // namespace

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
  const double raw = (0.5 * hi - 0.5 * lo) / std::max(1, count) * 2;  // (halves: hi - lo may overflow)
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw) { step = m * magnitude; break; }
  std::vector<double> ticks;
  // (Beyond the largest double v and hi + 1e-9 step are both infinite: stop there.)
  for (double v = std::ceil(lo / step - 1e-9) * step; std::isfinite(v) && v <= hi + 1e-9 * step; v += step)
    ticks.push_back(v);
  return ticks;
}

MapStyle damage_style(const std::string& title) {
  MapStyle s;
  s.title = title;
  s.bar_label = "damage";
  return s;
}

MapStyle strain_energy_style(const std::vector<double>& values, const std::string& title) {
  MapStyle s;
  s.title = title;
  s.bar_label = "SED J/m^3";
  s.log_scale = true;
  s.vmax = std::max(1e-30, values.empty() ? 0.0 : *std::max_element(values.begin(), values.end()));
  return s;
}

bool overlap(const Box& a, const Box& b) {
  return !a.empty() && !b.empty() && a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

namespace {

constexpr int title_top = 12, legend_top = 36, band_gap = 8;

// Title and legend band of a picture `width` px wide (widened for the title):
// returns the row below the band.
int lay_out_header(PictureLayout& l, const std::string& title, std::vector<LegendEntry> legend, int left) {
  l.title = {left, title_top, left + Canvas::text_width(title), title_top + Canvas::text_height()};
  l.width = std::max(l.width, l.title.x1 + 16);
  l.legend_grid = make_legend(std::move(legend), l.width - left - 16);
  if (l.legend_grid.entries.empty()) return l.title.y1;
  l.legend = {left, legend_top, left + l.legend_grid.width(), legend_top + l.legend_grid.height()};
  return l.legend.y1;
}

// Whether a tip path's segment jumps across a pore (more than half a radius
// of it inside one): the tip re-initiated on the far side, and no crack
// runs through the pore's empty inside, so the segment is not drawn.
bool crosses_a_pore(double x0, double y0, double x1, double y1, const std::vector<Pore>& pores) {
  for (const auto& p : pores)
    if (p.length_inside(x0, y0, x1, y1) > 0.5 * p.radius) return true;
  return false;
}

// A pore's edge on the picture: its circle, or the sides of its outline's
// cells that border material.
void draw_pore(Canvas& c, const Frame& f, const Pore& p, double px_per_m, Color colour) {
  if (!p.has_outline()) {
    c.circle(f.px(p.x * 1e3), f.py(p.y * 1e3), p.radius * px_per_m, colour);
    return;
  }
  const PoreOutline& o = p.outline;
  const auto in = [&](long i, long j) { return i >= 0 && j >= 0 && i < o.nx && j < o.ny && o.inside[j * o.nx + i]; };
  const auto side = [&](double xa, double ya, double xb, double yb) {  // [m]
    c.line(f.px(xa * 1e3), f.py(ya * 1e3), f.px(xb * 1e3), f.py(yb * 1e3), colour, 1);
  };
  for (long j = 0; j < o.ny; ++j)
    for (long i = 0; i < o.nx; ++i) {
      if (!in(i, j)) continue;
      const double xa = o.x0 + i * o.cell, xb = xa + o.cell, ya = o.y0 + j * o.cell, yb = ya + o.cell;
      if (!in(i - 1, j)) side(xa, ya, xa, yb);
      if (!in(i + 1, j)) side(xb, ya, xb, yb);
      if (!in(i, j - 1)) side(xa, ya, xb, ya);
      if (!in(i, j + 1)) side(xa, yb, xb, yb);
    }
}

}  // namespace

PictureLayout layout_particle_map(double x_extent, double y_extent, const std::string& title,
                                  std::vector<LegendEntry> legend) {
  int plot_w = 1000, plot_h = static_cast<int>(std::lround(1000 * y_extent / x_extent));
  if (plot_h > 500) plot_w = std::max(1, static_cast<int>(std::lround(500 * x_extent / y_extent))), plot_h = 500;
  plot_h = std::max(plot_h, 100);
  const int left = 80, right = 120, bottom = 60, bar_label = 24;
  PictureLayout l;
  l.width = left + plot_w + right;
  const int header = lay_out_header(l, title, std::move(legend), left);
  const int top = header + band_gap + bar_label;
  l.plot = {left, top, left + plot_w, top + plot_h};
  l.bar = {left + plot_w + 25, top - bar_label, l.width, top + plot_h + band_gap};
  l.height = top + plot_h + bottom;
  return l;
}

PictureLayout layout_line_plot(const std::string& title, std::vector<LegendEntry> legend) {
  const int left = 90, plot_w = 880, plot_h = 400, bottom = 60;
  PictureLayout l;
  l.width = 1000;
  const int top = lay_out_header(l, title, std::move(legend), left) + 12;
  l.plot = {left, top, left + plot_w, top + plot_h};
  l.height = top + plot_h + bottom;
  return l;
}

Canvas draw_particle_map(const MapParticles& data, const std::vector<double>& values,
                         const MapStyle& style, const std::vector<TipPath>& tips,
                         double tips_until, const std::vector<Pore>& pores) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (std::size_t i = 0; i < data.x.size(); ++i) {
    const double h = 0.5 * data.cell_size[i];
    xmin = std::min(xmin, data.x[i] - h), xmax = std::max(xmax, data.x[i] + h);
    ymin = std::min(ymin, data.y[i] - h), ymax = std::max(ymax, data.y[i] + h);
  }
  // Legend of every drawn tip path.
  std::vector<int> drawn;
  for (const auto& tip : tips)
    if (!tip.time.empty() && tip.time[0] <= tips_until) drawn.push_back(tip.branch);
  const PictureLayout l = layout_particle_map(xmax - xmin, ymax - ymin, style.title, branch_legend_entries(drawn));
  Canvas c(l.width, l.height);
  const int plot_w = l.plot.x1 - l.plot.x0, plot_h = l.plot.y1 - l.plot.y0;
  // Axes in mm: the frame works in mm, particles are placed through it.
  const Frame f{l.plot.x0, l.plot.y0, plot_w, plot_h, xmin * 1e3, xmax * 1e3, ymin * 1e3, ymax * 1e3};
  const double px_per_m = plot_w / (xmax - xmin);
  const double py_per_m = plot_h / (ymax - ymin);

  std::vector<std::size_t> order(data.x.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  for (auto i : order) {
    const double cx = f.px(data.x[i] * 1e3), cy = f.py(data.y[i] * 1e3);
    const double hx = std::max(0.5, 0.5 * data.cell_size[i] * px_per_m);
    const double hy = std::max(0.5, 0.5 * data.cell_size[i] * py_per_m);
    c.fill_rect(static_cast<int>(std::floor(cx - hx)), static_cast<int>(std::floor(cy - hy)),
                static_cast<int>(std::ceil(cx + hx)), static_cast<int>(std::ceil(cy + hy)),
                colormap(colour_fraction(values[i], style)));
  }
  // Free cells drawn as squares of their area leave pinholes between them
  // that would read as pores: patches up to the largest cell's area (a hole
  // of the plate is larger than a cell).
  double largest_cell_px = 0;
  for (double size : data.cell_size) largest_cell_px = std::max(largest_cell_px, size * px_per_m);
  c.fill_pinholes(l.plot.x0, l.plot.y0, l.plot.x1 + 1, l.plot.y1 + 1,
                  std::max<std::size_t>(16, static_cast<std::size_t>(largest_cell_px * largest_cell_px)));
  for (const auto& p : pores) draw_pore(c, f, p, px_per_m, mid_grey);

  // Tip paths: a thin line with the branch's marker every tenth of the path,
  // so the damage underneath stays visible, and a filled marker at the tip;
  // a jump across a pore is left out (the pore's circle is drawn instead).
  for (auto it = tips.rbegin(); it != tips.rend(); ++it) {
    const auto& tip = *it;
    if (tip.time.empty() || tip.time[0] > tips_until) continue;
    const BranchStyle st = branch_style(tip.branch);
    std::size_t last = 0;
    while (last + 1 < tip.time.size() && tip.time[last + 1] <= tips_until) ++last;
    for (std::size_t k = 1; k <= last; ++k)
      if ((tip.x[k] != tip.x[k - 1] || tip.y[k] != tip.y[k - 1]) &&
          !crosses_a_pore(tip.x[k - 1], tip.y[k - 1], tip.x[k], tip.y[k], pores))
        c.line(f.px(tip.x[k - 1] * 1e3), f.py(tip.y[k - 1] * 1e3), f.px(tip.x[k] * 1e3), f.py(tip.y[k] * 1e3),
               st.color);
    const std::size_t every = std::max<std::size_t>(1, (last + 1) / 10);
    for (std::size_t k = 0; k < last; k += every)
      draw_marker(c, f.px(tip.x[k] * 1e3), f.py(tip.y[k] * 1e3), st.marker, 4, st.color, false);
    const double tx = f.px(tip.x[last] * 1e3), ty = f.py(tip.y[last] * 1e3);
    draw_marker(c, tx, ty, st.marker, 6, black, true);
    draw_marker(c, tx, ty, st.marker, 4.5, st.color, true);
  }
  // Blank the margins that squares at the edge or markers spilled into.
  c.fill_rect(0, 0, c.width(), l.plot.y0, white);
  c.fill_rect(0, l.plot.y1 + 1, c.width(), c.height(), white);
  c.fill_rect(0, 0, l.plot.x0, c.height(), white);
  c.fill_rect(l.plot.x1 + 1, 0, c.width(), c.height(), white);
  draw_axes(c, f, "x (mm)", "y (mm)");
  c.text(l.title.x0, l.title.y0, style.title, black);
  draw_legend(c, l.legend_grid, l.legend.x0, l.legend.y0);
  draw_colour_bar(c, l.bar.x0, l.plot.y0, plot_h, style);
  return c;
}

Canvas draw_speed_plot(const std::vector<SpeedSample>& samples, double rayleigh, SpeedAxis axis,
                       const std::vector<Pore>& pores, const std::vector<PoreVisit>& visits,
                       const std::string& title) {
  std::vector<int> branches;
  for (const auto& s : samples)
    if (std::find(branches.begin(), branches.end(), s.branch) == branches.end()) branches.push_back(s.branch);
  const PictureLayout l = layout_line_plot(title, branch_legend_entries(branches));
  const int left = l.plot.x0, top = l.plot.y0, plot_w = l.plot.x1 - l.plot.x0, plot_h = l.plot.y1 - l.plot.y0;
  Canvas c(l.width, l.height);
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
    for (const auto& p : pores) x0 = std::min(x0, p.x_min() * 1e3), x1 = std::max(x1, p.x_max() * 1e3);
  if (x1 <= x0) x1 = x0 + 1;
  const double pad = 0.02 * (x1 - x0);
  const double y1 = std::max(1.2, std::ceil(std::min(top_speed, 3.0) * 5 + 0.5) / 5);
  const Frame f{left, top, plot_w, plot_h, x0 - pad, x1 + pad, 0.0, y1};

  auto shade = [&](double a, double b) {
    const int l0 = std::max(left, static_cast<int>(f.px(a))), r = std::min(left + plot_w, static_cast<int>(f.px(b)) + 1);
    c.fill_rect(l0, top, r, top + plot_h, light_grey);
  };
  if (axis == SpeedAxis::tip_x)
    for (const auto& p : pores) shade(p.x_min() * 1e3, p.x_max() * 1e3);
  else
    for (const auto& v : visits)
      if (v.restart_time > v.enter_time) shade(v.enter_time * 1e6, v.restart_time * 1e6);
  c.dashed_line(left, f.py(1.0), left + plot_w, f.py(1.0), mid_grey);
  c.text(left + 6, static_cast<int>(f.py(1.0)) - 20, "c_R", mid_grey);

  // Curves first, markers on top of all of them.
  std::vector<std::vector<const SpeedSample*>> drawn(branches.size());
  for (std::size_t rank = 0; rank < branches.size(); ++rank) {
    const SpeedSample* prev = nullptr;
    const Color col = branch_color(branches[rank]);
    for (const auto& s : samples) {
      if (s.branch != branches[rank] || abscissa(s) < x0) continue;
      if (!s.is_growth()) { prev = nullptr; continue; }  // gap: the tip jumped over a pore or a gap
      const double y = std::min(s.speed / rayleigh, y1);
      if (prev) c.line(f.px(abscissa(*prev)), f.py(std::min(prev->speed / rayleigh, y1)), f.px(abscissa(s)), f.py(y), col, 2);
      prev = &s;
      drawn[rank].push_back(&s);
    }
  }
  // The branch's marker ten times along its curve. Mirror branches often
  // run at the same speed, one curve on the other: each branch starts its
  // markers a fifth of the spacing further on, so both show.
  for (std::size_t rank = 0; rank < branches.size(); ++rank) {
    const BranchStyle st = branch_style(branches[rank]);
    const auto& points = drawn[rank];
    const std::size_t every = std::max<std::size_t>(1, points.size() / 10);
    for (std::size_t k = every * (1 + rank % 4) / 5; k < points.size(); k += every)
      draw_marker(c, f.px(abscissa(*points[k])), f.py(std::min(points[k]->speed / rayleigh, y1)), st.marker, 4,
                  st.color, false);
  }
  draw_axes(c, f, axis == SpeedAxis::time ? "time (us)" : "tip x (mm)", "speed / c_R");
  c.text(l.title.x0, l.title.y0, title, black);
  draw_legend(c, l.legend_grid, l.legend.x0, l.legend.y0);
  return c;
}

Canvas draw_line_plot(const std::vector<Series>& series, const std::string& x_label, const std::string& y_label,
                      const std::string& title) {
  std::vector<LegendEntry> entries;
  for (const auto& s : series) entries.push_back({s.label, s.style});
  const PictureLayout l = layout_line_plot(title, entries);
  Canvas c(l.width, l.height);
  double x0 = 1e300, x1 = -1e300, y0 = 0, y1 = 0;  // the y axis always shows 0
  for (const auto& s : series)
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      if (!std::isfinite(s.x[k])) continue;
      x0 = std::min(x0, s.x[k]), x1 = std::max(x1, s.x[k]);  // missing values keep their place on the axis
      if (std::isfinite(s.y[k])) y0 = std::min(y0, s.y[k]), y1 = std::max(y1, s.y[k]);
    }
  if (!(x1 > x0)) x0 = x1 > -1e300 ? x1 - 1 : 0, x1 = x0 + 1;
  if (!(y1 > y0)) y1 = y0 + 1;
  const auto [x_lo, x_hi] = padded(x0, x1, 0.02);
  const auto [y_lo, y_hi] = padded(y0, y1, 0.05);
  const Frame f{l.plot.x0, l.plot.y0, l.plot.x1 - l.plot.x0, l.plot.y1 - l.plot.y0,
                x_lo, x_hi, y0 < 0 ? y_lo : 0.0, y1 > 0 ? y_hi : 0.0};
  if (f.y0 < 0 && f.y1 > 0) c.dashed_line(f.left, f.py(0.0), f.left + f.width, f.py(0.0), mid_grey);
  // A point that is not finite (a missing value) breaks the line.
  auto finite = [](const Series& s, std::size_t k) { return std::isfinite(s.x[k]) && std::isfinite(s.y[k]); };
  for (const auto& s : series) {
    const std::size_t every = std::max<std::size_t>(1, s.x.size() / 25);
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      if (!finite(s, k)) continue;
      if (k > 0 && finite(s, k - 1))
        c.line(f.px(s.x[k - 1]), f.py(s.y[k - 1]), f.px(s.x[k]), f.py(s.y[k]), s.style.color, 2);
      if (k % every == 0) draw_marker(c, f.px(s.x[k]), f.py(s.y[k]), s.style.marker, 4, s.style.color, false);
    }
  }
  draw_axes(c, f, x_label, y_label);
  c.text(l.title.x0, l.title.y0, title, black);
  draw_legend(c, l.legend_grid, l.legend.x0, l.legend.y0);
  return c;
}

Canvas draw_line_profile(const std::vector<LineSample>& samples, const std::string& title) {
  Series opening{"opening", branch_style(0), {}, {}}, sliding{"sliding", branch_style(1), {}, {}};
  const double missing = std::numeric_limits<double>::quiet_NaN();
  for (const auto& s : samples) {
    opening.x.push_back(s.s * 1e3), opening.y.push_back(s.has_jump ? s.opening * 1e6 : missing);
    sliding.x.push_back(s.s * 1e3), sliding.y.push_back(s.has_jump ? s.sliding * 1e6 : missing);
  }
  return draw_line_plot({opening, sliding}, "distance along the line (mm)", "jump (um)", title);
}

Canvas draw_cell_map(const ParticleSet& p, const std::vector<Color>& fill, std::vector<double> window,
                     const std::string& title, const MapStyle* bar,
                     const std::vector<std::pair<Color, std::string>>& legend) {
  if (window.size() != 4) window = {p.xmin, p.xmax, p.ymin, p.ymax};
  const double xmin = window[0], xmax = window[1], ymin = window[2], ymax = window[3];
  // The aspect ratio in double first: a window 1e-20 m wide made 1000 x its
  // ratio a number no int holds before 7 December 2026.
  const double aspect = (ymax - ymin) / (xmax - xmin);
  int plot_w = 1000, plot_h = 700;
  if (1000 * aspect < 700.5)
    plot_h = static_cast<int>(std::lround(1000 * aspect));
  else
    plot_w = static_cast<int>(std::lround(std::max(0.0, 700 / aspect)));
  // A window far taller than wide (--zoom along a crack) gets the least
  // size across a flat one gets: before 7 December 2026 its plot could be
  // 0 px wide, no cell drawn, and the title cut at the picture's edge.
  plot_h = std::max(plot_h, 100);
  plot_w = std::max(plot_w, 100);
  // Right of the plot: the colour bar, or the legend's swatches (20-36 px)
  // and labels (from 42 px), as wide as its longest label needs.
  const int legend_label_left = 42;
  int right = bar ? 120 : 200;
  for (const auto& entry : legend)
    right = std::max(right, legend_label_left + Canvas::text_width(entry.second) + 16);
  const int left = 80, bottom = 60;
  // The colour bar's label sits 24 px above the plot: below the title where
  // the title reaches over the bar.
  const int top = bar && left + Canvas::text_width(title) > left + plot_w + 20 ? 60 : 40;
  Canvas c(std::max(left + plot_w + right, left + Canvas::text_width(title) + 16), top + plot_h + bottom);
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
    c.text(left + plot_w + legend_label_left, ly, label, black);
    ly += 22;
  }
  return c;
}

}  // namespace pd::post
