// Hostile and oversized input: a geometry file is data, gmsh's time is
// bounded, and a grid that cannot fit in memory is refused before meshing,
// with its estimated size. Each case runs pd-mesh as a user would.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>

#include "family_size_estimate.hpp"
#include "mesh_worker.hpp"
#include "particle_file.hpp"
#include "pd_mesh_run.hpp"

namespace fs = std::filesystem;

namespace {

using namespace pd::test_support;

const std::string plate =
    "Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {10, 10, 0}; Point(4) = {0, 10, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n";

// A square plate of side `side` mm with count x count holes of radius 0.3 mm,
// `pitch` mm apart (OpenCASCADE, as geometries/c3a_pores.geo).
std::string small_holes_plate(int side, int count, double pitch) {
  return "SetFactory(\"OpenCASCADE\");\nW = " + std::to_string(side) + "; N = " + std::to_string(count) +
         "; P = " + std::to_string(pitch) +
         "; R = 0.3;\nRectangle(1) = {0, 0, 0, W, W};\nFor i In {0:N-1}\n  For j In {0:N-1}\n"
         "    Disk(2 + i * N + j) = {P / 2 + i * P, P / 2 + j * P, 0, R, R};\n  EndFor\nEndFor\n"
         "BooleanDifference(1000) = { Surface{1}; Delete; }{ Surface{2:N*N+1}; Delete; };\n";
}

}  // namespace

TEST_CASE("a geometry file that runs a shell command is refused before gmsh reads it", "[mesher][hostile]") {
  // The command would leave a marker file; gmsh never sees the file, so the
  // marker must not exist afterwards. (Before this check, gmsh ran it.)
  const auto marker = mesher_temp("marker");
  fs::remove(marker);
  const auto geo = write_text_file("shell.geo", plate + "SystemCall \"touch " + marker + "\";\n");
  const auto out = mesher_temp("never.pdp");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon 3mm -o " + out);
  INFO(run.err);
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::Contains(geo + ":4: 'SystemCall' runs a shell command"));
  CHECK_FALSE(fs::exists(marker));
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("statements that act outside the geometry are refused with file and line", "[mesher][hostile]") {
  const struct {
    const char* name;
    const char* text;
    const char* expected;
  } cases[] = {
      {"include.geo", "Include \"other.geo\";\n", ":4: 'Include' runs another script"},
      {"macro.geo", "Macro Boom\n  NonBlockingSystemCall \"ls\";\nReturn\n", ":5: 'NonBlockingSystemCall' runs a shell command"},
      {"printf.geo", "Printf(\"%g\", 1) > \"leak.txt\";\n", ":4: 'Printf' with '>' writes to a file"},
      {"append.geo", "Printf(\"x\") >> \"leak.txt\";\n", ":4: 'Printf' with '>>' writes to a file"},
      {"exit.geo", "Exit;\n", ":4: 'Exit' ends the process"},
      {"onelab.geo", "OnelabRun(\"solver\", \"ls\");\n", ":4: 'OnelabRun' runs another program"},
      {"save.geo", "Save \"mesh.msh\";\n", ":4: 'Save' writes a file"},
      {"mkdir.geo", "CreateDir \"d\";\n", ":4: 'CreateDir' creates a directory"},
      {"merge.geo", "Merge \"other.geo\";\n", ":4: 'Merge' reads another file"},
  };
  for (const auto& c : cases) {
    const auto geo = write_text_file(c.name, plate + c.text);
    const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon 3mm -o " + mesher_temp("never.pdp"));
    INFO(c.name << ": " << run.err);
    CHECK(run.status == 1);
    CHECK_THAT(run.err, Catch::Contains(std::string(c.name) + c.expected));
  }
}

TEST_CASE("the same words in comments, strings and variable names are fine", "[mesher][hostile]") {
  const auto geo = write_text_file("harmless.geo", "// SystemCall \"rm -rf /\" in a comment\n/* Include \"x\"; */\n"
                                             "Save = 2; Print[] = {1}; label = \"SystemCall\";\n" + plate);
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon 3mm -o " + mesher_temp("harmless.pdp"));
  INFO(run.err);
  CHECK(run.status == 0);
}

