// Damage of a run against a reference run's crack (post/crack_comparison.hpp):
// synthetic runs whose damaged particles are known by construction.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "post_pipeline.hpp"
#include "synthetic_output.hpp"

using namespace pd::post;
using namespace pd::post::test;
namespace fs = std::filesystem;

namespace {
constexpr double dx = 0.1e-3, v = 600.0;
// A straight crack along the row of centres at y = 5.05 mm, from x = 0 to 15 mm.
double straight_crack(double x, double y, double row_y) {
  return std::abs(y - row_y) < 0.5 * dx && x < 15e-3 ? x / v : -1;
}
}  // namespace

TEST_CASE("damage away from the reference run's crack is counted, damage beside it is not", "[comparison]") {
  // Reference: the straight crack. Run: the same crack one row higher (0.1 mm
  // away, inside any band of 0.5 mm) plus a spurious row of damage at
  // y = 1.05 mm for 2 mm <= x < 4 mm: 20 particles of 0.1 mm x 0.1 mm, 4 mm
  // from the reference crack. Expected by construction: 20 outside,
  // 2e-7 m^2, out of 150 + 20 damaged.
  const auto lattice = make_lattice(20e-3, 10e-3, dx);
  const auto reference = fresh_dir("comparison_reference");
  write_arrival_output(reference, lattice, [](double x, double y) { return straight_crack(x, y, 5.05e-3); }, 40e-6);
  const auto run = fresh_dir("comparison_run");
  write_arrival_output(run, lattice, [](double x, double y) {
    if (std::abs(y - 1.05e-3) < 0.5 * dx && x > 2e-3 && x < 4e-3) return 10e-6;
    return straight_crack(x, y, 5.15e-3);
  }, 40e-6);

  PostOptions o;
  o.outdir = run;
  o.reference_dir = reference;
  o.band = 0.5e-3;
  const auto r = run_post(o);
  REQUIRE(r.comparison);
  CHECK(r.comparison->reference_damaged == 150);
  CHECK(r.comparison->damaged == 170);
  CHECK(r.comparison->outside == 20);
  CHECK(r.comparison->area_outside == Approx(20 * dx * dx).epsilon(1e-9));
  std::stringstream summary;
  summary << std::ifstream(r.postdir + "/summary.json").rdbuf();
  CHECK(summary.str().find("\"damaged_outside_band\": 20") != std::string::npos);

  // A band wider than the 4 mm to the spurious row takes it in.
  o.band = 4.5e-3;
  CHECK(analyse(o).comparison->outside == 0);
  // The reference against a copy of itself (the same damage in another
  // folder; its own folder is refused): nothing outside.
  const auto copy = fresh_dir("comparison_reference_copy");
  fs::copy(reference, copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  o.outdir = copy;
  o.band = 0;  // two horizons
  CHECK(analyse(o).comparison->outside == 0);
  // Levels outside (0, 1] are refused.
  o.damage_level = 0;
  CHECK_THROWS_WITH(analyse(o), Catch::Contains("--damage-level"));
}
