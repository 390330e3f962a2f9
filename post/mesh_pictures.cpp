#include "mesh_pictures.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "error.hpp"
#include "units.hpp"
#include "particle_file.hpp"
#include "plots.hpp"
#include "post_pipeline.hpp"

namespace pd::post {

namespace {

// Lengths in mm to 6 digits, as typed (18mm, not 18.000000000000004).
std::string mm_list(const std::vector<double>& values) {
  std::string text;
  for (double v : values) text += (text.empty() ? "" : ", ") + format_number(v * 1e3);
  return text;
}

std::string window_text(double x0, double x1, double y0, double y1) {
  return "x in [" + mm_list({x0, x1}) + "] mm, y in [" + mm_list({y0, y1}) + "] mm";
}

// The share of the window x in [x0, x1], y in [y0, y1] that the plate's bounding box covers.
double share_on_plate(const ParticleSet& p, double x0, double x1, double y0, double y1) {
  const double w = std::max(0.0, std::min(x1, p.xmax) - std::max(x0, p.xmin));
  const double h = std::max(0.0, std::min(y1, p.ymax) - std::max(y0, p.ymin));
  return w / (x1 - x0) * (h / (y1 - y0));
}

// Four lengths in order, x0 < x1 and y0 < y1.
void check_window_form(const std::vector<double>& window) {
  if (window.size() != 4 || !(window[1] > window[0]) || !(window[3] > window[2]))
    throw Error("--zoom " + mm_list(window) + " mm (" + std::to_string(window.size()) +
                (window.size() == 1 ? " length" : " lengths") +
                "): expected x0,x1,y0,y1 with a unit on each and x0 < x1, y0 < y1, e.g. 4mm,12mm,4mm,12mm");
}

}  // namespace

ZoomWindow checked_zoom_window(const ParticleSet& p, const std::string& particle_file,
                               const std::vector<double>& window) {
  ZoomWindow z;
  if (window.empty()) return z;
  check_window_form(window);
  const double x0 = window[0], x1 = window[1], y0 = window[2], y1 = window[3];
  // A window off the plate (e.g. in the wrong unit) would draw empty pictures.
  if (std::none_of(p.x.begin(), p.x.end(), [&, i = std::size_t{0}](double x) mutable {
        const double y = p.y[i++];
        return x >= x0 && x <= x1 && y >= y0 && y <= y1;
      })) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "--zoom: the window x in [%g, %g] mm, y in [%g, %g] mm holds no particle centre of %s (the "
                  "plate spans x in [%g, %g] mm, y in [%g, %g] mm; a window within one cell holds none)",
                  x0 * 1e3, x1 * 1e3, y0 * 1e3, y1 * 1e3, particle_file.c_str(), p.xmin * 1e3, p.xmax * 1e3,
                  p.ymin * 1e3, p.ymax * 1e3);
    throw Error(text);
  }
  const std::string plate = window_text(p.xmin, p.xmax, p.ymin, p.ymax);
  // --line and --refine-region take x0,y0,x1,y1: the same four lengths
  // typed in that order still make an ordered window, drawn without a word
  // before 7 December 2026. Its meaning stays (scripts use it); a window
  // mostly off the plate that the other reading puts on it is named.
  const double a = window[0], b = window[1], c = window[2], d = window[3];
  const bool other_ordered = c > a && d > b;
  if (share_on_plate(p, x0, x1, y0, y1) < 0.5 && other_ordered && share_on_plate(p, a, c, b, d) >= 0.9)
    z.warnings.push_back("--zoom " + mm_list(window) + " mm is read as x0,x1,y0,y1: " + window_text(x0, x1, y0, y1) +
                         ", mostly off the plate (" + plate + "); read as x0,y0,x1,y1, the order of --line, it "
                         "would lie on the plate (" + window_text(a, c, b, d) + "): for that window give --zoom " +
                         format_number(a * 1e3) + "mm," + format_number(c * 1e3) + "mm," + format_number(b * 1e3) +
                         "mm," + format_number(d * 1e3) + "mm");
  // A window far larger than the plate draws the plate as a dot: it is
  // clipped to the plate's bounding box, the picture of what the window
  // holds (a refusal would ask for the same picture again).
  z.window = window;
  const double held_w = std::min(x1, p.xmax) - std::max(x0, p.xmin);
  const double held_h = std::min(y1, p.ymax) - std::max(y0, p.ymin);
  const bool clip_x = x1 - x0 > zoom_clip_factor * held_w, clip_y = y1 - y0 > zoom_clip_factor * held_h;
  if (clip_x) z.window[0] = std::max(x0, p.xmin), z.window[1] = std::min(x1, p.xmax);
  if (clip_y) z.window[2] = std::max(y0, p.ymin), z.window[3] = std::min(y1, p.ymax);
  if (clip_x || clip_y)
    z.warnings.push_back("--zoom: the window " + window_text(x0, x1, y0, y1) + " is more than " +
                         format_number(zoom_clip_factor) + " times " +
                         (clip_x && clip_y ? "as wide and as tall" : clip_x ? "as wide" : "as tall") +
                         " as the part of the plate it holds (the plate spans " + plate +
                         "): drawn clipped to the plate, " +
                         window_text(z.window[0], z.window[1], z.window[2], z.window[3]) +
                         " (are its lengths in the unit meant?)");
  return z;
}

