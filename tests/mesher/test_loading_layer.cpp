// pd-mesh --loading-layer (docs/mesher.md, "Loading layers"): rows of lattice
// squares outside the plate beyond the named sides, bonded to the body like
// any particle, each layer in a set of its own; the plate's own sets and the
// bonds cut by notches stay as without layers.
//
// References: the lattice (squares of dx^2 on the plate's lattice, counted by
// hand from the geometry), the disk area pi delta^2 that a particle's
// neighbourhood covers when its horizon lies in the material (docs/theory.md
// Sec. 2.2), and closed-form segment-rectangle clipping for the notch.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <utility>

#include "particle_file.hpp"
#include "pd_mesh_run.hpp"

namespace fs = std::filesystem;

namespace {

using namespace pd::test_support;

// 20 x 20 mm with a slot 1 mm wide and 6 mm deep cut down from the top edge
// (faces on the 0.5 mm lattice): the top side is two straight curves.
const std::string slotted =
    "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0}; Point(4) = {10.5, 20, 0};\n"
    "Point(5) = {10.5, 14, 0}; Point(6) = {9.5, 14, 0}; Point(7) = {9.5, 20, 0}; Point(8) = {0, 20, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};\n"
    "Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8}; Plane Surface(1) = {1};\n";

// True if the open segment a-b meets the open rectangle (Liang-Barsky clipping).
bool segment_meets_box(double ax, double ay, double bx, double by, double x0, double y0, double x1, double y1) {
  double t0 = 0, t1 = 1;
  const double dx = bx - ax, dy = by - ay;
  const double p[4] = {-dx, dx, -dy, dy}, q[4] = {ax - x0, x1 - ax, ay - y0, y1 - ay};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] <= 0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
  }
  return t1 - t0 > 1e-9;
}

std::set<std::pair<double, double>> positions(const pd::ParticleSet& p, const std::string& set) {
  std::set<std::pair<double, double>> out;
  for (auto i : p.find_set(set)->particles) out.insert({p.x[i], p.y[i]});
  return out;
}

// V_i + sum_j phi_ij V_j: pi delta^2 for a particle whose disk lies in the material.
double neighbourhood_area(const pd::ParticleSet& p, std::size_t i) {
  double sum = p.volume[i];
  for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) sum += p.partial_volume[k] * p.volume[p.neighbors[k]];
  return sum;
}

}  // namespace

TEST_CASE("pd-mesh --loading-layer adds bonded lattice rows outside the named sides", "[mesher][loading_layer]") {
  const auto geo = write_text_file("slotted.geo", slotted);
  const auto plain_file = mesher_temp("slotted_plain.pdp"), layered_file = mesher_temp("slotted_layers.pdp");
  const double dx = 0.5e-3, delta = 1.5e-3;
  auto run = run_pd_mesh(geo + " --spacing 0.5mm --horizon 1.5mm -o " + plain_file);
  INFO(run.err);
  REQUIRE(run.status == 0);
  run = run_pd_mesh(geo + " --spacing 0.5mm --horizon 1.5mm --loading-layer left,right,top -o " + layered_file);
  INFO(run.err);
  REQUIRE(run.status == 0);
  const auto plain = pd::read_particle_file(plain_file);
  const auto p = pd::read_particle_file(layered_file);  // the reader checks the lattice squares

  // One horizon deep = 3 rows; the top layer spans both parts of the top edge, not the slot's mouth.
  REQUIRE(p.find_set("loading_layer_left") != nullptr);
  REQUIRE(p.find_set("loading_layer_right") != nullptr);
  REQUIRE(p.find_set("loading_layer_top") != nullptr);
  CHECK(p.find_set("loading_layer_bottom") == nullptr);
  CHECK(p.find_set("loading_layer_left")->particles.size() == 3 * 40);
  CHECK(p.find_set("loading_layer_right")->particles.size() == 3 * 40);
  CHECK(p.find_set("loading_layer_top")->particles.size() == 3 * (19 + 19));
  CHECK(p.size() == plain.size() + 3 * (40 + 40 + 38));
  CHECK(p.xmin == Approx(-delta).margin(1e-15));
  CHECK(p.xmax == Approx(20e-3 + delta).margin(1e-15));
  CHECK(p.ymin == plain.ymin);
  CHECK(p.ymax == Approx(20e-3 + delta).margin(1e-15));
  for (const char* name : {"loading_layer_left", "loading_layer_right", "loading_layer_top"})
    for (auto i : p.find_set(name)->particles) {
      CHECK(p.region[i] == 0);
      CHECK(p.volume[i] == Approx(dx * dx).epsilon(1e-12));
      CHECK((p.x[i] < 0 || p.x[i] > 20e-3 || p.y[i] > 20e-3));
      CHECK(!(p.x[i] > 9.5e-3 && p.x[i] < 10.5e-3));  // nothing above the slot's mouth
    }
  // The plate's own sets are the in-body strips, as without layers.
  for (const char* name : {"left", "right", "top", "bottom"}) {
    INFO(name);
    CHECK(positions(p, name) == positions(plain, name));
  }

  // Next to the loaded edges, away from corners and the slot, the layer
  // completes the neighbourhood: pi delta^2 where it was cut without layers.
  const double disk = M_PI * delta * delta;
  std::size_t checked = 0;
  double worst = 0, worst_plain = 1;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool near_left = p.x[i] > 0 && p.x[i] < delta && p.y[i] > 2 * delta && p.y[i] < 20e-3 - 2 * delta;
    const bool near_top = p.y[i] < 20e-3 && p.y[i] > 20e-3 - delta && p.x[i] > 2 * delta && p.x[i] < 9.5e-3 - 2 * delta;
    if (!near_left && !near_top) continue;
    worst = std::max(worst, std::fabs(neighbourhood_area(p, i) / disk - 1));
    ++checked;
  }
  for (std::size_t i = 0; i < plain.size(); ++i)
    if (plain.x[i] < dx && plain.y[i] > 2 * delta && plain.y[i] < 20e-3 - 2 * delta)
      worst_plain = std::min(worst_plain, neighbourhood_area(plain, i) / disk);
  INFO("particles next to loaded edges: " << checked << ", worst |area / (pi delta^2) - 1| " << worst
                                          << "; without layers the edge column has " << worst_plain);
  CHECK(checked == 3 * 28 + 3 * 7);  // rows 3.25 .. 16.75 mm; columns 3.25 .. 6.25 mm
  CHECK(worst < 1e-12);
  CHECK(worst_plain < 0.7);

  // The slot still cuts every bond through it, up through the layer's gap.
  std::size_t through_slot = 0, into_layer = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) {
      const auto j = p.neighbors[k];
      if (segment_meets_box(p.x[i], p.y[i], p.x[j], p.y[j], 9.5e-3, 14e-3, 10.5e-3, 20e-3 + delta)) ++through_slot;
      if (p.x[i] > 0 && p.x[j] < 0) ++into_layer;
    }
  CHECK(through_slot == 0);
  CHECK(into_layer > 0);
}

