// The FEM reference itself (validation/): CalculiX runs on gmsh meshes.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "c1_comparison.hpp"
#include "calculix.hpp"
#include "error.hpp"
#include "fem_mesh.hpp"
#include "gmsh_session.hpp"
#include "plate_grid.hpp"
#include "support.hpp"

using namespace pd::validation;

namespace {

// Largest deviation from the exact homogeneous uniaxial plane-stress field
// u_x = -U + eps (x - xmin), u_y = -nu eps (y - y_pin), divided by U, over
// nodes farther than 5 mm from the hole.
double uniaxial_deviation(const std::string& folder, double section_thickness) {
  const auto fem = pd::quasistatic::test::tiny_hole_fem(folder, 0.004e-3, "tiny", section_thickness);
  const auto& mesh = fem.mesh;
  const auto& s = fem.solution;
  const double U = 1e-7, eps = 2 * U / 0.02, nu = 1.0 / 3.0;
  // The pinned node: nearest to the middle of the left edge (calculix.cpp), u_y = 0 there.
  std::size_t pin = 0;
  for (std::size_t k = 0; k < mesh.x.size(); ++k)
    if (std::hypot(mesh.x[k], mesh.y[k] - 0.01) < std::hypot(mesh.x[pin], mesh.y[pin] - 0.01)) pin = k;
  double largest = 0;
  for (std::size_t k = 0; k < mesh.x.size(); ++k) {
    if (std::hypot(mesh.x[k] - 0.01, mesh.y[k] - 0.01) < 5e-3) continue;
    largest = std::max(largest, std::fabs(s.ux[k] - (-U + eps * mesh.x[k])));
    largest = std::max(largest, std::fabs(s.uy[k] - (-nu * eps * (mesh.y[k] - mesh.y[pin]))));
  }
  return largest / U;
}

}  // namespace

// Reference: the exact homogeneous plane-stress solution (a tiny hole does not
// disturb the far field).
TEST_CASE("CalculiX reproduces the uniaxial plane-stress field of a plate with a tiny hole", "[quasistatic][fem]") {
  const auto folder = pd::quasistatic::test::fresh_folder("tiny_hole");
  const double deviation = uniaxial_deviation(folder, 1e-6);
  INFO("deviation / U with a 1e-6 m section: " << deviation);
  CHECK(deviation < 1e-5);
}

// Reference: plane stress does not depend on the thickness. ccx builds one layer
// of 3D elements as deep as the section: for a thin section (1e-6 or 1e-4 m) the
// reaction per metre of thickness is the same, for a section as thick as the
// plate is wide (1 m for a 20 mm plate) the layer is no longer in plane stress
// around the hole and the plate comes out stiffer (by about 2 %, docs/validation.md).
TEST_CASE("CalculiX needs a thin section for plane stress", "[quasistatic][fem]") {
  const auto folder = pd::quasistatic::test::fresh_folder("thickness");
  pd::PlateGeometry plate;
  make_plate_grid({PD_C1_GEOMETRY, pd::GridKind::uniform, 1e-3, 3e-3, pd::Quadrature::full}, &plate);
  FemMeshOptions mesh_options;
  mesh_options.hole_size = 2e-4;
  const auto mesh = write_fem_mesh(plate, mesh_options, folder + "/mesh.inp");
  const auto reaction = [&](double thickness, const std::string& job) {
    return run_calculix(mesh, plate, FemLoadCase{3.24e9, 1.0 / 3.0, 0, -1e-7, 1e-7, thickness}, job).right_reaction_x;
  };
  const double thin = reaction(1e-6, "thin"), thinner = reaction(1e-4, "thinner"), thick = reaction(1.0, "thick");
  INFO("reaction per metre [N/m]: 1e-6 m " << thin << ", 1e-4 m " << thinner << ", 1 m " << thick);
  CHECK(thinner == Approx(thin).epsilon(1e-5));
  CHECK(thick > 1.005 * thin);
}

TEST_CASE("a missing ccx is a clear error", "[quasistatic][fem]") {
  const auto folder = pd::quasistatic::test::fresh_folder("no_ccx");
  const auto plate = pd::quasistatic::test::tiny_hole_plate(folder);
  FemMeshOptions mesh_options;
  mesh_options.hole_size = 0.004e-3;
  mesh_options.far_size = 2e-3;
  const auto mesh = write_fem_mesh(plate, mesh_options, folder + "/mesh.inp");
  const std::string path = std::getenv("PATH");
  ::setenv("PATH", folder.c_str(), 1);  // a folder without ccx
  const bool available = calculix_available();
  std::string message;
  try {
    run_calculix(mesh, plate, FemLoadCase{3.24e9, 1.0 / 3.0, 0, -1e-7, 1e-7}, "job");
  } catch (const pd::Error& e) {
    message = e.what();
  }
  ::setenv("PATH", path.c_str(), 1);
  CHECK_FALSE(available);
  CHECK_THAT(message, Catch::Contains("job.inp") && Catch::Contains("'ccx' is not on the PATH") &&
                          Catch::Contains("calculix-ccx"));
}

