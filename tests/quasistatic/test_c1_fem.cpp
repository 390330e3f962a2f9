// Case C1 (docs/validation.md): PD quasi-static displacements against the
// CalculiX plane-stress reference on the three grids.
//
// CI resolution: dx = 0.2 mm, m = 4 (delta = 0.8 mm), about 8,700 particles
// (the case itself is dx = 0.05 mm, delta = 0.2 mm: bench/accuracy_cost.sh and
// pd-validate-c1 run it). FEM: 6-node triangles, h = 0.1 mm at the hole.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "c1_comparison.hpp"
#include "hole_stress.hpp"
#include "plate_grid.hpp"
#include "support.hpp"

using namespace pd::validation;

namespace {

struct GridResult {
  C1Errors errors;
  double pd_reaction = 0, fem_reaction = 0;
};

GridResult c1_errors(pd::GridKind grid, double spacing, double horizon, const std::string& folder) {
  pd::PlateGeometry geometry;
  const auto particles = make_plate_grid({PD_C1_GEOMETRY, grid, spacing, horizon, pd::Quadrature::analytic}, &geometry);
  const C1Material material;
  const auto fem = solve_c1_fem(geometry, material, horizon, 1e-4, folder, "c1");
  PdOptions options;  // surface correction on, as in the paper
  options.tolerance = 1e-8;
  const auto pd = solve_c1_pd(particles, material, options);
  const auto at = fem_at_particles(fem, particles);
  GridResult r;
  r.errors = compare_with_fem(particles, pd, at, 0.01, 0.01, 0.004, 2 * horizon);
  r.pd_reaction = pd.reaction_x;
  r.fem_reaction = fem.solution.right_reaction_x;
  return r;
}

}  // namespace

// Reference: FEM (CalculiX, plane stress, nu = 1/3, same clamped strips).
// At this resolution the difference between the grids is small next to the
// error every grid shares (the nonlocal boundary layer, about one horizon deep,
// at the free edges, the hole and the strips). With the directional surface
// correction (docs/theory.md, surface correction) the measured largest
// difference near the hole is 0.0118 U on NB-NUG and 0.0114 U on the free
// grid, overall 0.0289 U and 0.0293 U, RMS 0.0115 U and 0.0102 U: the grids do
// not differ in a way this test could order (docs/validation.md, C1). Both are
// held to the bound.
//
// Bound: the PD solution differs from the local elastic one by O(delta / L)
// near boundaries (first order, see the next test). At delta = 0.8 mm we allow
// max |du_x| <= 0.04 U and RMS <= 0.015 U on either grid (measured above), and
// the reaction force within 3 % (measured -2.5 % and -2.3 %).
TEST_CASE("C1: NB-NUG and the free grid are within the stated bound of FEM", "[quasistatic][c1]") {
  const auto folder = pd::quasistatic::test::fresh_folder("c1_ordering");
  const auto nbnug = c1_errors(pd::GridKind::nbnug, 2e-4, 8e-4, folder);
  const auto free = c1_errors(pd::GridKind::free, 2e-4, 8e-4, folder);
  INFO("NB-NUG: max " << nbnug.errors.ux.max_rel << " RMS " << nbnug.errors.ux.rms_rel << " near hole "
                      << nbnug.errors.ux_near_hole.max_rel << " uy max " << nbnug.errors.uy.max_rel << " reaction "
                      << nbnug.pd_reaction / nbnug.fem_reaction << "; free: max " << free.errors.ux.max_rel << " RMS "
                      << free.errors.ux.rms_rel << " near hole " << free.errors.ux_near_hole.max_rel << " reaction "
                      << free.pd_reaction / free.fem_reaction);
  for (const auto* grid : {&nbnug, &free}) {
    CHECK(grid->errors.ux.max_rel < 0.04);
    CHECK(grid->errors.ux.rms_rel < 0.015);
    CHECK(grid->errors.uy.max_rel < 0.04);
    CHECK(grid->pd_reaction == Approx(grid->fem_reaction).epsilon(0.03));
  }
}

// Reference: FEM at each clamp width. Halving the horizon (dx 0.2 -> 0.1 mm,
// m = 4) must roughly halve the NB-NUG difference (first-order nonlocal error):
// measured 0.0289 U -> 0.0146 U (ratio 0.51); we require a ratio below 0.65.
TEST_CASE("C1: the NB-NUG difference from FEM falls in proportion to the horizon", "[quasistatic][c1]") {
  const auto folder = pd::quasistatic::test::fresh_folder("c1_convergence");
  const auto coarse = c1_errors(pd::GridKind::nbnug, 2e-4, 8e-4, folder + "/coarse");
  const auto fine = c1_errors(pd::GridKind::nbnug, 1e-4, 4e-4, folder + "/fine");
  INFO("max |du_x| / U: " << coarse.errors.ux.max_rel << " -> " << fine.errors.ux.max_rel);
  CHECK(fine.errors.ux.max_rel < 0.65 * coarse.errors.ux.max_rel);
  CHECK(fine.errors.ux.rms_rel < 0.65 * coarse.errors.ux.rms_rel);
}