TEST_CASE("pd-mesh --loading-layer-depth sets the number of rows", "[mesher][loading_layer]") {
  const auto geo = write_text_file("slotted_depth.geo", slotted);
  const auto out = mesher_temp("slotted_depth.pdp");
  // 0.8 mm rounds up to 2 rows of 0.5 mm.
  const auto run = run_pd_mesh(geo + " --spacing 0.5mm --horizon 1.5mm --loading-layer bottom --loading-layer-depth 0.8mm -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  const auto p = pd::read_particle_file(out);
  CHECK(p.find_set("loading_layer_bottom")->particles.size() == 2 * 40);
  CHECK(p.ymin == Approx(-1e-3).margin(1e-15));
  CHECK_THAT(p.provenance, Catch::Contains("\"loading_layer\": [\"bottom\"]"));
}

TEST_CASE("pd-mesh refuses loading layers it cannot build", "[mesher][loading_layer][cli]") {
  const auto geo = write_text_file("slotted_bad.geo", slotted);
  const auto out = mesher_temp("never_layer.pdp");
  const auto expect_failure = [&](const std::string& arguments, const std::string& fragment) {
    fs::remove(out);
    const auto run = run_pd_mesh(arguments + " -o " + out);
    INFO("stderr: " << run.err);
    CHECK(run.status != 0);
    CHECK_THAT(run.err, Catch::Contains(fragment));
    CHECK_FALSE(fs::exists(out));
  };
  const std::string base = geo + " --spacing 0.5mm --horizon 1.5mm";
  expect_failure(base + " --loading-layer front", "--loading-layer: 'front' in 'front' is not an edge");
  expect_failure(base + " --loading-layer top,,left", "--loading-layer: '' in 'top,,left' is not an edge");
  expect_failure(base + " --loading-layer top,top", "the edge 'top' is given twice");
  expect_failure(base + " --loading-layer-depth 1mm", "--loading-layer-depth 1mm needs --loading-layer");
  expect_failure(base + " --loading-layer top --loading-layer-depth 0.2mm", "is less than the spacing");
  expect_failure(base + " --loading-layer top --loading-layer-depth 2", "no unit");
  expect_failure(base + " --loading-layer ''", "--loading-layer: the value is empty (''; an unset shell variable?)");
  // A depth in the wrong unit (1e30 mm; 100000 mm made 4e8 particles until memory ran out).
  expect_failure(base + " --loading-layer left --loading-layer-depth 1e30mm",
                 "--loading-layer-depth 1e30mm is more than 10 horizons (15 mm)");
  // A round plate has no straight side.
  const auto disk = write_text_file("disk.geo", "SetFactory(\"OpenCASCADE\"); Disk(1) = {10, 10, 0, 10};\n");
  expect_failure(disk + " --spacing 0.5mm --horizon 1.5mm --loading-layer top",
                 "has no straight outer curve on the top side");
  // A side whose curve ends off the lattice lines: 9.75 mm on a 0.5 mm lattice.
  const auto off = write_text_file("off_lattice.geo",
                             "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0}; Point(4) = {10.25, 20, 0};\n"
                             "Point(5) = {10.25, 14, 0}; Point(6) = {9.75, 14, 0}; Point(7) = {9.75, 20, 0}; Point(8) = {0, 20, 0};\n"
                             "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};\n"
                             "Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};\n"
                             "Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8}; Plane Surface(1) = {1};\n");
  expect_failure(off + " --spacing 0.5mm --horizon 1.5mm --loading-layer top", "off the lattice lines");
}