// A ccx that fails is named by how it ended, as a shell would say it
// (before 7 December 2026 by std::system's raw status: "ccx failed (exit
// status 768)" for an exit of 3, "exit status 9" for a kill).
TEST_CASE("a failing ccx is named by its exit status or the signal that killed it", "[quasistatic][fem]") {
  const auto folder = pd::quasistatic::test::fresh_folder("failing_ccx");
  const auto plate = pd::quasistatic::test::tiny_hole_plate(folder);
  FemMeshOptions mesh_options;
  mesh_options.hole_size = 0.004e-3;
  mesh_options.far_size = 2e-3;
  const auto mesh = write_fem_mesh(plate, mesh_options, folder + "/mesh.inp");
  std::filesystem::create_directories(folder + "/bin");
  const std::string path = std::getenv("PATH");
  ::setenv("PATH", (folder + "/bin:" + path).c_str(), 1);
  const auto message_of = [&](const std::string& script) {
    std::ofstream(folder + "/bin/ccx") << "#!/bin/sh\necho ' *ERROR made up'\n" << script << "\n";
    std::filesystem::permissions(folder + "/bin/ccx", std::filesystem::perms::owner_all);
    std::string message;
    try {
      run_calculix(mesh, plate, FemLoadCase{3.24e9, 1.0 / 3.0, 0, -1e-7, 1e-7}, "job");
    } catch (const pd::Error& e) {
      message = e.what();
    }
    return message;
  };
  const std::string exited = message_of("exit 3"), killed = message_of("kill -9 $$");
  ::setenv("PATH", path.c_str(), 1);
  CHECK(exited == folder + "/job.inp: ccx exited with status 3; end of " + folder + "/job.log:\n   *ERROR made up");
  CHECK_THAT(killed, Catch::StartsWith(folder + "/job.inp: ccx was killed by signal 9; end of " + folder + "/job.log:"));
  CHECK(ccx_status_text(3 << 8) == "ccx exited with status 3");
  CHECK(ccx_status_text(9) == "ccx was killed by signal 9");
}

// Reference: the FEM solution itself, at twice the resolution. The C1 tests
// below use h = 0.1 mm at the hole; halving h must change the displacements at
// the particles by far less than the PD - FEM differences they measure (>= 1e-2 U)
// and than the differences between grids (>= 1e-3 U near the hole).
TEST_CASE("the C1 FEM reference is converged: halving the element size changes little", "[quasistatic][fem]") {
  const auto folder = pd::quasistatic::test::fresh_folder("fem_refinement");
  pd::PlateGeometry geometry;
  const auto particles =
      make_plate_grid({PD_C1_GEOMETRY, pd::GridKind::nbnug, 2e-4, 8e-4, pd::Quadrature::analytic}, &geometry);
  const C1Material material;
  const auto coarse = solve_c1_fem(geometry, material, 8e-4, 1e-4, folder, "coarse");
  const auto fine = solve_c1_fem(geometry, material, 8e-4, 5e-5, folder, "fine");
  const auto a = fem_at_particles(coarse, particles), b = fem_at_particles(fine, particles);
  double dux = 0, duy = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    dux = std::max(dux, std::fabs(a.ux[i] - b.ux[i]));
    duy = std::max(duy, std::fabs((a.uy[i] - a.uy[0]) - (b.uy[i] - b.uy[0])));
  }
  const double U = material.edge_displacement;
  INFO("max |du_x| / U = " << dux / U << ", max |du_y| / U = " << duy / U);
  // Measured 1.8e-4 and 2.6e-4: the largest changes sit at the ends of the clamp
  // lines on the free edges (singular points), far below the PD differences.
  CHECK(dux / U < 5e-4);
  CHECK(duy / U < 5e-4);
  CHECK(coarse.solution.right_reaction_x == Approx(fine.solution.right_reaction_x).epsilon(3e-4));
  // Equilibrium of the FEM solution: the two strips carry opposite forces.
  CHECK(coarse.solution.left_reaction_x == Approx(-coarse.solution.right_reaction_x).epsilon(1e-6));
}
