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

std::vector<std::string> write_mesh_pictures(const std::string& particle_file, const std::string& out_dir,
                                             const std::vector<double>& window) {
  if (!window.empty() && (window.size() != 4 || !(window[1] > window[0]) || !(window[3] > window[2]))) {
    // The lengths as read, in mm, to 6 digits: the metres' conversion back
    // printed 18mm as 18.000000000000004.
    std::string given;
    for (double v : window) given += (given.empty() ? "" : ", ") + format_number(v * 1e3);
    throw Error("--zoom " + given + " mm (" + std::to_string(window.size()) + (window.size() == 1 ? " length" : " lengths") +
                "): expected x0,x1,y0,y1 with a unit on each and x0 < x1, y0 < y1, e.g. 4mm,12mm,4mm,12mm");
  }
  const auto p = read_particle_file(particle_file);
  // A window off the plate (e.g. in the wrong unit) would draw empty pictures.
  if (!window.empty() && std::none_of(p.x.begin(), p.x.end(), [&, i = std::size_t{0}](double x) mutable {
        const double y = p.y[i++];
        return x >= window[0] && x <= window[1] && y >= window[2] && y <= window[3];
      })) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "--zoom: the window x in [%g, %g] mm, y in [%g, %g] mm holds no particle centre of %s (the "
                  "plate spans x in [%g, %g] mm, y in [%g, %g] mm; a window within one cell holds none)",
                  window[0] * 1e3, window[1] * 1e3, window[2] * 1e3, window[3] * 1e3, particle_file.c_str(),
                  p.xmin * 1e3, p.xmax * 1e3, p.ymin * 1e3, p.ymax * 1e3);
    throw Error(text);
  }
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
  std::vector<std::string> written;
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
  return written;
}

}  // namespace pd::post