TEST_CASE("gmsh's time is bounded: a loop of 10^9 iterations ends with an error naming the bound",
          "[mesher][hostile]") {
  const auto geo = write_text_file("loop.geo", "x = 0;\nFor i In {1:1e9}\n  x += i;\nEndFor\n" + plate);
  const auto out = mesher_temp("never.pdp");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon 3mm --gmsh-time-limit 1 -o " + out, 60);
  INFO(run.err);
  CHECK(run.status == 1);
  // The message comes from the bound itself; without it the loop would run
  // until run_pd_mesh's own limit (60 s) killed pd-mesh.
  CHECK_THAT(run.err, Catch::Contains(geo + ": gmsh did not finish reading the geometry within 1 s (--gmsh-time-limit 1"));
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("the meshing time limit grows with the cells gmsh is to make, faster than gmsh makes them",
          "[mesher][hostile]") {
  // A free region of 20 x 20 mm at a target size of 0.05 mm: 160,000 cells,
  // about C1's global free grid at the paper's resolution (139,808 cells).
  // gmsh took 197 s for that grid on the shared 2-core machine, and more than
  // the 440 s the limit then allowed (300 s plus 1 ms per cell) once, so the
  // documented command failed: the allowance per cell was below gmsh's own
  // time per cell (up to about 3 ms on a loaded machine).
  pd::RegionShape square;
  square.spacing = 0.05e-3;
  square.vertices = {{0, 0}, {0.02, 0}, {0.02, 0.02}, {0, 0.02}};
  square.loops = {{0, 1, 2, 3}};
  const double cells = 160000;
  const double limit = pd::meshing_time_limit(300, {square});
  CHECK(limit == Approx(300 + 10e-3 * cells).epsilon(1e-9));
  CHECK(limit - 300 > 3e-3 * cells);
  // A graded region is counted at its finest size.
  square.fine_size = 0.025e-3;
  CHECK(pd::meshing_time_limit(300, {square}) == Approx(300 + 10e-3 * 4 * cells).epsilon(1e-9));
}

TEST_CASE("a grid too big for the machine is refused before meshing, with its estimated size",
          "[mesher][hostile]") {
  const auto c1 = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  SECTION("1 um on the 20 mm plate: 3.5e8 particles") {
    // Area 400 - 16 pi mm^2 = 349.7 mm^2 -> 3.50e8 particles. With m = 3, 44
    // cells meet the disk of radius 3 dx around a square's centre (by columns
    // |i| = 0, 1, 2, 3: 6 + 14 + 14 + 10): 1.54e10 bonds.
    const auto run = run_pd_mesh(c1 + " --spacing 1um --horizon 3um -o " + out);
    INFO(run.err);
    CHECK(run.status == 1);
    CHECK_THAT(run.err, Catch::Contains("about 3.5e+08 particles and 1.54e+10 bonds") &&
                            Catch::Contains("--max-memory SIZE"));
  }
  SECTION("0.1 um: more particles than the file's 32-bit indices reach") {
    const auto run = run_pd_mesh(c1 + " --spacing 0.1um --horizon 0.3um -o " + out);
    INFO(run.err);
    CHECK(run.status == 1);
    CHECK_THAT(run.err, Catch::Contains("about 3.5e+10 particles") && Catch::Contains("32 bits"));
  }
  SECTION("--max-memory sets the budget") {
    // 0.2 mm: 8.7e3 particles, about 116 MB with pd-mesh's own 100 MB.
    const auto small = run_pd_mesh(c1 + " --spacing 0.2mm --horizon 0.6mm --max-memory 50MB -o " + out);
    INFO(small.err);
    CHECK(small.status == 1);
    CHECK_THAT(small.err, Catch::Contains("more than the 50 MB of memory allowed by --max-memory 50MB") &&
                              Catch::Contains("a larger --max-memory"));
    const auto enough = run_pd_mesh(c1 + " --spacing 0.2mm --horizon 0.6mm --max-memory 2GB -o " + out);
    INFO(enough.err);
    CHECK(enough.status == 0);
    CHECK(fs::exists(out));
  }
  SECTION("a size without a unit is an error") {
    const auto run = run_pd_mesh(c1 + " --spacing 0.2mm --horizon 0.6mm --max-memory 64 -o " + out);
    CHECK(run.status == 1);
    CHECK_THAT(run.err, Catch::Contains("--max-memory: '64' needs a unit"));
  }
}

// Holes narrower than the spacing: every loop is sampled in at least 8
// chords, so the free cells round a hole of 0.6 mm at dx = 1 mm are about
// 0.23 mm, and each keeps the horizon 3 mm: some 330 bonds per particle
// where 44 is usual. The estimate before meshing (area / dx^2, 96 particles,
// 100.1 MB) saw none of it; before, a 20 mm plate with 64 such holes was
// estimated at 382 particles and 100 MB and meshed to 5,943 particles, 2.4
// million bonds and a 136 MB peak under --max-memory 101MB, without a word.
TEST_CASE("holes narrower than the spacing: the bonds are estimated again once meshed, and warned about",
          "[mesher][hostile]") {
  // 10 x 10 mm, 4 x 4 holes 2.5 mm apart: about 1,160 particles and 4.4e5 bonds (111 MB by the model;
  // 4.14e5 and 366 bonds per small cell before the disk was counted in strips, 7 December 2026).
  const auto geo = write_text_file("small_holes.geo", small_holes_plate(10, 4, 2.5));
  const auto out = mesher_temp("small_holes.pdp");
  fs::remove(out);
  const auto refused = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --max-memory 105MB -o " + out);
  INFO(refused.err);
  CHECK(refused.status == 1);
  CHECK_THAT(refused.err, Catch::StartsWith("pd-mesh: error: " + geo + ": once meshed, this grid needs about 1.16e+03 "
                                            "particles and 4.4e+05 bonds (") &&
                              Catch::Contains("keep the horizon 3 mm, about 390 bonds each where 44 is usual") &&
                              Catch::Contains("more than the 105 MB of memory allowed by --max-memory 105MB: use "
                                              "--box-spacing 0.25mm") &&
                              Catch::EndsWith("or a larger --max-memory\n"));
  CHECK(std::count(refused.err.begin(), refused.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(out));

  const auto allowed = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --max-memory 200MB -o " + out);
  INFO(allowed.err);
  REQUIRE(allowed.status == 0);
  CHECK_THAT(allowed.err,
             Catch::Contains("pd-mesh: warning: " + geo + ": 16 holes narrower than the spacing 1 mm (hole_1, hole_2, "
                             "...; 0.6 mm wide) force ") &&
                 Catch::Contains("below half the 1 mm their horizon 3 mm is meant for: about ") &&
                 Catch::Contains(" bonds per particle there where 44 is usual") &&
                 Catch::Contains("--box-spacing 0.25mm (the boxes' horizons then follow their cells), a --spacing of "
                                 "about 0.232 mm or holes wider than the spacing give the usual families"));
  const auto p = pd::read_particle_file(out);
  const double per_particle = static_cast<double>(p.bond_count()) / static_cast<double>(p.size());
  CHECK(per_particle > 200);
  // The estimate counts by distance, as if the holes were not there: above the
  // bonds built, below them plus those the holes cut (a further 6.9e4 here).
  const auto sizes = pd::estimate_family_sizes(p);
  const double estimated = std::accumulate(sizes.begin(), sizes.end(), 0.0);
  CHECK(estimated > static_cast<double>(p.bond_count()));
  CHECK(estimated < 1.25 * static_cast<double>(p.bond_count()));
}

TEST_CASE("the box spacing the small-holes warning names gives the usual families, without a warning",
          "[mesher][hostile]") {
  // 10 x 10 mm, 2 x 2 holes 5 mm apart: 530 particles and 184 bonds each at dx = 1 mm.
  const auto geo = write_text_file("small_holes_box.geo", small_holes_plate(10, 2, 5));
  const auto out = mesher_temp("small_holes_box.pdp");
  const auto plain = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 -o " + out);
  INFO(plain.err);
  REQUIRE(plain.status == 0);
  CHECK_THAT(plain.err, Catch::Contains("4 holes narrower than the spacing 1 mm") &&
                            Catch::Contains("--box-spacing 0.25mm"));
  const auto boxed = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --box-spacing 0.25mm -o " + out);
  INFO(boxed.err);
  REQUIRE(boxed.status == 0);
  CHECK_THAT(boxed.err, !Catch::Contains("warning"));
  const auto p = pd::read_particle_file(out);
  CHECK(static_cast<double>(p.bond_count()) / static_cast<double>(p.size()) < 44);
}

// A pore traced as 400 short lines (0.06 mm) forces free cells of that size;
// the warning says that one Spline through the same points meshes at the
// usual size, and it does: no warning, and bonds per particle below a
// square's 44 (the lines: about 100 per particle).
TEST_CASE("an outline traced as short lines is warned about, one spline through its points is not",
          "[mesher][hostile]") {
  const auto traced = [](bool spline) {
    std::string geo = "Point(1) = {0,0,0}; Point(2) = {40,0,0}; Point(3) = {40,40,0}; Point(4) = {0,40,0};\n"
                      "Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,1}; Curve Loop(1) = {1:4};\n";
    const int n = 400;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n, r = 4 + 0.8 * std::sin(5 * a);
      geo += "Point(" + std::to_string(100 + k) + ") = {" + std::to_string(20 + r * std::cos(a)) + ", " +
             std::to_string(20 + r * std::sin(a)) + ", 0};\n";
    }
    if (spline) {
      geo += "Spline(10) = {100:" + std::to_string(99 + n) + ", 100}; Curve Loop(2) = {10};\n";
    } else {
      for (int k = 0; k < n; ++k)
        geo += "Line(" + std::to_string(10 + k) + ") = {" + std::to_string(100 + k) + ", " +
               std::to_string(100 + (k + 1) % n) + "};\n";
      geo += "Curve Loop(2) = {10:" + std::to_string(9 + n) + "};\n";
    }
    return geo + "Plane Surface(1) = {1, 2};\n";
  };
  const auto out = mesher_temp("traced.pdp");
  const auto lines = run_pd_mesh(write_text_file("traced_lines.geo", traced(false)) +
                                 " --spacing 0.5mm --horizon-factor 3 -o " + out);
  INFO(lines.err);
  REQUIRE(lines.status == 0);
  CHECK_THAT(lines.err, Catch::Contains("warning") && Catch::Contains("drawn as one Spline through the same points"));
  const auto spline = run_pd_mesh(write_text_file("traced_spline.geo", traced(true)) +
                                  " --spacing 0.5mm --horizon-factor 3 -o " + out);
  INFO(spline.err);
  REQUIRE(spline.status == 0);
  CHECK_THAT(spline.err, !Catch::Contains("warning"));
  const auto p = pd::read_particle_file(out);
  CHECK(static_cast<double>(p.bond_count()) / static_cast<double>(p.size()) < 44);
}

// On a plate without small features the estimate once meshed is the families
// built to a few per cent, an interior square's exactly (44 at m = 3; 42.2,
// by the disk's area alone, before 7 December 2026).
TEST_CASE("the bond estimate once meshed follows the families of an ordinary grid", "[mesher][hostile]") {
  const auto estimated_bonds = [](const pd::ParticleSet& p) {
    const auto sizes = pd::estimate_family_sizes(p);
    return std::accumulate(sizes.begin(), sizes.end(), 0.0);
  };
  const auto c1 = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("estimate.pdp");
  const auto hole = run_pd_mesh(c1 + " --spacing 0.5mm --horizon-factor 3 -o " + out);
  INFO(hole.err);
  REQUIRE(hole.status == 0);
  CHECK_THAT(hole.err, !Catch::Contains("warning"));
  const auto with_hole = pd::read_particle_file(out);
  CHECK(estimated_bonds(with_hole) == Approx(static_cast<double>(with_hole.bond_count())).epsilon(0.1));

  const auto geo = write_text_file("estimate.geo", rectangle_geo(20, 10));
  const auto plain = run_pd_mesh(geo + " --spacing 0.5mm --horizon-factor 3 -o " + out);
  REQUIRE(plain.status == 0);
  const auto p = pd::read_particle_file(out);
  CHECK(estimated_bonds(p) == Approx(static_cast<double>(p.bond_count())).epsilon(0.1));
  const auto sizes = pd::estimate_family_sizes(p);
  std::size_t interior = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double margin = p.horizon[i] + p.spacing;
    if (p.x[i] < margin || p.x[i] > 20e-3 - margin || p.y[i] < margin || p.y[i] > 10e-3 - margin) continue;
    ++interior;
    CHECK(sizes[i] == Approx(44).epsilon(1e-9));
  }
  CHECK(interior > 300);
}

