// A refinement region end to end, as a user runs it: pd-mesh --refine-region
// (with and without --horizon-smoothing), a dynamic scene with
// model.dual_horizon, pd-solve; pd-post draws the file.
//
// Reference: energy balance (theory.md Secs. 4.3-4.4 and 6.2): dual-horizon
// PMB forces derive from an energy, so for an elastic strip pulled by
// prescribed velocities kinetic + strain energy equal the external work
// (docs/formats.md: to within 1 %, the same bound as for one horizon).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "pd_mesh_run.hpp"

namespace fs = std::filesystem;

namespace {

using namespace pd::test_support;

}  // namespace

TEST_CASE("a refined strip runs with dual horizons and keeps its energy balance",
          "[mesher][specimens][refinement]") {
  const auto dir = fs::path(PD_TEST_TMPDIR) / "refinement_scene";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto geo = (dir / "strip.geo").string();
  std::ofstream(geo) << rectangle_geo(20, 10);
  const auto pdp = (dir / "strip.pdp").string();
  // The horizon jumps at x = 10 mm, or ramps over 1 mm = 8 fine spacings (theory.md Sec. 7).
  const std::string smoothing = GENERATE(as<std::string>{}, "", " --horizon-smoothing 1mm");
  INFO("pd-mesh" << smoothing);
  REQUIRE(run_shell(std::string(PD_MESH_EXE) + " " + geo +
              " --spacing 0.5mm --horizon-factor 3 --refine-region 10mm,0mm,20mm,10mm --refine-factor 4" + smoothing +
              " -o " + pdp + " > " + (dir / "mesh.txt").string() + " 2>&1") == 0);
  const auto scene = [&](const std::string& model) {
    const auto path = (dir / "strip.toml").string();
    std::ofstream(path) << "particles = \"" << pdp << "\"\n"
                        << "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\nfracture_energy = 200\n"
                           "thickness = 1e-3\n"
                        << model
                        << "[effects]\ndamage = false\n"
                           "[time]\nstep = \"auto\"\nend = 4e-6\n"
                           "[[loads]]\nset = \"left\"\ntype = \"velocity\"\nx = -0.5\nramp_time = 1e-6\n"
                           "[[loads]]\nset = \"right\"\ntype = \"velocity\"\nx = 0.5\nramp_time = 1e-6\n";
    return path;
  };
  const auto out = (dir / "out").string(), log = (dir / "solve.txt").string();

  SECTION("without model.dual_horizon the file is refused, naming it and the key") {
    CHECK(run_shell(std::string(PD_SOLVE_EXE) + " " + scene("") + " -o " + out + " > " + log + " 2>&1") != 0);
    const auto text = file_text(log);
    CHECK_THAT(text, Catch::Contains(pdp + ": particles have different horizons (0.375 mm to 1.5 mm); set "
                                           "model.dual_horizon = true"));
  }
  SECTION("with dual horizons") {
    const int status = run_shell(std::string(PD_SOLVE_EXE) + " " + scene("[model]\ndual_horizon = true\n") + " -o " + out +
                           " > " + log + " 2>&1");
    INFO(file_text(log));
    REQUIRE(status == 0);
    CHECK_THAT(file_text(log), Catch::Contains("horizons dual_horizon"));
    CHECK_THAT(file_text(out + "/summary.json"), Catch::Contains("\"horizons\": \"dual_horizon\""));
    const auto energy = out + "/energy.csv";
    const double kinetic = last_csv_value(energy, "kinetic_J"), strain = last_csv_value(energy, "strain_J"),
                 work = last_csv_value(energy, "external_work_J");
    INFO("kinetic " << kinetic << " J, strain " << strain << " J, work " << work << " J");
    CHECK(strain > 0.1 * work);  // the strip really deformed
    CHECK(std::fabs(kinetic + strain - work) < 0.01 * work);
    // pd-post draws the particle file (its crack pictures need a crack, which this elastic run has not).
    CHECK(run_shell(std::string(PD_POST_EXE) + " --particles " + pdp + " -o " + (dir / "pictures").string() + " > " +
              (dir / "post.txt").string() + " 2>&1") == 0);
    CHECK(fs::exists(dir / "pictures" / "strip_volume.png"));
    CHECK(fs::exists(dir / "pictures" / "strip_horizon.png"));  // two resolution levels: two horizons
  }
}
