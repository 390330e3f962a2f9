#pragma once
// Pictures of a particle file (pd-post --particles): cells coloured by region
// and by volume / dx^2 (and by horizon where it varies), for docs/mesher.md and for checking a new grid.
#include <string>
#include <vector>

namespace pd::post {

// Writes OUT_DIR/STEM_region.png and OUT_DIR/STEM_volume.png for the
// particle file, and OUT_DIR/STEM_horizon.png when its horizons differ;
// `window` = {x0, x1, y0, y1} [m], or empty for the whole plate. Returns the
// paths written.
std::vector<std::string> write_mesh_pictures(const std::string& particle_file, const std::string& out_dir,
                                             const std::vector<double>& window);

}  // namespace pd::post
