// The specimens of geometries/ run end to end at a coarse resolution:
// pd-mesh -> pd-solve -> pd-post, each as a user runs it, with the scene as
// written (only the particle file and the output folder are set on the
// command line). For each specimen it is asserted that
//   1. the grid's area equals the specimen's area in closed form (rectangles,
//      half disks, disks, the fillet's square minus a quarter disk) to 1e-9;
//   2. no bond crosses a void: no bond's segment meets the interior of the
//      notch (a rectangle and its half-disk tip), of a pin hole (a disk) or
//      of the cut-out (rectangles), checked in closed form (Liang-Barsky
//      clipping, distance from a disk's centre);
//   3. pd-solve and pd-post finish (status 0) and write their summaries;
//   4. damage starts where the specimen concentrates stress: the first
//      particle to reach damage 0.35 lies within two horizons of a notch tip
//      (of the re-entrant corner for the L-shaped panel).
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "particle_file.hpp"
#include "../test_commands.hpp"

namespace fs = std::filesystem;

namespace {

using pd::test_support::run_shell;

struct Rectangle {
  double x0, y0, x1, y1;  // mm
};
struct Disk {
  double x, y, r;  // mm
};

// Length of the part of segment a-b inside the open rectangle (Liang-Barsky), mm.
double clipped_length(double ax, double ay, double bx, double by, const Rectangle& r) {
  double t0 = 0, t1 = 1;
  const double d[2] = {bx - ax, by - ay}, lo[2] = {r.x0 - ax, r.y0 - ay}, hi[2] = {r.x1 - ax, r.y1 - ay};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0) {
      if (lo[k] >= 0 || hi[k] <= 0) return 0;
      continue;
    }
    double ta = lo[k] / d[k], tb = hi[k] / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  return t1 > t0 ? (t1 - t0) * std::hypot(d[0], d[1]) : 0;
}

double distance_to_segment(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double t = std::clamp(((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
  return std::hypot(px - ax - t * dx, py - ay - t * dy);
}

// A notch from the plate's edge at x = 0 along y = y_mid, width w, its
// half-disk tip at x = x_tip.
void add_notch(double y_mid, double w, double x_tip, std::vector<Rectangle>& rectangles, std::vector<Disk>& disks) {
  rectangles.push_back({-1, y_mid - w / 2, x_tip - w / 2, y_mid + w / 2});
  disks.push_back({x_tip - w / 2, y_mid, w / 2});
}

struct Specimen {
  std::string name;
  double spacing_mm, horizon_mm;
  double area_mm2;
  std::vector<Rectangle> rectangles;
  std::vector<Disk> disks;
  std::vector<std::pair<double, double>> starts;  // where damage must start (mm)
};

void run_specimen(const Specimen& s) {
  const fs::path work = fs::path(PD_TEST_TMPDIR) / s.name;
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string geometries = PD_GEOMETRY_DIR;
  const std::string pdp = (work / (s.name + ".pdp")).string(), out = (work / "run").string();
  char lengths[128];
  std::snprintf(lengths, sizeof lengths, " --spacing %gmm --horizon %gmm", s.spacing_mm, s.horizon_mm);
  REQUIRE(run_shell(std::string(PD_MESH_EXE) + " " + geometries + "/" + s.name + ".geo" + lengths + " -o " + pdp + " > " +
              (work / "mesh.log").string()) == 0);

  // 1. Area.
  const auto p = pd::read_particle_file(pdp);
  double area = 0;
  for (double v : p.volume) area += v;
  CHECK(std::fabs(area * 1e6 - s.area_mm2) / s.area_mm2 < 1e-9);

  // 2. No bond through a void.
  std::size_t through_void = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto k = p.family_offsets[i]; k < p.family_offsets[i + 1]; ++k) {
      const auto j = p.neighbors[k];
      const double ax = p.x[i] * 1e3, ay = p.y[i] * 1e3, bx = p.x[j] * 1e3, by = p.y[j] * 1e3;
      bool crosses = false;
      for (const auto& r : s.rectangles) crosses |= clipped_length(ax, ay, bx, by, r) > 1e-9;
      for (const auto& d : s.disks) crosses |= distance_to_segment(d.x, d.y, ax, ay, bx, by) < d.r - 1e-6 * s.spacing_mm;
      through_void += crosses;
    }
  CHECK(through_void == 0);

  // 3. The scene runs as written, and pd-post reads its output.
  REQUIRE(run_shell(std::string(PD_SOLVE_EXE) + " " + geometries + "/" + s.name + ".toml --set particles=" + pdp +
              " --threads 1 -q -o " + out + " > " + (work / "solve.log").string() + " 2>&1") == 0);
  CHECK(fs::exists(out + "/summary.json"));
  REQUIRE(run_shell(std::string(PD_POST_EXE) + " " + out + " > " + (work / "post.log").string() + " 2>&1") == 0);
  CHECK(fs::exists(out + "/post/summary.json"));
  CHECK(fs::exists(out + "/post/crack_tips.csv"));
  // pd-post's pictures of the particle file: a --zoom window off the plate
  // (a kilometre away) is refused, naming the plate's extent, not drawn empty.
  const std::string zoom_log = (work / "zoom.log").string();
  CHECK(run_shell(std::string(PD_POST_EXE) + " --particles " + pdp + " --zoom 1000m,1001m,0m,1m -o " +
                  (work / "zoom").string() + " > " + zoom_log + " 2>&1") != 0);
  CHECK_THAT(pd::test_support::file_text(zoom_log), Catch::Contains("holds no particle centre of " + pdp) &&
                                                        Catch::Contains("the plate spans"));
  // A window backwards or of three lengths is named with what was read
  // (before 6 December 2026 the message gave no value; before 7 December
  // 2026 18mm read back from metres as 18.000000000000004).
  CHECK(run_shell(std::string(PD_POST_EXE) + " --particles " + pdp + " --zoom 10mm,5mm,0mm,18mm -o " +
                  (work / "zoom").string() + " > " + zoom_log + " 2>&1") != 0);
  CHECK_THAT(pd::test_support::file_text(zoom_log),
             Catch::Contains("pd-post: error: --zoom 10, 5, 0, 18 mm (4 lengths): expected x0,x1,y0,y1"));
  CHECK(run_shell(std::string(PD_POST_EXE) + " --particles " + pdp + " --zoom 1mm,2mm,3mm -o " +
                  (work / "zoom").string() + " > " + zoom_log + " 2>&1") != 0);
  CHECK_THAT(pd::test_support::file_text(zoom_log), Catch::Contains("--zoom 1, 2, 3 mm (3 lengths): expected"));

  // 4. Where damage starts.
  vtkNew<vtkXMLPolyDataReader> reader;
  const std::string arrival = out + "/arrival.vtp";
  reader->SetFileName(arrival.c_str());
  reader->Update();
  vtkPolyData* data = reader->GetOutput();
  vtkDataArray* times = data->GetPointData()->GetArray("arrival_time_0.35");
  REQUIRE(times != nullptr);
  double first = INFINITY, fx = 0, fy = 0;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
    const double t = times->GetTuple1(i);
    if (t > 0 && t < first) {
      double xyz[3];
      data->GetPoint(i, xyz);
      first = t, fx = xyz[0] * 1e3, fy = xyz[1] * 1e3;
    }
  }
  REQUIRE(std::isfinite(first));
  double nearest = INFINITY;
  for (const auto& [x, y] : s.starts) nearest = std::min(nearest, std::hypot(fx - x, fy - y));
  INFO(s.name << ": damage 0.35 first at (" << fx << ", " << fy << ") mm, t = " << first * 1e6 << " us");
  CHECK(nearest <= 2 * s.horizon_mm);
}

}  // namespace

