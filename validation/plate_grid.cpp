#include "plate_grid.hpp"

#include "families.hpp"
#include "gmsh_session.hpp"
#include "grids.hpp"

namespace pd::validation {

const char* grid_name(GridKind grid) {
  switch (grid) {
    case GridKind::uniform: return "uniform";
    case GridKind::free: return "free";
    case GridKind::nbnug: return "NB-NUG";
  }
  return "?";
}

ParticleSet make_plate_grid(const PlateGridSpec& spec, PlateGeometry* geometry_out) {
  GmshSession session;
  const auto geometry = load_plate_geometry(session, spec.geometry_file, 1e-3, spec.spacing);
  GridReport report;
  // NB-NUG boxes padded by one horizon, pd-mesh's default.
  auto particles = build_grid(session, geometry, {spec.grid, spec.spacing, spec.horizon}, report);
  sort_particles_spatially(particles);
  particles.horizon_nominal = spec.horizon;
  for (auto& h : particles.horizon) h = spec.horizon;
  build_families(particles, spec.quadrature);
  add_boundary_sets(particles, geometry, spec.horizon);
  if (geometry_out) *geometry_out = geometry;
  return particles;
}

std::vector<solver::LoadSpec> opposite_edge_displacements(double u) {
  std::vector<solver::LoadSpec> loads;
  for (const char* side : {"left", "right"}) {
    solver::LoadSpec load;
    load.name = side;
    load.kind = solver::LoadKind::displacement;
    load.region.set = side;
    load.has_x = true;
    load.x = std::string(side) == "left" ? -u : u;
    loads.push_back(load);
  }
  return loads;
}

}  // namespace pd::validation
