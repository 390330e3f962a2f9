// The Rayleigh speed of the model that ran: plane stress or strain, the
// model's Poisson ratio, and the fallbacks for older or unfinished outputs.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>

#include "post_pipeline.hpp"
#include "rayleigh_speed.hpp"
#include "synthetic_output.hpp"

using namespace pd::post;
using namespace pd::post::test;
using Catch::Matchers::Contains;

namespace {
// Rayleigh's equation squared out, in x = k^2 with a2 = c_s^2 / c_p^2:
// x^3 - 8 x^2 + (24 - 16 a2) x - 16 (1 - a2) = 0, which is -16 (1 - a2) < 0
// at x = 0 and 1 at x = 1. Its root there, halving the interval: the
// polynomial, not the square roots the code evaluates.
double cubic_root(double nu) {
  const double a2 = (1 - 2 * nu) / (2 * (1 - nu));
  double lo = 0, hi = 1;
  for (int i = 0; i < 200; ++i) {
    const double x = 0.5 * (lo + hi);
    (x * x * x - 8 * x * x + (24 - 16 * a2) * x - 16 * (1 - a2) < 0 ? lo : hi) = x;
  }
  return std::sqrt(0.5 * (lo + hi));
}

double straight(double x, double y) {
  if (std::abs(y - 5.05e-3) > 0.101e-3 || x > 15e-3) return -1;
  return x <= 2e-3 ? 0.0 : (x - 2e-3) / 600.0;
}

PostResult analyse_run(const std::string& name, const SyntheticRun& run) {
  const auto dir = fresh_dir(name);
  write_arrival_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), straight, 30e-6, run);
  PostOptions o;
  o.outdir = dir;
  return analyse(o);
}

bool mentions(const std::vector<std::string>& list, const std::string& text) {
  for (const auto& s : list)
    if (s.find(text) != std::string::npos) return true;
  return false;
}
}  // namespace

TEST_CASE("the Rayleigh ratio is the root of Rayleigh's equation", "[rayleigh]") {
  // Poisson solid (nu' = 1/4): k^2 = 2 - 2 / sqrt(3) exactly [Rayleigh 1885].
  CHECK(rayleigh_ratio(0.25) == Approx(std::sqrt(2 - 2 / std::sqrt(3.0))).epsilon(1e-12));
  for (double nu : {-0.5, 0.0, 0.1, 0.2, 1.0 / 3.0, 0.45, 0.499}) {
    INFO("nu' = " << nu);
    CHECK(rayleigh_ratio(nu) == Approx(cubic_root(nu)).epsilon(1e-10));
  }
  // Plane stress sees nu' = nu / (1 + nu): PMB's 1/3 is 1/4 in the plane.
  CHECK(in_plane_poisson_ratio(1.0 / 3.0, Plane::stress) == Approx(0.25).epsilon(1e-15));
  CHECK(in_plane_poisson_ratio(0.25, Plane::strain) == 0.25);
}

TEST_CASE("the Rayleigh speed of PMMA as simulated by PMB", "[rayleigh]") {
  const double k = std::sqrt(2 - 2 / std::sqrt(3.0));
  // Plane stress, nu = 1/3: mu = 3E/8, c_s = sqrt(3 x 3.24e9 / 8 / 1190) = 1010.45 m/s, c_R = 929.0 m/s.
  const auto stress = rayleigh_speed(3.24e9, 1190, 1.0 / 3.0, Plane::stress);
  CHECK(stress.shear_speed == Approx(std::sqrt(3 * 3.24e9 / 8 / 1190)).epsilon(1e-12));
  CHECK(stress.speed == Approx(k * std::sqrt(3 * 3.24e9 / 8 / 1190)).epsilon(1e-12));
  CHECK(stress.speed == Approx(929.0).margin(0.1));
  // Plane strain, nu = 1/4: mu = 2E/5, c_R = 959.5 m/s.
  const auto strain = rayleigh_speed(3.24e9, 1190, 0.25, Plane::strain);
  CHECK(strain.speed == Approx(k * std::sqrt(2 * 3.24e9 / 5 / 1190)).epsilon(1e-12));
}

