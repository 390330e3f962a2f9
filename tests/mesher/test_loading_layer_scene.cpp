// A loading layer end to end, as a user runs it: pd-mesh --loading-layer, a
// scene file that loads the layer's sets with a displacement, pd-solve.
//
// Reference: plane stress, nu = 1/3, free long edges: ends moved by -/+U give
// the reaction E (2U/L) W h (docs/scenes.md, "Which loading to use when", has
// the measured grip errors: rigid layers a little soft, in-body strips stiff
// by about 2 delta / L); for a linear elastic body loaded by prescribed
// displacements the strain energy is half the work of the reactions,
// (R_left (-U) + R_right U) / 2 = R_right U here.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pd_mesh_run.hpp"

namespace fs = std::filesystem;

namespace {

using namespace pd::test_support;

}  // namespace

TEST_CASE("a scene pulls a strip through its loading layers", "[mesher][specimens][loading_layer]") {
  const auto dir = fs::path(PD_TEST_TMPDIR) / "loading_layer_scene";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto geo = (dir / "strip.geo").string();
  std::ofstream(geo) << rectangle_geo(20, 10);
  const auto pdp = (dir / "strip.pdp").string();
  REQUIRE(run_shell(std::string(PD_MESH_EXE) + " " + geo + " --spacing 0.5mm --horizon 1.5mm --loading-layer left,right -o " +
              pdp + " > " + (dir / "mesh.txt").string() + " 2>&1") == 0);
  const double e = 3.24e9, u = 1e-6, length = 20e-3, width = 10e-3, thickness = 1e-3;
  const auto scene = [&](const std::string& left, const std::string& right) {
    const auto path = (dir / (left + ".toml")).string();
    std::ofstream(path) << "particles = \"" << pdp << "\"\n"
                        << "[material]\nyoungs_modulus = 3.24e9\nfracture_energy = 200\nthickness = 1e-3\n"
                           "[effects]\ndamage = false\nsurface_correction = true\n"
                           "[quasi_static]\nload_factors = [1.0]\ntolerance = 1e-10\nmax_iterations = 100000\n"
                           "[[loads]]\nset = \"" << left << "\"\ntype = \"displacement\"\nx = -1e-6\n"
                           "[[loads]]\nset = \"" << right << "\"\ntype = \"displacement\"\nx = 1e-6\n";
    return path;
  };
  const auto solve = [&](const std::string& left, const std::string& right) {
    const auto out = (dir / ("out_" + left)).string();
    const auto log = (dir / ("solve_" + left + ".txt")).string();
    const int status = run_shell(std::string(PD_SOLVE_EXE) + " " + scene(left, right) + " -o " + out + " > " + log + " 2>&1");
    INFO("pd-solve log: " << log);
    REQUIRE(status == 0);
    return out + "/load_steps.csv";
  };
  const auto layer_csv = solve("loading_layer_left", "loading_layer_right");
  const auto strip_csv = solve("left", "right");
  const double expected = e * (2 * u / length) * width * thickness;
  const double layer = last_csv_value(layer_csv, "loading_layer_right_reaction_x_N");
  const double strip = last_csv_value(strip_csv, "right_reaction_x_N");
  const double energy = last_csv_value(layer_csv, "strain_energy_J");
  INFO("reaction / (E 2U/L W h) - 1: layers " << layer / expected - 1 << ", in-body strips " << strip / expected - 1
                                              << "; strain energy / (R U) - 1 " << energy / (layer * u) - 1);
  // delta / L = 0.075 (dx 0.5 mm, m = 3): measured layers -3.8 %, strips +12.9 %.
  CHECK(strip / expected - 1 > 0.05);
  CHECK(layer / expected - 1 < 0);
  CHECK(std::fabs(layer / expected - 1) < 0.5 * (strip / expected - 1));
  // The totals include the layers' share of the bonds, so the balance holds.
  CHECK(energy == Approx(layer * u).epsilon(1e-3));
}
