#pragma once
// The C1 plate with its hole (20 mm, hole radius 4 mm, centre (10, 10) mm,
// geometries/c1_plate_hole.geo) as an NB-NUG grid, for tests that need
// lattice squares away from the hole and free gmsh cells round it (those
// along the hole with their curved edge as a polyline). Needs the mesher's
// library and PD_GEOMETRY_DIR.
#include <string>

#include "boundary_sets.hpp"
#include "families.hpp"
#include "gmsh_session.hpp"
#include "grids.hpp"
#include "particle_file.hpp"
#include "plate_geometry.hpp"

namespace pd::test_support {

// Spacing `dx` [m], every horizon `delta` [m], partial volumes by
// `quadrature`; with `boundary_sets`, the mesher's sets (left, hole, ...).
inline ParticleSet c1_plate_nbnug(double dx, double delta, Quadrature quadrature, bool boundary_sets = false) {
  GmshSession session;
  const auto geometry = load_plate_geometry(session, std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo", 1e-3, dx);
  GridReport report;
  auto p = build_grid(session, geometry, {GridKind::nbnug, dx, delta}, report);
  sort_particles_spatially(p);
  p.horizon_nominal = delta;
  for (auto& h : p.horizon) h = delta;
  build_families(p, quadrature);
  if (boundary_sets) add_boundary_sets(p, geometry, delta);
  return p;
}

}  // namespace pd::test_support