MeshPictures write_mesh_pictures(const std::string& particle_file, const std::string& out_dir,
                                 const std::vector<double>& zoom) {
  MeshPictures pictures;
  if (!zoom.empty()) check_window_form(zoom);  // before the file is read
  const auto p = read_particle_file(particle_file);
  const ZoomWindow z = checked_zoom_window(p, particle_file, zoom);
  const std::vector<double>& window = z.window;
  pictures.warnings = z.warnings;
  create_output_folder(out_dir, "-o " + clipped(out_dir), "the folder of the pictures");
  const std::string stem = std::filesystem::path(particle_file).stem().string();
  const std::string name = std::string(to_string(p.grid)) + " grid, dx " + std::to_string(p.spacing * 1e3).substr(0, 5) +
                           " mm, " + std::to_string(p.size()) + " particles";

  // Regions: squares, free quads and free triangles (curved cells carry 7 arc
  // points per curved edge, so a triangle has 3 + 7k vertices).
  const Color square{200, 205, 215}, quad{255, 160, 60}, triangle{220, 30, 60}, other_quad{90, 170, 90};
  std::vector<Color> by_region(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto vertices = p.cell_offsets[i + 1] - p.cell_offsets[i];
    const bool is_triangle = (vertices - 3) % 7 == 0;
    if (p.region[i] == static_cast<std::uint8_t>(Region::uniform_square))
      by_region[i] = square;
    else if (is_triangle)
      by_region[i] = triangle;
    else
      by_region[i] = p.region[i] == static_cast<std::uint8_t>(Region::box_free_mesh) ? quad : other_quad;
  }
  const std::vector<std::pair<Color, std::string>> legend{
      {square, "dx squares"}, {quad, "near-boundary quads"}, {other_quad, "free quads"}, {triangle, "triangles"}};
  std::vector<std::string>& written = pictures.written;
  const std::string region_png = (std::filesystem::path(out_dir) / (stem + "_region.png")).string();
  draw_cell_map(p, by_region, window, name + ": region", nullptr, legend).write_png(region_png);
  written.push_back(region_png);

  MapStyle style;
  style.bar_label = "V / dx^2";
  style.vmin = 0.25;
  style.vmax = 2.0;
  std::vector<Color> by_volume(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    by_volume[i] = colormap((p.volume[i] / (p.spacing * p.spacing) - style.vmin) / (style.vmax - style.vmin));
  const std::string volume_png = (std::filesystem::path(out_dir) / (stem + "_volume.png")).string();
  draw_cell_map(p, by_volume, window, name + ": cell volume", &style, {}).write_png(volume_png);
  written.push_back(volume_png);

  // Horizons, when they differ between particles (refinement regions,
  // smoothed horizons): the resolution levels and the ramps between them.
  const auto [smallest, largest] = std::minmax_element(p.horizon.begin(), p.horizon.end());
  if (!p.horizon.empty() && *largest > *smallest * (1 + 1e-9)) {
    MapStyle horizon_style;
    horizon_style.bar_label = "horizon [mm]";
    horizon_style.vmin = *smallest * 1e3;
    horizon_style.vmax = *largest * 1e3;
    std::vector<Color> by_horizon(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      by_horizon[i] = colormap((p.horizon[i] - *smallest) / (*largest - *smallest));
    const std::string horizon_png = (std::filesystem::path(out_dir) / (stem + "_horizon.png")).string();
    draw_cell_map(p, by_horizon, window, name + ": horizon", &horizon_style, {}).write_png(horizon_png);
    written.push_back(horizon_png);
  }
  return pictures;
}

}  // namespace pd::post
