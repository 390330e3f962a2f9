#include "loads.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "error.hpp"

namespace pd::solver {

std::vector<std::uint32_t> resolve_region(const RegionSpec& region, const ParticleSet& p,
                                          const std::string& scene_path, const std::string& key) {
  std::vector<std::uint32_t> out;
  if (region.has_box) {
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.x[i] >= region.box[0] && p.x[i] <= region.box[2] && p.y[i] >= region.box[1] && p.y[i] <= region.box[3])
        out.push_back(static_cast<std::uint32_t>(i));
  } else if (region.set == "all") {
    out.resize(p.size());
    std::iota(out.begin(), out.end(), 0u);
  } else if (const BoundarySet* s = p.find_set(region.set)) {
    out = s->particles;
  } else {
    std::string known;
    for (const auto& s : p.sets) known += (known.empty() ? "" : ", ") + s.name;
    throw Error(scene_path + ": key '" + key + ".set' = \"" + region.set +
                "\": no such boundary set in the particle file (known: " + known + ", or \"all\")");
  }
  if (out.empty())
    throw Error(scene_path + ": key '" + key + "': " + region.describe() + " contains no particle");
  return out;
}

double set_edge_length(const ParticleSet& p, const std::vector<std::uint32_t>& set) {
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (auto i : set) {
    const double h = 0.5 * p.cell_size[i];
    xmin = std::min(xmin, p.x[i] - h), xmax = std::max(xmax, p.x[i] + h);
    ymin = std::min(ymin, p.y[i] - h), ymax = std::max(ymax, p.y[i] + h);
  }
  return std::max(xmax - xmin, ymax - ymin);
}

std::vector<ResolvedLoad> resolve_loads(const Scene& scene, const ParticleSet& p) {
  std::vector<ResolvedLoad> loads;
  for (std::size_t k = 0; k < scene.loads.size(); ++k) {
    ResolvedLoad load;
    load.spec = scene.loads[k];
    load.particles = resolve_region(load.spec.region, p, scene.path, "loads[" + std::to_string(k) + "]");
    if (load.spec.kind == LoadKind::traction) {
      load.edge_length = load.spec.edge_length > 0 ? load.spec.edge_length : set_edge_length(p, load.particles);
      double area = 0;
      for (auto i : load.particles) area += p.volume[i];
      load.body_force_x = load.spec.x * load.edge_length / area;
      load.body_force_y = load.spec.y * load.edge_length / area;
    }
    loads.push_back(std::move(load));
  }
  return loads;
}

}  // namespace pd::solver