// OSB at nu = 1/3 (plane stress) against PMB on C1, on the uniform grid at
// the CI resolution (dx = 0.2 mm, m = 4), surface correction on for both.
//
// Why they may differ at all: at nu = 1/3 the OSB dilatation coefficient a
// vanishes and its bond sum has the PMB micromodulus and the same surface
// correction factors (theory.md Secs. 5.2, 5.7), so the two share every
// constant and their dynamic forces agree particle by particle
// (tests/solver/test_osb.cpp). What differs is the quasi-static machinery:
// PMB minimises the energy of its symmetrised table with exact Hessian
// products (theory.md Secs. 4.7, 4.8), OSB its state-based energy with its
// own gradient loop and Hessian products by differences (Sec. 5.6), each to
// the tolerance 1e-8. On the uniform grid (the hole a staircase of squares)
// the two equilibria must then be one: any difference beyond the tolerance
// is an error of one path. (The NB-NUG and free grids:
// test_osb_quasi_static.cpp.)
//
// Without surface correction the two models are one in the bulk and at the
// edges alike (theory.md Sec. 5.2), so the two equilibria must agree to what
// the minimisations leave (relative residual 1e-8): 1e-5 U. With their own
// surface corrections they differ within a horizon of the boundary: PMB's
// scalar energy-method factors against OSB's distortion and dilatation
// factors (theory.md Secs. 3 and 5.7). That difference is part of what PD at
// this resolution does not resolve of the continuum, so the bound "the same
// within the discretisation error" is PMB's largest difference from the
// CalculiX reference on the same particles (0.03 U, docs/validation.md, C1;
// it halves with the horizon, the previous test), and OSB must be no farther
// from the reference than PMB (10 % margin). Measured: PMB - FEM 0.0289 U
// (u_x) and 0.0192 U (u_y); corrected OSB - FEM 0.0286 and 0.0174 U;
// corrected OSB - PMB 0.0107 and 0.0048 U, reactions 0.35 % apart.
TEST_CASE("C1: OSB at nu = 1/3 and PMB give the same displacements within the discretisation error",
          "[quasistatic][c1][osb]") {
  const auto folder = pd::quasistatic::test::fresh_folder("c1_osb_pmb");
  const double spacing = 2e-4, horizon = 8e-4;
  pd::PlateGeometry geometry;
  const auto particles =
      make_plate_grid({PD_C1_GEOMETRY, pd::GridKind::uniform, spacing, horizon, pd::Quadrature::analytic}, &geometry);
  const C1Material material;
  const auto fem = solve_c1_fem(geometry, material, horizon, 1e-4, folder, "c1");
  const auto at = fem_at_particles(fem, particles);
  PdOptions pmb_options;
  pmb_options.tolerance = 1e-8;
  auto osb_options = pmb_options;
  osb_options.model = pd::solver::ModelType::osb;
  REQUIRE(material.poisson_ratio == 1.0 / 3.0);  // the FEM's, and OSB's
  // OSB against PMB: the PMB field as the reference of the same comparison
  // (differences divided by U, u_y after removing the mean difference).
  const auto difference = [&](const PdSolution& osb, const PdSolution& pmb) {
    return compare_with_fem(particles, osb, FemAtParticles{pmb.ux, pmb.uy}, 0.01, 0.01, 0.004, 2 * horizon);
  };
  SECTION("without surface correction: one equilibrium") {
    pmb_options.surface_correction = osb_options.surface_correction = false;
    const auto pmb = solve_c1_pd(particles, material, pmb_options);
    const auto osb = solve_c1_pd(particles, material, osb_options);
    const auto between = difference(osb, pmb);
    INFO("OSB - PMB: u_x max " << between.ux.max_rel << " U, u_y max " << between.uy.max_rel << " U; iterations "
                               << pmb.iterations << ", " << osb.iterations);
    CHECK(between.ux.max_rel < 1e-5);
    CHECK(between.uy.max_rel < 1e-5);
    CHECK(osb.reaction_x == Approx(pmb.reaction_x).epsilon(1e-5));
  }
  SECTION("each with its own surface correction: within the discretisation error") {
    const auto pmb = solve_c1_pd(particles, material, pmb_options);
    const auto osb = solve_c1_pd(particles, material, osb_options);
    const auto pmb_error = compare_with_fem(particles, pmb, at, 0.01, 0.01, 0.004, 2 * horizon);
    const auto osb_error = compare_with_fem(particles, osb, at, 0.01, 0.01, 0.004, 2 * horizon);
    const auto between = difference(osb, pmb);
    const double discretisation = std::max(pmb_error.ux.max_rel, pmb_error.uy.max_rel);
    INFO("PMB - FEM: u_x max " << pmb_error.ux.max_rel << " U, u_y max " << pmb_error.uy.max_rel
                               << " U; OSB - FEM: u_x max " << osb_error.ux.max_rel << " U, u_y max "
                               << osb_error.uy.max_rel << " U; OSB - PMB: u_x max " << between.ux.max_rel << " U (RMS "
                               << between.ux.rms_rel << "), u_y max " << between.uy.max_rel << " U; reactions PMB "
                               << pmb.reaction_x << ", OSB " << osb.reaction_x << " N/m; iterations " << pmb.iterations
                               << ", " << osb.iterations);
    REQUIRE(discretisation > 0.01);  // the error the bound is made of
    CHECK(between.ux.max_rel < discretisation);
    CHECK(between.uy.max_rel < discretisation);
    CHECK(osb_error.ux.max_rel < 1.1 * pmb_error.ux.max_rel);
    CHECK(osb_error.uy.max_rel < 1.1 * pmb_error.uy.max_rel);
    CHECK(osb.reaction_x == Approx(pmb.reaction_x).epsilon(0.01));
  }
}