// The particle file's size once meshed, as the summary prints it, against
// the file written: before 7 December 2026 it was 3.9 % low for C1 at m = 3
// (3.32 MB for 3.46 MB), the squares' families counted by the disk's area
// (42.2 for 44), and later that day still 2.5 % low for C1 at 0.5 mm (0.808
// MB for 0.829 MB) and 1.0 to 1.4 % at 0.25 mm, a square of pi / 4 of its
// particles standing for the disk near the edges; now within 1 %, small
// plates of mostly boundary cells included.
TEST_CASE("the particle file's size estimated once meshed is the file written to 1 per cent", "[mesher][hostile]") {
  const auto c1 = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto rectangle = write_text_file("file_size.geo", rectangle_geo(20, 10));
  for (const std::string& arguments : {c1 + " --spacing 0.25mm --horizon-factor 3", c1 + " --spacing 0.25mm -m 4",
                                       c1 + " --spacing 0.5mm -m 3", rectangle + " --spacing 0.25mm -m 3",
                                       rectangle + " --spacing 0.5mm -m 3"}) {
    const auto out = mesher_temp("file_size.pdp"), summary = mesher_temp("file_size_summary.txt");
    REQUIRE(pd::test_support::run_shell(std::string(PD_MESH_EXE) + " " + arguments + " -o " + out + " > " + summary +
                                        " 2> /dev/null") == 0);
    const std::string text = file_text(summary);
    const auto line = text.find("estimate once meshed:");
    REQUIRE(line != std::string::npos);
    const auto end = text.find(" MB file", line);
    REQUIRE(end != std::string::npos);
    const double estimated = std::stod(text.substr(text.rfind(", ", end) + 2)) * 1e6;
    const double written = static_cast<double>(std::filesystem::file_size(out));
    INFO(arguments << ": estimated " << estimated << " bytes, written " << written);
    CHECK(estimated == Approx(written).epsilon(0.01));
  }
}
