#pragma once
// The pictures: particle maps (damage, strain energy density) with the
// tracked tip paths and pores, and crack-speed line plots. Axes are in mm
// and us; everything else is SI.
#include <string>
#include <vector>

#include "arrival_data.hpp"
#include "particle_file.hpp"
#include "canvas.hpp"
#include "crack_speed.hpp"
#include "pores.hpp"
#include "tip_tracking.hpp"

namespace pd::post {

// One colour per branch (cycled).
Color branch_color(int branch);

// Colour of f in [0, 1] on a perceptually ordered dark-blue-to-yellow scale.
Color colormap(double f);

struct MapStyle {
  std::string title;
  std::string bar_label;
  bool log_scale = false;  // log10 colour scale over [vmax / 1000, vmax]
  double vmin = 0, vmax = 1;
};

// Plot area 1000 px wide (height by aspect ratio, at most 500 px) plus
// margins: 1200 x 600 px for a plate twice as wide as high. Particles are
// squares of their cell size; tip paths are drawn up to `tips_until` [s].
Canvas draw_particle_map(const ArrivalData& data, const std::vector<double>& values,
                         const MapStyle& style, const std::vector<TipPath>& tips,
                         double tips_until, const std::vector<Pore>& pores);

enum class SpeedAxis { time, tip_x };

// Speed / c_R against time [us] or tip x [mm], one line per branch; pores
// (tip x) or trapping intervals (time) shaded. 1000 x 500 px.
Canvas draw_speed_plot(const std::vector<SpeedSample>& samples, double rayleigh, SpeedAxis axis,
                       const std::vector<Pore>& pores, const std::vector<PoreVisit>& visits,
                       const std::string& title);

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
