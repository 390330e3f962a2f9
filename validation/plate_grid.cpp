#include "plate_grid.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

#include "box_spacing.hpp"
#include "error.hpp"
#include "families.hpp"
#include "gmsh_session.hpp"
#include "grids.hpp"
#include "loading_layer.hpp"
#include "refinement.hpp"
#include "resource_estimate.hpp"
#include "units.hpp"

namespace pd::validation {

const char* grid_name(GridKind grid) {
  switch (grid) {
    case GridKind::uniform: return "uniform";
    case GridKind::free: return "free";
    case GridKind::nbnug: return "NB-NUG";
  }
  return "?";
}

void check_grid_fits_memory(const PlateGridSpec& spec, const PlateGeometry& geometry) {
  // A grid that cannot fit in memory is refused before it is built, as
  // pd-mesh refuses it (before 7 December 2026 the validation tools built
  // it: --spacing 1um on the 20 mm plate ran out of time or memory). The
  // estimate is pd-mesh's, NB-NUG boxes meshed finer included (before that
  // day's later change the plate at dx alone, which --box-refinement 64
  // exceeds 4096 times in the boxes).
  const double free_cell_size = spec.spacing / spec.box_refinement;
  const bool finer_boxes = spec.grid == GridKind::nbnug && spec.box_refinement > 1;
  const FinerBoxesEstimate boxes =
      finer_boxes ? finer_boxes_estimate(geometry, spec.spacing, free_cell_size, spec.horizon) : FinerBoxesEstimate{};
  const ResourceEstimate estimate = estimate_resources(geometry.exact_area() + boxes.extra_area, spec.spacing,
                                                       spec.horizon, spec.quadrature, boxes.smoothed_extra_bond_area);
  const double available = available_memory_bytes();
  if (!std::isfinite(estimate.memory_bytes) || (available > 0 && estimate.memory_bytes > available)) {
    char counts[64];
    std::snprintf(counts, sizeof counts, "%.3g particles", estimate.particles);
    throw file_error(spec.geometry_file,
                     std::string("the ") + grid_name(spec.grid) + " grid at the spacing " + format_mm(spec.spacing) +
                         (finer_boxes ? ", its boxes at " + format_mm(free_cell_size) + " (--box-refinement " +
                                            std::to_string(spec.box_refinement) + "),"
                                      : std::string()) +
                         " would have about " + counts + " and need " + format_bytes(estimate.memory_bytes) +
                         " of memory, more than the " + format_bytes(available) + " available: give a larger --spacing" +
                         (finer_boxes ? " or a smaller --box-refinement" : ""));
  }
}

PlateGeometry plate_geometry_of(const std::string& geometry_file, double spacing) {
  GmshSession session;
  return load_plate_geometry(session, geometry_file, 1e-3, spacing);
}

ParticleSet make_plate_grid(const PlateGridSpec& spec, PlateGeometry* geometry_out, const LoadingLayers& layers) {
  GmshSession session;
  // The curves' samples as far apart as the free cells are large (as pd-mesh).
  const double free_cell_size = spec.spacing / spec.box_refinement;
  const auto geometry = load_plate_geometry(session, spec.geometry_file, 1e-3, free_cell_size);
  check_grid_fits_memory(spec, geometry);
  GridReport report;
  // NB-NUG boxes padded by one horizon, pd-mesh's default.
  auto particles = build_grid(session, geometry, {spec.grid, spec.spacing, spec.horizon, free_cell_size}, report);
  const double depth = layers.depth > 0 ? layers.depth : spec.horizon;
  if (!layers.edges.empty())
    append_loading_layers(particles, geometry, layers.edges, depth, "loading layer");
  sort_particles_spatially(particles);
  assign_horizons(particles, spec.horizon, spec.box_refinement > 1 ? free_cell_size : 0);
  if (layers.edges.empty()) {
    build_families(particles, spec.quadrature);
  } else {
    // With layers the bonds into them must be kept: pd-mesh's boundary with the layers as material.
    const auto boundary = material_boundary_with_layers(geometry, spec.spacing, spec.horizon, layers.edges, depth);
    build_families(particles, spec.quadrature, &boundary);
  }
  add_boundary_sets(particles, geometry, spec.horizon);
  if (!layers.edges.empty()) add_loading_layer_sets(particles, geometry, layers.edges);
  if (geometry_out) *geometry_out = geometry;
  return particles;
}

std::vector<solver::LoadSpec> opposite_edge_displacements(double u, const std::string& left_set,
                                                          const std::string& right_set) {
  std::vector<solver::LoadSpec> loads;
  for (const auto& [set, value] : {std::pair{left_set, -u}, std::pair{right_set, u}}) {
    solver::LoadSpec load;
    load.name = set;
    load.kind = solver::LoadKind::displacement;
    load.region.set = set;
    load.has_x = true;
    load.x = value;
    loads.push_back(load);
  }
  return loads;
}

}  // namespace pd::validation