// Reference: FEM (CalculiX, plane stress, nu = 1/3) with u_x = -/+ U on its
// left and right edge nodes, the counterpart of PD's loading layers beyond
// those edges (docs/scenes.md, "Which loading to use when"); NB-NUG at the CI
// resolution. Displacements: the same first-order nonlocal error as with the
// strips (first test), so the same bounds for u_x (measured 0.029 U largest,
// 0.0097 U RMS; u_y is left out: 0.048 U at the loaded corners, where the
// rigid layer meets a free edge); the reaction is low with layers
// (the grips slip by a fraction of a horizon, docs/scenes.md): measured
// -1.9 %, required between -6 % and -1 %.
// Stress at the hole (docs/theory.md Sec. 10, docs/validation.md "C1: stress
// at the hole per grid"): over the first ring of particles the PD hoop stress
// from the family's displacement gradient and the PD strain energy density
// must follow the FEM's at the same points within the smoothing of a
// one-sided horizon: measured RMS differences 0.073 (hoop) and 0.016 (SED)
// of the FEM's peak on the ring of 124 particles; required below 0.1 and 0.03.
TEST_CASE("C1 with loading layers: displacements and the stress at the hole against the edge-loaded FEM",
          "[quasistatic][c1]") {
  const auto folder = pd::quasistatic::test::fresh_folder("c1_layers");
  const double spacing = 2e-4, horizon = 8e-4;
  pd::PlateGeometry geometry;
  const auto particles = c1_particles({PD_C1_GEOMETRY, pd::GridKind::nbnug, spacing, horizon, pd::Quadrature::analytic},
                                      C1Loading::layers, &geometry);
  const C1Material material;
  const auto fem = solve_c1_fem(geometry, material, 0.0, 1e-4, folder, "c1_edges");
  PdOptions options;
  options.tolerance = 1e-8;
  options.loading = C1Loading::layers;
  const auto pd_all = solve_c1_pd(particles, material, options);
  const auto plate = plate_only(particles, pd_all, geometry);
  REQUIRE(plate.particles.size() < particles.size());  // the layers are left out of the comparison
  const auto errors = compare_with_fem(plate.particles, plate.pd, fem_at_particles(fem, plate.particles), 0.01, 0.01,
                                       0.004, 2 * horizon);
  const double reaction = pd_all.reaction_x / fem.solution.right_reaction_x - 1;
  const auto ring = hole_stress_samples(particles, pd_all, {0.01, 0.01, 0.004}, spacing, {&fem}, material.youngs_modulus,
                                        1.0 / 3.0);
  double hoop_peak = 0, sed_peak = 0, hoop_sum = 0, sed_sum = 0;
  for (const auto& s : ring) {
    hoop_peak = std::max(hoop_peak, std::fabs(s.fem_hoop[0]));
    sed_peak = std::max(sed_peak, s.fem_energy_density[0]);
    hoop_sum += std::pow(s.pd_hoop - s.fem_hoop[0], 2);
    sed_sum += std::pow(s.pd_energy_density - s.fem_energy_density[0], 2);
  }
  const double hoop_rms = std::sqrt(hoop_sum / ring.size()) / hoop_peak;
  const double sed_rms = std::sqrt(sed_sum / ring.size()) / sed_peak;
  INFO("u_x max " << errors.ux.max_rel << " RMS " << errors.ux.rms_rel << ", u_y max " << errors.uy.max_rel
                  << "; reaction PD / FEM - 1 = " << reaction << "; ring of " << ring.size() << " particles: hoop RMS "
                  << hoop_rms << ", SED RMS " << sed_rms << " of the FEM peak");
  REQUIRE(ring.size() > 100);
  CHECK(errors.ux.max_rel < 0.04);
  CHECK(errors.ux.rms_rel < 0.015);
  CHECK(reaction < -0.01);
  CHECK(reaction > -0.06);
  CHECK(hoop_rms < 0.1);
  CHECK(sed_rms < 0.03);
}