TEST_CASE("single-edge-notch strip: mesh, run, post", "[specimens]") {
  Specimen s{"sen_strip", 0.5, 1.5, 20 * 40 - (4.5 * 1 + M_PI * 0.25 / 2), {}, {}, {{5, 20}}};
  add_notch(20, 1, 5, s.rectangles, s.disks);
  run_specimen(s);
}

TEST_CASE("compact-tension specimen with its pin holes: mesh, run, post", "[specimens]") {
  const double hole = M_PI * 6.25 * 6.25;
  Specimen s{"compact_tension", 1.25, 3.75, 62.5 * 60 - (36.75 * 1.5 + M_PI * 0.75 * 0.75 / 2) - 2 * hole, {}, {},
             {{37.5, 30}}};
  add_notch(30, 1.5, 37.5, s.rectangles, s.disks);
  s.disks.push_back({12.5, 16.25, 6.25});
  s.disks.push_back({12.5, 43.75, 6.25});
  run_specimen(s);
}

TEST_CASE("Kalthoff-Winkler plate, struck between its notches: mesh, run, post", "[specimens]") {
  Specimen s{"kalthoff_winkler", 2, 6, 100 * 200 - 2 * (49.25 * 1.5 + M_PI * 0.75 * 0.75 / 2), {}, {},
             {{50, 75}, {50, 125}}};
  add_notch(75, 1.5, 50, s.rectangles, s.disks);
  add_notch(125, 1.5, 50, s.rectangles, s.disks);
  run_specimen(s);
}

TEST_CASE("L-shaped panel: mesh, run, post", "[specimens]") {
  // The cut-out [50, 100] x [0, 50] mm less the fillet's corner square [50, 51] x [49, 50].
  Specimen s{"l_panel", 2, 6, 100 * 100 - 50 * 50 + (1 - M_PI / 4), {{51, -1, 101, 50}, {50, -1, 101, 49}}, {},
             {{50, 50}}};
  run_specimen(s);
}