TEST_CASE("pd-post uses the plane and Poisson ratio of the run, and says where they came from", "[rayleigh]") {
  const double k = std::sqrt(2 - 2 / std::sqrt(3.0));
  SECTION("plane stress PMB: summary.json and the field poisson_ratio") {
    const auto r = analyse_run("rayleigh_stress", SyntheticRun{});
    // Not the material's 0.35 (which would give 938 m/s with the usual approximation).
    CHECK(r.rayleigh_speed == Approx(k * std::sqrt(3 * test_youngs / 8 / test_density)).epsilon(1e-12));
    CHECK(r.model.plane == Plane::stress);
    CHECK(r.model.poisson_ratio == Approx(1.0 / 3.0));
    CHECK_THAT(r.model.plane_source, Contains("summary.json"));
    CHECK_THAT(r.model.poisson_ratio_source, Contains("poisson_ratio"));
    REQUIRE(r.material_rayleigh);  // the material's ratio, for reference
    CHECK(r.material_rayleigh->speed ==
          Approx(std::sqrt(test_youngs / (2 * 1.35) / test_density) * rayleigh_ratio(0.35 / 1.35)).epsilon(1e-12));
    CHECK(r.notes.empty());
  }
  SECTION("plane strain PMB") {
    SyntheticRun run;
    run.plane = "strain";
    run.model_poisson_ratio = 0.25;
    const auto r = analyse_run("rayleigh_strain", run);
    CHECK(r.model.plane == Plane::strain);
    CHECK(r.rayleigh_speed == Approx(k * std::sqrt(2 * test_youngs / 5 / test_density)).epsilon(1e-12));
  }
  SECTION("a state-based model with the material's own ratio, in plane strain") {
    SyntheticRun run;
    run.plane = "strain";
    run.model_poisson_ratio = 0.35;
    const auto r = analyse_run("rayleigh_state_based", run);
    CHECK(r.rayleigh_speed == Approx(std::sqrt(test_youngs / 2.7 / test_density) * cubic_root(0.35)).epsilon(1e-9));
  }
  SECTION("no field poisson_ratio (older outputs): the PMB value of the plane, noted") {
    SyntheticRun run;
    run.plane = "strain";
    run.model_poisson_ratio.reset();
    const auto r = analyse_run("rayleigh_no_field", run);
    CHECK(r.model.poisson_ratio == 0.25);
    CHECK(r.rayleigh_speed == Approx(k * std::sqrt(2 * test_youngs / 5 / test_density)).epsilon(1e-12));
    CHECK(mentions(r.notes, "no field \"poisson_ratio\""));
  }
  SECTION("no summary.json and no field (an unfinished older run): plane stress PMB, noted") {
    SyntheticRun run;
    run.summary = false;
    run.model_poisson_ratio.reset();
    const auto r = analyse_run("rayleigh_nothing", run);
    CHECK(r.model.plane == Plane::stress);
    CHECK(r.model.poisson_ratio == Approx(1.0 / 3.0));
    CHECK(r.rayleigh_speed == Approx(k * std::sqrt(3 * test_youngs / 8 / test_density)).epsilon(1e-12));
    CHECK(mentions(r.notes, "plane stress assumed"));
    CHECK(mentions(r.notes, "no field \"poisson_ratio\""));
  }
  SECTION("the post summary states the speed, the formula and the sources") {
    const auto dir = fresh_dir("rayleigh_summary");
    write_arrival_output(dir, make_lattice(20e-3, 10e-3, 0.1e-3), straight, 30e-6, SyntheticRun{});
    PostOptions o;
    o.outdir = dir;
    run_post(o);
    std::ifstream f(dir + "/post/summary.json");
    std::stringstream text;
    text << f.rdbuf();
    CHECK_THAT(text.str(), Contains("\"formula\": \"c_R = k c_s") && Contains("\"plane\": \"stress\"") &&
                               Contains("\"poisson_ratio\": 0.333333333") && Contains("\"plane_source\""));
  }
}
