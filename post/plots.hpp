#pragma once
// The pictures: particle maps (damage, strain energy density, displacement)
// with the tracked tip paths and pores, crack-speed plots and line plots
// (reactions against load). Axes are in mm and us; everything else is SI.
#include <string>
#include <vector>

#include "arrival_data.hpp"
#include "branch_style.hpp"
#include "canvas.hpp"
#include "crack_speed.hpp"
#include "legend.hpp"
#include "line_profile.hpp"
#include "particle_file.hpp"
#include "pores.hpp"
#include "tip_tracking.hpp"

namespace pd::post {

// Colour of f in [0, 1] on a perceptually ordered dark-blue-to-yellow scale.
Color colormap(double f);

struct MapStyle {
  std::string title;
  std::string bar_label;
  bool log_scale = false;  // log10 colour scale over [vmax / 1000, vmax]
  double vmin = 0, vmax = 1;
};

// The colour scales of the maps: damage on [0, 1]; strain energy density
// on a log scale over three decades up to its largest value [J/m^3].
MapStyle damage_style(const std::string& title);
MapStyle strain_energy_style(const std::vector<double>& values, const std::string& title);

// A rectangle of pixels: columns [x0, x1), rows [y0, y1).
struct Box {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};
bool overlap(const Box& a, const Box& b);

// Where the parts of a picture go. From the top: the title, the legend in a
// band of its own (as many rows as it needs), then the plot; maps have the
// colour bar right of the plot with its label above it, below the legend.
// The picture is widened when the title needs it (tall plates).
struct PictureLayout {
  int width = 0, height = 0;
  Box title, legend, plot, bar;
  Legend legend_grid;
};

// Map of a plate x_extent wide and y_extent high [m]: plot area 1000 px wide
// (height by aspect ratio, at most 500 px, at least 100 px; a taller plate
// gets a narrower plot), 80 px left, 120 px right, 60 px below.
PictureLayout layout_particle_map(double x_extent, double y_extent, const std::string& title,
                                  std::vector<LegendEntry> legend);

// The particles a map draws (references, not copies).
struct MapParticles {
  const std::vector<double>& x;          // [m]
  const std::vector<double>& y;          // [m]
  const std::vector<double>& cell_size;  // [m]
};

// Particles are squares of their cell size; tip paths are drawn up to
// `tips_until` [s], one style per branch (branch_style.hpp).
Canvas draw_particle_map(const MapParticles& particles, const std::vector<double>& values,
                         const MapStyle& style, const std::vector<TipPath>& tips,
                         double tips_until, const std::vector<Pore>& pores);
inline Canvas draw_particle_map(const ArrivalData& data, const std::vector<double>& values, const MapStyle& style,
                                const std::vector<TipPath>& tips, double tips_until, const std::vector<Pore>& pores) {
  return draw_particle_map(MapParticles{data.x, data.y, data.cell_size}, values, style, tips, tips_until, pores);
}

enum class SpeedAxis { time, tip_x };

// Plots 1000 px wide: plot area 880 x 400 px, plus the title and legend band.
PictureLayout layout_line_plot(const std::string& title, std::vector<LegendEntry> legend);

// Speed / c_R against time [us] or tip x [mm], one line per branch; pores
// (tip x) or trapping intervals (time) shaded.
Canvas draw_speed_plot(const std::vector<SpeedSample>& samples, double rayleigh, SpeedAxis axis,
                       const std::vector<Pore>& pores, const std::vector<PoreVisit>& visits,
                       const std::string& title);

// y against x, one polyline with markers per series.
struct Series {
  std::string label;
  BranchStyle style;
  std::vector<double> x, y;
};
Canvas draw_line_plot(const std::vector<Series>& series, const std::string& x_label, const std::string& y_label,
                      const std::string& title);

// Opening and sliding (um) against the distance along the line (mm).
Canvas draw_line_profile(const std::vector<LineSample>& samples, const std::string& title);

// A particle file's cells as filled polygons, over a window [x0, x1] x
// [y0, y1] in metres (the plate if empty): coloured by `fill`, outlined
// when cells are at least 6 px wide, with axes in mm, a title, and either a
// colour bar (`bar`, colours from colormap) or a legend of (colour, label).
Canvas draw_cell_map(const ParticleSet& particles, const std::vector<Color>& fill,
                     std::vector<double> window, const std::string& title, const MapStyle* bar,
                     const std::vector<std::pair<Color, std::string>>& legend);

// Tick positions covering [lo, hi] with a 1-2-5 step, about `count` of them.
std::vector<double> nice_ticks(double lo, double hi, int count);

}  // namespace pd::post
