#pragma once
// Pictures of a particle file (pd-post --particles): cells coloured by region
// and by volume / dx^2 (and by horizon where it varies), for docs/mesher.md and for checking a new grid.
#include <string>
#include <vector>

namespace pd {
struct ParticleSet;
}  // namespace pd

namespace pd::post {

// The --zoom window {x0, x1, y0, y1} [m] to draw of a plate, and the
// warnings about it. Refused (pd::Error) when it holds no particle centre.
// Warned about: a window mostly off the plate that, read as x0,y0,x1,y1 (the
// order of --line), would lie on it; a window more than
// zoom_clip_factor times as wide (or tall) as the part of the plate it
// holds, which is then clipped to the plate's bounding box that way (the
// plate drawn a dot in a white picture otherwise, e.g. metres for mm).
inline constexpr double zoom_clip_factor = 10;
struct ZoomWindow {
  std::vector<double> window;
  std::vector<std::string> warnings;
};
ZoomWindow checked_zoom_window(const ParticleSet& particles, const std::string& particle_file,
                               const std::vector<double>& window);

// Writes OUT_DIR/STEM_region.png and OUT_DIR/STEM_volume.png for the
// particle file, and OUT_DIR/STEM_horizon.png when its horizons differ;
// `window` = {x0, x1, y0, y1} [m] (checked_zoom_window), or empty for the
// whole plate. Returns the paths written and the warnings.
struct MeshPictures {
  std::vector<std::string> written;
  std::vector<std::string> warnings;
};
MeshPictures write_mesh_pictures(const std::string& particle_file, const std::string& out_dir,
                                 const std::vector<double>& window);

}  // namespace pd::post
