// pd-mesh as a user runs it: bad input gets a clear message naming the file
// and the problem, a non-zero exit, and no output file; good input gives a
// byte-identical particle file every time.
#include <unistd.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "particle_file.hpp"
#include "pd_mesh_run.hpp"
#include "vtk_output.hpp"

namespace fs = std::filesystem;

namespace {

using namespace pd::test_support;

const std::string rectangle_20 =
    "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0}; Point(4) = {0, 20, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4};\n";

// A plate of four corners given as gmsh coordinate lists ("20, 0, 0"), one
// surface: for corners that gmsh reads but pd-mesh must refuse.
std::string quadrilateral_plate(const std::string& c1, const std::string& c2, const std::string& c3,
                                const std::string& c4) {
  return "Point(1) = {" + c1 + "}; Point(2) = {" + c2 + "}; Point(3) = {" + c3 + "}; Point(4) = {" + c4 +
         "};\nLine(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
         "Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n";
}

// A circular hole: points and curves tagged from `tag` on, its curve loop `loop`.
std::string circle_hole(double cx, double cy, double r, int tag = 10, int loop = 2) {
  auto n = [](double v) { return std::to_string(v); };
  const auto t = [&](int k) { return std::to_string(tag + k); };
  return "Point(" + t(0) + ") = {" + n(cx) + ", " + n(cy) + ", 0}; Point(" + t(1) + ") = {" + n(cx + r) + ", " +
         n(cy) + ", 0}; Point(" + t(2) + ") = {" + n(cx - r) + ", " + n(cy) + ", 0};\n" + "Circle(" + t(0) +
         ") = {" + t(1) + ", " + t(0) + ", " + t(2) + "}; Circle(" + t(1) + ") = {" + t(2) + ", " + t(0) + ", " +
         t(1) + "};\nCurve Loop(" + std::to_string(loop) + ") = {" + t(0) + ", " + t(1) + "};\n";
}

}  // namespace

TEST_CASE("pd-mesh --help and --version", "[mesher][cli]") {
  CHECK(run_pd_mesh("--help").status == 0);
  CHECK(run_pd_mesh("--version").status == 0);
  // The spacing divides a side only where straight edges lie along both
  // sides of the plate (a rotated plate meshes at any spacing, docs/mesher.md,
  // "The three grids"); the help said "must divide both plate sides" until 6
  // December 2026.
  const std::string help = mesher_temp("pd_mesh_help.txt");
  REQUIRE(run_shell(std::string(PD_MESH_EXE) + " --help > " + help) == 0);
  const std::string text = file_text(help);
  CHECK_THAT(text, Catch::Contains("where straight edges"));
  CHECK_THAT(text, !Catch::Contains("both plate sides"));
}

TEST_CASE("pd-mesh rejects bad geometry files", "[mesher][cli]") {
  const auto out = mesher_temp("never.pdp");
  SECTION("missing file") { expect_pd_mesh_failure(mesher_temp("nope.geo") + " --spacing 0.5mm --horizon 2mm", out, "not found"); }
  SECTION("syntax error") {
    const auto geo = write_text_file("syntax.geo", "Point(1) = {0, 0, 0;\nLine(1) = {1, 2};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out, "syntax error");
  }
  SECTION("a statement without its ';', which gmsh names by the line after it") {
    // Before 7 December 2026 only gmsh's "line 5: syntax error (Point)",
    // the line after the one at fault (past a blank line and a comment).
    const auto geo = write_text_file("no_semicolon.geo", "Point(1) = {0, 0, 0};\nPoint(2) = {20, 0, 0}\n\n"
                                                         "// the top\nPoint(3) = {20, 10, 0};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "pd-mesh: error: " + geo + ": reading the geometry failed:\n  gmsh: Error: '" + geo + "', "
                           "line 5: syntax error (Point)\n  line 2, 'Point(2) = {20, 0, 0}', does not end with ';': "
                           "every statement ends with one, and gmsh reads the line after as its continuation\n");
    // A ';' left out inside a line, or a brace left open on the line named,
    // is gmsh's message alone.
    const auto inside = write_text_file("brace_open.geo", "W = 20;\nPoint(1) = {0, 0, 0;\n");
    const auto run = run_pd_mesh(inside + " --spacing 0.5mm --horizon 2mm -o " + out);
    CHECK(run.status != 0);
    CHECK(run.err.find("does not end with ';'") == std::string::npos);
  }
  SECTION("a scene given for the geometry") {
    // Before 5 December 2026: a page of gmsh syntax errors.
    const auto scene = write_text_file("plate.toml", "# a scene\nparticles = \"plate.pdp\"\n");
    expect_pd_mesh_failure(scene + " --spacing 0.5mm --horizon 2mm", out,
                           "plate.toml: a scene (TOML), not a gmsh geometry: pd-mesh meshes the .geo file");
  }
  SECTION("an empty file, or one of white space only") {
    // Before 7 December 2026: "expected exactly one plane surface, found 0".
    for (const auto& [text, what] : std::vector<std::pair<std::string, std::string>>{
             {"", "the file is empty (0 bytes)"}, {" \n\t\n", "the file holds only white space"}}) {
      const auto geo = write_text_file("empty.geo", text);
      std::filesystem::remove(out);
      const auto run = run_pd_mesh(geo + " --spacing 0.5mm --horizon 2mm -o " + out);
      CHECK(run.status == 1);
      CHECK(run.err == "pd-mesh: error: " + geo + ": " + what +
                           ": a geometry file defines the plate (its points, curves, curve loops and one Plane "
                           "Surface; docs/mesher.md, \"Geometry input\"); was it cut short when copied?\n");
      CHECK_FALSE(std::filesystem::exists(out));
    }
  }
  SECTION("no surface") {
    const auto geo = write_text_file("nosurface.geo", rectangle_20);
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out, "expected exactly one plane surface, found 0");
  }
  // The 20 mm square with more geometry after its outer loop, meshed at 0.5 mm.
  const auto refused = [&](const std::string& name, const std::string& more, const std::string& message) {
    expect_pd_mesh_failure(write_text_file(name, rectangle_20 + more) + " --spacing 0.5mm --horizon 2mm", out, message);
  };
  SECTION("a plate in two pieces, or a hole with a surface of its own") {
    // Before: 'expected exactly one plane surface, found 2', without the surfaces or the way to one.
    refused("halves.geo",
            "Plane Surface(1) = {1};\nPoint(12) = {20, 30, 0}; Point(13) = {0, 30, 0};\n"
            "Line(12) = {4, 3}; Line(13) = {3, 12}; Line(14) = {12, 13}; Line(15) = {13, 4}; Curve Loop(2) = {12:15};\n"
            "Plane Surface(2) = {2};\n",
            "expected exactly one plane surface, found 2 (1, 2): pd-mesh meshes one plate");
    refused("hole_surface.geo",
            "Point(20) = {10, 10, 0}; Point(21) = {12, 10, 0}; Point(22) = {8, 10, 0};\n"
            "Circle(20) = {21, 20, 22}; Circle(21) = {22, 20, 21}; Curve Loop(20) = {20, 21};\n"
            "Plane Surface(1) = {1, 20};\nPlane Surface(2) = {20};\n",
            "expected exactly one plane surface, found 2 (1, 2): pd-mesh meshes one plate from its boundary loops; "
            "give it as one 'Plane Surface' of the outer curve loop and the holes' loops (a hole is a loop of that "
            "surface, not a surface of its own), or join the pieces with OpenCASCADE's BooleanUnion");
  }
  SECTION("a solid: a Box, or a plate extruded to its thickness") {
    // Before 7 December 2026 its faces were counted as pieces of a plate:
    // 'expected exactly one plane surface, found 6 (1, 2, 3, 4, 5, 6): ...
    // or join the pieces with OpenCASCADE's BooleanUnion'.
    const std::string message = ": the geometry is a solid (volume 1): pd-mesh meshes a plate as its plane face, in "
                                "2D; give the face alone (e.g. Rectangle instead of Box, or no Extrude), and the "
                                "plate's thickness in the scene (material.thickness)\n";
    const auto box = write_text_file("box.geo", "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 20, 10, 5};\n");
    expect_pd_mesh_failure(box + " --spacing 0.5mm --horizon 2mm", out, "pd-mesh: error: " + box + message);
    const auto extruded = write_text_file("extruded.geo", rectangle_20 + "Plane Surface(1) = {1};\n"
                                                                         "Extrude {0, 0, 5} { Surface{1}; }\n");
    expect_pd_mesh_failure(extruded + " --spacing 0.5mm --horizon 2mm", out, "pd-mesh: error: " + extruded + message);
  }
  SECTION("a notch longer than the plate, which cuts it in two") {
    // Before 7 December 2026 'expected exactly one plane surface, found 2
    // (1, 2): ... or join the pieces with OpenCASCADE's BooleanUnion', which
    // would fill the notch, the cut unsaid.
    const auto geo = write_text_file("notch_across.geo", "SetFactory(\"OpenCASCADE\");\nW = 20; H = 10; a = 25;\n"
                                                         "Rectangle(1) = {0, 0, 0, W, H};\n"
                                                         "Rectangle(2) = {0, H / 2 - 0.5, 0, a, 1};\n"
                                                         "BooleanDifference{ Surface{1}; Delete; }{ Surface{2}; "
                                                         "Delete; }\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           geo + ":5: BooleanDifference leaves the plate in 2 pieces (surfaces 1, 2): what it "
                                 "subtracts runs across the plate (a notch or slot longer than the plate, or "
                                 "coordinates in another unit?); pd-mesh meshes one plate: keep the cut within the "
                                 "plate, so that it stays one piece\n");
  }
  SECTION("a hole's curve loop left out of the plane surface") {
    // geometries/c1_plate_hole.geo with 'Plane Surface(1) = {1};': before 7
    // December 2026 the plate was meshed without its hole, exit 0.
    std::ifstream in(std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto at = text.find("Plane Surface(1) = {1, 2};");
    REQUIRE(at != std::string::npos);
    text.replace(at, 26, "Plane Surface(1) = {1};");
    const auto geo = write_text_file("c1_no_hole.geo", text);
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           geo + ": curves 5, 6, 7 and 8 close a loop inside the plate but bound no surface: was a "
                                 "hole's curve loop left out of 'Plane Surface'? List it there (Plane Surface(1) = "
                                 "{outer loop, hole loops}), or delete the curves\n");
    // One curve, a circle, is named in the singular (before 7 December 2026
    // 'curve 5 close a loop ... but bound no surface').
    const auto circle = write_text_file("circle_not_cut.geo", "SetFactory(\"OpenCASCADE\");\n"
                                                              "Rectangle(1) = {0, 0, 0, 20, 10};\n"
                                                              "Circle(5) = {10, 5, 0, 2};\n");
    expect_pd_mesh_failure(circle + " --spacing 0.5mm --horizon 2mm", out,
                           circle + ": curve 5 closes a loop inside the plate but bounds no surface: was a hole's "
                                    "curve loop left out of 'Plane Surface'? List it there (Plane Surface(1) = {outer "
                                    "loop, hole loops}), or delete the curve\n");
  }
  SECTION("a geometry cut short before its holes are cut from the plate") {
    // geometries/c3a_pores.geo cut at a statement boundary, as a copy cut
    // short leaves it. Inside its For loop (no EndFor): before 7 December
    // 2026 gmsh ran the loop's head alone and the plate was meshed without
    // its pores, exit 0. After its disks, before the BooleanDifference: the
    // disks lie on the plate, refused before with advice to join the pieces.
    std::ifstream in(std::string(PD_GEOMETRY_DIR) + "/c3a_pores.geo");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    REQUIRE(lines.size() == 12);
    REQUIRE(lines[8] == "For k In {1:8}");
    REQUIRE(lines[10] == "EndFor");
    const auto first = [&](std::size_t n) {
      std::string text;
      for (std::size_t k = 0; k < n; ++k) text += lines[k] + "\n";
      return text;
    };
    for (const std::size_t n : {9, 10}) {
      INFO(n << " lines");
      const auto geo = write_text_file("c3a_cut.geo", first(n));
      expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                             geo + ":9: 'For' has no 'EndFor' before the file ends: was the file cut short? gmsh "
                                   "would run it without the rest of the block; give the whole file\n");
    }
    const auto geo = write_text_file("c3a_cut.geo", first(11));
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           geo + ": 8 surfaces (2, 3, 4, 5, 6, 7, ...) lie on the plate (surface 1) without being cut "
                                 "from it: was the file cut short before its BooleanDifference? To make them holes, "
                                 "subtract them: BooleanDifference{ Surface{1}; Delete; }{ Surface{...}; Delete; }\n");
    const auto one = write_text_file("c3a_one_disk.geo", first(8) + "Disk(2) = {5, 12.5, 0, 0.75, 0.75};\n");
    expect_pd_mesh_failure(one + " --spacing 0.5mm --horizon 2mm", out,
                           ": 1 surface (2) lies on the plate (surface 1) without being cut from it");
    // The whole file meshes (its surface 100, the plate less the pores).
    const auto whole = write_text_file("c3a_whole.geo", first(12));
    const auto run = run_pd_mesh(whole + " --spacing 0.5mm --horizon 2mm -o " + out);
    INFO(run.err);
    CHECK(run.status == 0);
    std::filesystem::remove(out);
  }
  SECTION("a crack or point embedded in the surface") {
    // pd-mesh builds its grid from the boundary loops: an embedded crack would vanish.
    refused("embedded.geo",
            "Plane Surface(1) = {1};\nPoint(30) = {4, 10, 0}; Point(31) = {8, 10, 0}; Point(32) = {15, 15, 0};\n"
            "Line(30) = {30, 31};\nLine{30} In Surface{1};\nPoint{32} In Surface{1};\n",
            "curve 30 and point 32 embedded in the surface ('In Surface')");
  }
  SECTION("a hole loop listed twice") {
    // gmsh meshes the hole once: the surface would not be the plate the file lists.
    refused("twice.geo", circle_hole(10, 10, 3) + "Plane Surface(1) = {1, 2, 2};\n",
            "curve 11 is twice in the surface's boundary: a curve loop listed twice in 'Plane Surface'");
  }
  SECTION("open boundary") {
    // A hole loop made of one arc: its ends do not meet.
    refused("open.geo",
            "Point(10) = {10, 10, 0}; Point(11) = {14, 10, 0}; Point(12) = {6, 10, 0};\n"
            "Circle(10) = {11, 10, 12};\nCurve Loop(2) = {10};\nPlane Surface(1) = {1, 2};\n",
            "open boundary: curve 10 ends at (6, 10) mm and curve 10 starts at (14, 10) mm, where no other curve "
            "meets them");
  }
  SECTION("open outer loop") {
    // gmsh refuses the loop ("Curve Loop 1 is wrong") without a place; pd-mesh names the free ends.
    const auto geo = write_text_file("open_outer.geo",
                                     "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0};"
                                     " Point(4) = {0, 20, 0}; Point(5) = {0, 18, 0};\n"
                                     "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {5, 1};\n"
                                     "Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "the loop is open: curve 3 ends at (0, 20) mm and curve 4 starts at (0, 18) mm");
  }
  SECTION("self-intersecting hole") {
    // A bow-tie polygon.
    const auto geo = write_text_file("bowtie.geo", rectangle_20 +
                                                 "Point(10) = {6, 6, 0}; Point(11) = {14, 14, 0}; Point(12) = {14, 6, 0};"
                                                 " Point(13) = {6, 14, 0};\n"
                                                 "Line(10) = {10, 11}; Line(11) = {11, 12}; Line(12) = {12, 13};"
                                                 " Line(13) = {13, 10};\n"
                                                 "Curve Loop(2) = {10, 11, 12, 13}; Plane Surface(1) = {1, 2};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "a boundary loop intersects itself near (10, 10) mm (curves 10 and 12)");
  }
  SECTION("a hole of zero area") {
    // Two quarter arcs running the same way from (8, 10) to (10, 12) mm: a
    // loop that encloses nothing. Before, the uniform grid took it for a
    // narrow void 0 mm wide (exit 0) and the NB-NUG grid failed inside gmsh
    // ('Unable to recover the edge').
    const auto geo = write_text_file("zero_area.geo", rectangle_20 +
                                                    "Point(10) = {10, 10, 0}; Point(11) = {8, 10, 0};"
                                                    " Point(12) = {10, 12, 0};\n"
                                                    "Circle(10) = {11, 10, 12}; Circle(11) = {11, 10, 12};\n"
                                                    "Curve Loop(2) = {10, -11}; Plane Surface(1) = {1, 2};\n");
    for (const std::string grid : {"uniform", "nbnug"})
      expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm --grid " + grid, out,
                             "a hole (curves 10 and 11) encloses no area: its curves run along each other");
  }
  SECTION("a traced outline with a point given twice in a row") {
    // A Spline (Catmull-Rom) through eight points of a circle of radius 3 mm
    // with its top point (10, 13) given twice: it leaves the point and comes
    // back to it, a small loop. The error names the curve and the likely
    // cause (before: 'a boundary curve intersects itself near (10, 13) mm'
    // and no more, whichever of a plate's traced pores it was).
    std::string geo_text = rectangle_20;
    for (int k = 0; k < 8; ++k)
      geo_text += "Point(" + std::to_string(100 + k) + ") = {" + std::to_string(10 + 3 * std::sin(k * M_PI / 4)) +
                  ", " + std::to_string(10 + 3 * std::cos(k * M_PI / 4)) + ", 0};\n";
    geo_text += "Point(108) = {10, 13, 0};\nSpline(20) = {100, 108, 101:107, 100}; Curve Loop(2) = {20};\n"
                "Plane Surface(1) = {1, 2};\n";
    const auto geo = write_text_file("doubled_point.geo", geo_text);
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "a boundary curve intersects itself near (10, 13) mm (curve 20): a Spline through the "
                           "same point twice in a row, or a spline through points that double back, loops there");
  }
  SECTION("hole crossing the plate edge without a boolean cut") {
    // With the built-in kernel a hole loop that crosses the outer loop is no
    // surface; OpenCASCADE's BooleanDifference makes the notch.
    const auto geo = write_text_file("crossing.geo", rectangle_20 + circle_hole(19, 10, 3) + "Plane Surface(1) = {1, 2};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                   "a hole touches or crosses the outer boundary near (20, 7.1716) mm (curves 2 and 11) without");
  }
  SECTION("two holes that cross") {
    const auto geo = write_text_file("two_holes.geo", rectangle_20 + circle_hole(8, 10, 3) + circle_hole(12, 10, 3, 20, 3) +
                                                    "Plane Surface(1) = {1, 2, 3};\n");
    // The crossing of the circles, (10, 10 - sqrt(5)) mm, and the arcs that
    // cross there (the place alone before).
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "two holes touch or cross near (10, 7.7639) mm (curves 11 and 21) without");
  }
  SECTION("a hole inside another hole") {
    const auto geo = write_text_file("nested.geo", rectangle_20 + circle_hole(10, 10, 5) + circle_hole(10, 10, 2, 20, 3) +
                                                 "Plane Surface(1) = {1, 2, 3};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out, "a hole lies inside another hole near (12, 10) mm");
  }
  SECTION("a small hole tangent to the plate edge, at every spacing") {
    // A hole of radius 0.2 mm touching the bottom edge at (10, 0) mm, a point
    // the two do not share. The polylines (within 1e-6 dx of the curves) need
    // not meet there: before, 0.1 mm meshed it with a ligament of zero width,
    // and other spacings failed with advice to take a smaller spacing.
    const auto geo = write_text_file("tangent_small.geo",
                                     "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 10, 0}; "
                                     "Point(4) = {0, 10, 0};\nLine(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; "
                                     "Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4};\n" +
                                         circle_hole(10, 0.2, 0.2) + "Plane Surface(1) = {1, 2};\n");
    // The place is a polyline vertex, printed to 0.1 um: its y, 9e-7 mm
    // from round-off, reads 0. The curves that touch there are named, as for
    // a crossing (before, the place alone).
    for (const std::string spacing : {"0.5mm", "0.25mm", "0.1mm", "0.05mm"}) {
      expect_pd_mesh_failure(geo + " --spacing " + spacing + " --horizon-factor 3", out,
                             "a hole touches the outer boundary near (10.000");
      CHECK_THAT(run_pd_mesh(geo + " --spacing " + spacing + " --horizon-factor 3 -o " + out).err,
                 Catch::Matches("[\\s\\S]*near \\(10\\.000[0-9]*, 0\\) mm \\(curves 1 and 11\\) without sharing a "
                                "point with it[\\s\\S]*"));
    }
  }
  // Careless input that gmsh reads without a word, each named for what it is
  // (before: "a hole lies outside the outer boundary", "open boundary: curve
  // 1 starts at (-nan, 0) mm", a file without the group's set, a set that
  // passed for a loading layer, gmsh's syntax errors full of raw bytes).
  SECTION("a curve of zero length") {
    const auto geo = write_text_file("zero_length.geo",
                                     "Point(1) = {0, 0, 0}; Point(2) = {20, 0, 0}; Point(3) = {20, 20, 0}; "
                                     "Point(4) = {0, 20, 0}; Point(5) = {20, 0, 0};\nLine(1) = {1, 2}; Line(5) = {2, 5}; "
                                     "Line(6) = {5, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
                                     "Curve Loop(1) = {1, 5, 6, 3, 4};\nPlane Surface(1) = {1};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "curve 5 has zero length: it starts and ends at (20, 0) mm");
  }
  SECTION("a coordinate beyond the range of a double") {
    const auto geo = write_text_file("infinite.geo", quadrilateral_plate("0, 0, 0", "1e400, 0, 0", "20, 20, 0", "0, 20, 0"));
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "point 2 has a coordinate that is not a finite number (inf, 0, 0 in file units)");
  }
  SECTION("a physical curve group of a curve that does not exist") {
    const auto geo = write_text_file("missing_curve.geo", rectangle_20 + "Plane Surface(1) = {1};\n"
                                                                         "Physical Curve(\"grip\") = {99};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "missing_curve.geo:5: physical curve group 'grip' holds no curve of the geometry");
  }
  SECTION("a physical curve group under a name the tools reserve") {
    // A loading layer's set name, and 'all', which scenes read as every
    // particle (before 5 December 2026 'all' was written, and a scene's
    // set = "all" then loaded the whole plate, not the group).
    for (const auto& [name, message] : std::vector<std::pair<std::string, std::string>>{
             {"loading_layer_top", "names starting with 'loading_layer_' are"},
             {"all", "a scene's set = \"all\" means every particle"}}) {
      const auto geo = write_text_file("reserved_name.geo", rectangle_20 + "Plane Surface(1) = {1};\n"
                                                                           "Physical Curve(\"" + name + "\") = {3};\n");
      expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                             "physical curve group '" + name + "': " + message);
    }
  }
  SECTION("a binary file") {
    const auto geo = write_text_file("binary.geo", std::string("\x7f" "ELF\x02\x01\x01", 7) + rectangle_20);
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out,
                           "not a text file (byte 0x7f at offset 0, line 1)");
  }
  SECTION("a tilted plate (not in the xy plane)") {
    // Its projection would have 20 x 20 mm; the plate itself is larger.
    const auto geo = write_text_file("tilted.geo", quadrilateral_plate("0, 0, 0", "20, 0, 0", "20, 20, 5", "0, 20, 5"));
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out, "the surface is not flat in the xy plane");
  }
  SECTION("hole touching the plate edge without sharing a point") {
    const auto geo = write_text_file("touching.geo", rectangle_20 + circle_hole(17, 10, 3) + "Plane Surface(1) = {1, 2};\n");
    expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm", out, "BooleanDifference");
  }
}

// geometries/c3a_pores.geo cut short after its Rectangle is a plate without
// holes, which gmsh reads without a word: before 7 December 2026 it was
// meshed as a plain plate, exit 0. The numbers set for the pores, read by
// nothing, say that more was meant. A plain plate that reads all it sets,
// and the whole file, mesh with no warning.
TEST_CASE("a plate left without the holes its file meant is warned about: cut short, or cut where it is not",
          "[mesher][cli]") {
  std::ifstream in(std::string(PD_GEOMETRY_DIR) + "/c3a_pores.geo");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  REQUIRE(lines.size() == 12);
  REQUIRE(lines[6] == "W = 50; H = 25; R = 0.75; D = W / 9;");
  REQUIRE(lines[7] == "Rectangle(1) = {0, 0, 0, W, H};");
  std::string text;
  for (std::size_t k = 0; k < 8; ++k) text += lines[k] + "\n";
  const auto geo = write_text_file("c3a_cut_after_rectangle.geo", text);
  const auto out = mesher_temp("cut_after_rectangle.pdp");
  expect_pd_mesh_warning_alone(geo + " --spacing 0.5mm --horizon 2mm -o " + out,
                               geo + ": the plate has no hole, yet the file sets 'R' (line 7) and 'D' (line 7) that "
                                     "no statement reads: was it cut short after line 8, its last statement? It is "
                                     "meshed as it stands, without holes; give the whole file, or leave out what it "
                                     "does not use");
  // A hole subtracted where the plate is not (x = 40 mm on a plate 20 mm
  // wide): before, the plate was meshed whole without a word.
  const auto off = write_text_file("hole_off_the_plate.geo",
                                   "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 20, 10};\n"
                                   "Disk(2) = {40, 5, 0, 2, 2};\n"
                                   "BooleanDifference{ Surface{1}; Delete; }{ Surface{2}; Delete; }\n");
  expect_pd_mesh_warning_alone(off + " --spacing 0.5mm --horizon 2mm -o " + out,
                               off + ": line 4: BooleanDifference leaves the plate four-sided and without a hole: "
                                     "what it subtracts lies off the plate (coordinates in another unit, or off by a "
                                     "sign?), and the plate is meshed whole; place the holes on the plate (0 to 20 by "
                                     "0 to 10 in file units)");
  for (const std::string& plate : {std::string(PD_GEOMETRY_DIR) + "/plate_no_pores.geo",
                                  std::string(PD_GEOMETRY_DIR) + "/c3a_pores.geo"})
    expect_pd_mesh_warning_alone(plate + " --spacing 0.5mm --horizon 2mm -o " + out, "");
  // A plain built-in plate that sets a name it does not read (a thickness
  // for the scene, a mesh size): its Plane Surface lists every loop, so it
  // cannot have lost holes by a cut. Before 7 December 2026 it was warned
  // about as cut short ("... sets 't' (line 1) and 'lc' (line 1) that no
  // statement reads: was it cut short after line 5 ...").
  const auto plain = write_text_file("plain_plate_with_notes.geo",
                                     "W = 20; H = 10; t = 5; lc = 0.5;  // t: thickness, for the scene\n"
                                     "Point(1) = {0, 0, 0}; Point(2) = {W, 0, 0}; Point(3) = {W, H, 0}; "
                                     "Point(4) = {0, H, 0};\nLine(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; "
                                     "Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n");
  expect_pd_mesh_warning_alone(plain + " --spacing 0.5mm --horizon 2mm -o " + out, "");
  // The same plate made by OpenCASCADE may have been cut before its holes.
  const auto cut = write_text_file("occ_plate_with_unread_radius.geo",
                                   "SetFactory(\"OpenCASCADE\");\nW = 20; H = 10; R = 2;\n"
                                   "Rectangle(1) = {0, 0, 0, W, H};\n");
  expect_pd_mesh_warning_alone(cut + " --spacing 0.5mm --horizon 2mm -o " + out,
                               cut + ": the plate has no hole, yet the file sets 'R' (line 2) that no statement "
                                     "reads: was it cut short after line 3, its last statement? It is meshed as it "
                                     "stands, without holes; give the whole file, or leave out what it does not use");
  std::filesystem::remove(out);
}

// A BooleanDifference without Delete keeps what it cut from, or what it cut
// out, as a surface of its own. Before 7 December 2026 both were told to
// join the pieces with BooleanUnion, which would fill the hole.
TEST_CASE("a BooleanDifference that keeps its plate or its holes' disks is refused, naming the line", "[mesher][cli]") {
  const auto out = mesher_temp("never.pdp");
  const std::string start = "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 20, 10};\n"
                            "Disk(2) = {10, 5, 0, 2, 2};\n";
  const auto keeps_plate = write_text_file("difference_keeps_plate.geo",
                                           start + "BooleanDifference{ Surface{1}; }{ Surface{2}; Delete; }\n");
  expect_pd_mesh_refusal_alone(keeps_plate + " --spacing 0.5mm --horizon 2mm", out,
                               keeps_plate + ":4: BooleanDifference without 'Delete;' in its first braces keeps the "
                                             "surface it cuts from: the plate is there whole, and again with its "
                                             "holes (2 surfaces); delete both, BooleanDifference{ Surface{plate}; "
                                             "Delete; }{ Surface{holes}; Delete; }");
  const auto keeps_disk = write_text_file("difference_keeps_disk.geo",
                                          start + "BooleanDifference{ Surface{1}; Delete; }{ Surface{2}; }\n");
  expect_pd_mesh_refusal_alone(keeps_disk + " --spacing 0.5mm --horizon 2mm", out,
                               keeps_disk + ":4: BooleanDifference without 'Delete;' in its second braces keeps the "
                                            "surfaces it cuts out: they fill the holes (2 surfaces); delete both, "
                                            "BooleanDifference{ Surface{plate}; Delete; }{ Surface{holes}; Delete; }");
}

TEST_CASE("pd-mesh rejects bad numbers", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 0.4mm", out, "smaller than the spacing");
  expect_pd_mesh_failure(geo + " --spacing -0.5mm --horizon 2mm", out, "--spacing must be positive");
  expect_pd_mesh_failure(geo + " --spacing 0mm --horizon 2mm", out, "--spacing must be positive");
  expect_pd_mesh_failure(geo + " --spacing nanmm --horizon 2mm", out, "--spacing");
  expect_pd_mesh_failure(geo + " --spacing 0.5 --horizon 2mm", out, "no unit");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm --padding 1mm", out, "less than one horizon");
  // A padding in the wrong unit (1e30 mm: before, an internal error of the box arithmetic).
  expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm --padding 1e30mm", out,
                         "--padding 1e+30 mm is more than ten times the plate's larger side (20 mm)");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm --grid hexagons", out, "unknown grid 'hexagons'");
  // The option and its value named (before 6 December 2026: "--horizon-factor
  // must be finite", "the horizon must be positive, got -1.5 mm",
  // "--gmsh-time-limit must be a positive number of seconds").
  expect_pd_mesh_failure(geo + " --spacing 0.5mm -m nan", out, "--horizon-factor nan: must be a finite number");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm -m -3", out,
                         "--horizon-factor -3: the horizon must be positive, got -1.5 mm");
  // A length, a word or hexadecimal for the factor, minutes for the time
  // limit: before 7 December 2026 Boost's "the argument ('3mm') for option
  // '--horizon-factor' is invalid", which said neither what the option takes
  // nor that a length is --horizon's.
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {"-m 2mm", "--horizon-factor 2mm: a factor is a number of spacings, without a unit (delta = m dx, e.g. -m "
                      "3); a horizon as a length is --horizon 2mm"},
           {"-m abc", "--horizon-factor abc: expected a number of spacings (delta = m dx, e.g. -m 3)"},
           {"-m 0x4", "--horizon-factor 0x4: expected a number of spacings (delta = m dx, e.g. -m 3)"},
           {"-m 3 --gmsh-time-limit 5min",
            "--gmsh-time-limit 5min: expected a number of seconds (e.g. 600 for ten minutes; the default is 300)"}})
    expect_pd_mesh_refusal_alone(geo + " --spacing 0.5mm " + arguments, out, message);
  // (Before 7 December 2026: "the size must be positive, got 'infGB'".)
  expect_pd_mesh_failure(geo + " --spacing 0.5mm -m 3 --max-memory infGB", out,
                         "pd-mesh: error: --max-memory: 'infGB' is not a finite size (e.g. 64GB, 500MB)\n");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm -m 3 --max-memory 0GB", out,
                         "pd-mesh: error: --max-memory: the size must be positive, got '0GB'\n");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm -m 3 --gmsh-time-limit 0", out,
                         "--gmsh-time-limit 0: must be a positive number of seconds");
  // Above a year: a slip, whose waits in nanoseconds or milliseconds would
  // overflow (before 6 December 2026, undefined behaviour, no word).
  expect_pd_mesh_failure(geo + " --spacing 0.5mm -m 3 --gmsh-time-limit 1e300", out,
                         "--gmsh-time-limit 1e+300: more than a year (31536000 s); the limit is in seconds, and gmsh "
                         "takes minutes (default 300)");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm -m 3 --gmsh-time-limit 31536001", out,
                         "--gmsh-time-limit 31536001: more than a year (31536000 s)");
  {
    // A year itself is taken, with the free regions meshed by the worker,
    // whose wait (over poll's 24.8 days) is made in several polls.
    const auto year = mesher_temp("a_year_limit.pdp");
    std::filesystem::remove(year);
    const auto run = run_pd_mesh(geo + " --spacing 0.5mm -m 3 --grid free --gmsh-time-limit 31536000 -o " + year);
    INFO(run.err);
    CHECK(run.status == 0);
    CHECK(std::filesystem::exists(year));
  }
  // The padding sizes NB-NUG's boxes: before 6 December 2026 the uniform and
  // free grids dropped it without a word.
  expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm --grid uniform --padding 5mm", out,
                         "--padding 5mm needs --grid nbnug (the uniform grid has no boxes around holes to pad)");
  expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 2mm --grid free --padding 5mm", out,
                         "--padding 5mm needs --grid nbnug (the free grid has no boxes around holes to pad)");
  // 20 mm is not a multiple of 0.3 mm; the nearest spacing that fits is 20/67 mm.
  expect_pd_mesh_failure(geo + " --spacing 0.3mm --horizon 1.2mm", out, "nearest spacing that fits both sides is 0.298507");
  // A character after the length: before, the advice was to write '2mm,mm'.
  expect_pd_mesh_failure(geo + " --spacing 2mm, --horizon-factor 3", out,
                         "--spacing: '2mm,' has characters after the length '2mm' (','); give one length, e.g. '2mm'");
  expect_pd_mesh_failure(geo + " --spacing 2mm,3mm --horizon-factor 3", out,
                         "--spacing: '2mm,3mm' is not a length (a number with a unit, e.g. 0.5mm)");
}

// An option given an empty value (an unset shell variable: `--vtk "$VIEW"`)
// read as the option left out: before 6 December 2026 `--vtk ''` wrote no
// view, `--refine-region ''` meshed without refinement, `--max-memory ''`
// took the machine's memory, `--horizon ''` beside -m took -m, exit 0.
TEST_CASE("pd-mesh refuses an option given an empty value by its name", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  for (const std::string option : {"--vtk", "--refine-region", "--max-memory", "--horizon", "--padding",
                                   "--box-spacing", "--graded-spacing", "--horizon-smoothing", "--loading-layer-depth"})
    expect_pd_mesh_failure(geo + " --spacing 1mm -m 3 " + option + " ''", out,
                           "pd-mesh: error: " + option + ": the value is empty (''; an unset shell variable?): give "
                           "one, or leave " + option + " out");
  // -o '' (the output named by its long form).
  std::filesystem::remove(out);
  const auto run = run_pd_mesh(geo + " --spacing 1mm -m 3 -o ''");
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::Contains("pd-mesh: error: --output: the value is empty"));
}

// The geometry file left out, or given as an empty name (`pd-mesh "$GEO"`
// with GEO unset): before 7 December 2026 both were "no geometry file given
// (pd-mesh --help shows the usage)", which said neither how to give it nor
// that a name was given empty. The help says what GEOMETRY.geo is.
TEST_CASE("pd-mesh says how to give the geometry file when it is left out or empty", "[mesher][cli]") {
  const auto out = mesher_temp("never.pdp");
  const std::string example = "e.g. pd-mesh plate.geo --spacing 0.05mm --horizon 0.2mm -o plate.pdp\n";
  for (const std::string arguments : {"--spacing 1mm -m 3", "--spacing 1mm -m 3 --vtk view.vtp"}) {
    std::filesystem::remove(out);
    const auto run = run_pd_mesh(arguments + " -o " + out);
    CHECK(run.status == 1);
    CHECK(run.err == "pd-mesh: error: no geometry file given: give the plate's .geo file as the command's one "
                     "argument, " + example);
  }
  for (const std::string arguments : {"'' --spacing 1mm -m 3", "--spacing 1mm -m 3 --geometry ''"}) {
    const auto run = run_pd_mesh(arguments + " -o " + out);
    INFO(arguments);
    CHECK(run.status == 1);
    CHECK(run.err == "pd-mesh: error: the geometry file's name is empty (''; an unset shell variable?): give the "
                     "plate's .geo file, " + example);
  }
  CHECK_FALSE(std::filesystem::exists(out));
  const std::string help = mesher_temp("pd_mesh_help_geometry.txt");
  REQUIRE(run_shell(std::string(PD_MESH_EXE) + " --help > " + help) == 0);
  CHECK_THAT(file_text(help), Catch::Contains("Usage: pd-mesh GEOMETRY.geo --spacing DX (--horizon DELTA | "
                                              "--horizon-factor M) -o OUT.pdp [options]\nGEOMETRY.geo: the plate, a "
                                              "gmsh geometry file (in mm unless --geo-unit says otherwise).\n"));
}

// Boost's prefix guessing took `--gri uniform` for --grid uniform and
// `--horizon-f 3` for --horizon-factor 3: undocumented, and an option added
// later that begins the same way would change what an abbreviation means.
// Since 7 December 2026 an abbreviation is an unknown option, the options
// that begin with it named.
TEST_CASE("pd-mesh takes no abbreviated option and names the full ones", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("abbreviated.pdp");
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {"--spacing 1mm -m 3 --gri uniform", "--gri: no such option; did you mean --grid?"},
           {"--spacing 1mm -m 3 --gri=uniform", "--gri: no such option; did you mean --grid?"},
           {"--spacing 1mm --horizon-f 3", "--horizon-f: no such option; did you mean --horizon-factor?"},
           {"--spacing 1mm -m 3 --Grid uniform", "--Grid: no such option; did you mean --grid?"},
           {"--spacing 1mm -m 3 --refine 0mm,0mm,4mm,4mm",
            "--refine: no such option; did you mean --refine-region or --refine-factor?"},
           // A misspelling: the nearest option within two edits (before 7
           // December 2026 the --help pointer alone); none near, the pointer.
           {"--spacing 1mm -m 3 --spaceing 1mm", "--spaceing: no such option; did you mean --spacing?"},
           {"--spacing 1mm -m 3 --horizon-factr 3", "--horizon-factr: no such option; did you mean --horizon-factor?"},
           {"--spacing 1mm -m 3 --vkt view.vtp", "--vkt: no such option; did you mean --vtk?"},
           {"--spacing 1mm -m 3 --xyz 1", "--xyz: no such option (pd-mesh --help lists them)"}}) {
    std::filesystem::remove(out);
    const auto run = run_pd_mesh(geo + " " + arguments + " -o " + out);
    INFO(arguments);
    CHECK(run.status == 1);
    CHECK(run.err == "pd-mesh: error: " + message + "\n");
    CHECK_FALSE(std::filesystem::exists(out));
  }
  // Written in full, the same command meshes.
  CHECK(run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 --grid uniform -o " + out).status == 0);
}

// A command line the frame would misread, refused naming the option and what
// to do, before 7 December 2026: an option given twice, or the geometry given
// as the argument and as --geometry (Boost's "option '--spacing' cannot be
// specified more than once" named neither the values nor what to do); an
// option left without its value, empty after '=' (`--spacing=`: "the argument
// for option '--spacing' should follow immediately after the equal sign"), at
// the end (`--vtk`: "the required argument for option '--vtk' is missing") or
// before another option (`--vtk --spacing 1mm` took --spacing for the view's
// name, then called 1mm an unexpected argument).
TEST_CASE("pd-mesh names an option given twice or left without its value, and what to do", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  const std::string no_vtk = "give one (--vtk VALUE, pd-mesh --help says what it takes), or leave --vtk out";
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {" --spacing 1mm --spacing=2mm -m 3", "--spacing given twice ('--spacing 1mm', then '--spacing=2mm'): give "
                                                "it once, with the value you mean"},
           {" --spacing 1mm -m 3 -m4 --horizon-factor 5", "--horizon-factor given 3 times ('-m 3', '-m4', then "
                                                          "'--horizon-factor 5'): give it once, with the value you mean"},
           {" --geometry other.geo --spacing 1mm -m 3", "GEOMETRY given twice ('" + geo + "', then '--geometry "
                                                        "other.geo'): give it once, as the command's first argument "
                                                        "(--geometry is another name for it)"},
           {" --spacing= -m 3", "--spacing: the value is empty (''; an unset shell variable?): give one, or leave "
                                "--spacing out"},
           {" --vtk --spacing 1mm -m 3", "--vtk: no value after it ('--spacing', the word after it, is an option): " +
                                             no_vtk}})
    expect_pd_mesh_refusal_alone(geo + arguments, out, message);
  const auto run = run_pd_mesh(geo + " --spacing 1mm -m 3 -o " + out + " --vtk");
  CHECK(run.status == 1);
  CHECK(run.err == "pd-mesh: error: --vtk: no value after it: " + no_vtk + "\n");
  CHECK_FALSE(std::filesystem::exists(out));
}

// A geometry file whose name begins with '-' reads as an option: before 7
// December 2026 "-p.geo: no such option" alone, which did not say that the
// file is given as ./-p.geo. A name that is no file gets no such hint.
TEST_CASE("pd-mesh tells a geometry file named with a leading dash to be written with ./", "[mesher][cli]") {
  const auto folder = std::filesystem::path(mesher_temp("dash-named")).string();
  std::filesystem::create_directories(folder);
  std::filesystem::copy_file(std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo", folder + "/-p.geo",
                             std::filesystem::copy_options::overwrite_existing);
  const std::string err = folder + "/stderr.txt";
  const auto run_in_folder = [&](const std::string& arguments) {
    return run_shell("cd '" + folder + "' && " + PD_MESH_EXE + " " + arguments + " 2> '" + err + "' > /dev/null");
  };
  CHECK(run_in_folder("-p.geo --spacing 1mm -m 3 -o x.pdp") == 1);
  CHECK(file_text(err) == "pd-mesh: error: -p.geo: no such option (pd-mesh --help lists them); for the file -p.geo "
                          "write ./-p.geo (a name that begins with '-' reads as an option)\n");
  CHECK(run_in_folder("-q.geo --spacing 1mm -m 3 -o x.pdp") == 1);
  CHECK(file_text(err) == "pd-mesh: error: -q.geo: no such option (pd-mesh --help lists them)\n");
  CHECK_FALSE(std::filesystem::exists(folder + "/x.pdp"));
  CHECK(run_in_folder("./-p.geo --spacing 1mm -m 3 -o x.pdp") == 0);
}

// A name with a space at its end (copied with it): before 7 December 2026
// pd-mesh wrote "x.pdp " with the advice to write -o "x.pdp .pdp", and a
// geometry "plate.geo " was "not found" with the space unseen.
TEST_CASE("pd-mesh refuses a file name that begins or ends with white space and names none", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("spaced.pdp");
  std::filesystem::remove(out);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"'" + geo + " ' --spacing 1mm -m 3 -o " + out,
       "'" + geo + " ': the name ends in a space, and no file or folder has that name (" + geo +
           ", without it, exists): give it without, " + geo},
      {geo + " --spacing 1mm -m 3 -o '" + out + " '",
       "-o '" + out + " ': the name ends in a space, and no file or folder has that name: give it without, -o " + out},
      {"' " + geo + "' --spacing 1mm -m 3 -o " + out,
       "' " + geo + "': the name begins with a space, and no file or folder has that name (" + geo +
           ", without it, exists): give it without, " + geo},
      {geo + " --spacing 1mm -m 3 -o " + out + " --vtk '" + out + ".vtp '",
       "--vtk '" + out + ".vtp ': the name ends in a space, and no file or folder has that name: give it without, "
       "--vtk " + out + ".vtp"}};
  for (const auto& [arguments, message] : cases) {
    const auto run = run_pd_mesh(arguments);
    INFO(arguments);
    CHECK(run.status == 1);
    CHECK(run.err == "pd-mesh: error: " + message + "\n");
  }
  CHECK_FALSE(std::filesystem::exists(out));
  CHECK_FALSE(std::filesystem::exists(out + " "));
  CHECK_FALSE(std::filesystem::exists(out + ".vtp "));
}

// A long option written with one dash is a short one with its value joined:
// before 7 December 2026 `-output=x.pdp` wrote the particle file "utput=x.pdp".
TEST_CASE("pd-mesh refuses a long option written with one dash", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto folder = std::filesystem::path(mesher_temp("one_dash")).string();
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const std::string err = folder + "/stderr.txt";
  CHECK(run_shell("cd '" + folder + "' && " + PD_MESH_EXE + " " + geo + " --spacing 1mm -m 3 -output=x.pdp 2> '" +
                  err + "' > /dev/null") == 1);
  CHECK(file_text(err) == "pd-mesh: error: -output=x.pdp: read as -o utput=x.pdp (a short option takes the rest of "
                          "its word for its value); a long option takes two dashes: --output=x.pdp\n");
  CHECK_FALSE(std::filesystem::exists(folder + "/utput=x.pdp"));
}

// More memory than a 64-bit address reaches: before 7 December 2026 taken
// as a budget (1e300GB), or as none at all (1e300TB, beyond a double's range).
TEST_CASE("pd-mesh refuses a --max-memory beyond what a 64-bit machine can address", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  for (const std::string size : {"1e300GB", "1e300TB", "2e7TB", "16777217TiB"})
    expect_pd_mesh_refusal_alone(geo + " --spacing 0.5mm -m 3 --max-memory " + size, out,
                                 "--max-memory: '" + size + "' is more memory than a 64-bit machine can address "
                                 "(2^64 bytes, about 1.8e7 TB): give the memory pd-mesh may use, e.g. 64GB");
}

// A limit shorter than gmsh takes to read a small geometry: before 7
// December 2026 it meshed on some runs and stopped on others, as gmsh or
// its watchdog came first (c1_plate_hole.geo at 0.001 s: 3 runs of 5 ended
// in "gmsh did not finish reading the geometry within 0.001 s", 2 meshed).
// Now refused, the same way on every run.
TEST_CASE("pd-mesh refuses a --gmsh-time-limit below a second, the same way on every run", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  for (const auto& [limit, shown] : std::vector<std::pair<std::string, std::string>>{
           {"1e-9", "1e-09"}, {"1e-9", "1e-09"}, {"0.001", "0.001"}, {"0.001", "0.001"}, {"0.999", "0.999"}})
    expect_pd_mesh_refusal_alone(geo + " --spacing 0.5mm -m 3 --gmsh-time-limit " + limit, out,
                                 "--gmsh-time-limit " + shown + ": less than 1 s, the shortest limit taken: gmsh "
                                 "reads even a small geometry in tens to hundreds of ms, as loaded as the machine is, "
                                 "so a shorter limit would stop some runs and not others; give at least 1 (the "
                                 "default is 300)");
}

// A folder of the path with white space at an end, which names nothing:
// before 7 December 2026 only the ends of the whole name were looked at, and
// pd-mesh made the folder "out " and wrote the particle file into it.
TEST_CASE("pd-mesh refuses an output path through a folder name with white space at an end", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto folder = std::filesystem::path(mesher_temp("spaced_folder")).string();
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder + "/out");
  const std::string err = folder + "/stderr.txt";
  const auto refused = [&](const std::string& arguments, const std::string& message) {
    INFO(arguments);
    CHECK(run_shell("cd '" + folder + "' && " + PD_MESH_EXE + " " + geo + " --spacing 1mm -m 3 " + arguments +
                    " 2> '" + err + "' > /dev/null") == 1);
    CHECK(file_text(err) == "pd-mesh: error: " + message + "\n");
  };
  refused("-o 'out /x.pdp'", "-o 'out /x.pdp': its part 'out ' ends in a space, and no folder or file has that "
                             "name (the folder out, without it, exists): give it without, -o out/x.pdp");
  refused("-o 'out/ new/x.pdp'", "-o 'out/ new/x.pdp': its part ' new' begins with a space, and no folder or file "
                                 "has that name: give it without, -o out/new/x.pdp");
  refused("-o out/x.pdp --vtk 'out/\tv /x.vtp'", "--vtk 'out/\tv /x.vtp': its part '\tv ' begins with a tab and "
                                                "ends in a space, and no folder or file has that name: give it "
                                                "without, --vtk out/v/x.vtp");
  CHECK_FALSE(std::filesystem::exists(folder + "/out "));
  CHECK_FALSE(std::filesystem::exists(folder + "/out/ new"));
  // A folder of that name that exists is the user's, and is taken.
  std::filesystem::create_directories(folder + "/out ");
  CHECK(run_shell("cd '" + folder + "' && " + PD_MESH_EXE + " " + geo + " --spacing 1mm -m 3 -o 'out /x.pdp' 2> '" +
                  err + "' > /dev/null") == 0);
  CHECK(std::filesystem::exists(folder + "/out /x.pdp"));
}

// `-o=plate.pdp` took '=plate.pdp' as the value: before 7 December 2026
// pd-mesh wrote a file named "=plate.pdp", exit 0.
TEST_CASE("pd-mesh refuses a short option joined to its value by an equals sign", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto folder = std::filesystem::path(mesher_temp("joined")).string();
  std::filesystem::create_directories(folder);
  const std::string err = folder + "/stderr.txt";
  CHECK(run_shell("cd '" + folder + "' && " + PD_MESH_EXE + " " + geo + " --spacing 1mm -m 3 -o=plate.pdp 2> '" +
                  err + "' > /dev/null") == 1);
  CHECK(file_text(err) == "pd-mesh: error: -o=plate.pdp: a short option takes its value after a space, -o "
                          "plate.pdp (or --output=plate.pdp); joined to it, '=' would be part of the value\n");
  CHECK_FALSE(std::filesystem::exists(folder + "/=plate.pdp"));
  expect_pd_mesh_refusal_alone(geo + " --spacing 1mm -m=3", folder + "/x.pdp",
                               "-m=3: a short option takes its value after a space, -m 3 (or --horizon-factor=3); "
                               "joined to it, '=' would be part of the value");
}

// A length typed with a space before its unit (`--spacing 0.5 mm`) leaves the
// unit as a second positional argument: before 7 December 2026 Boost's "too
// many positional options have been specified on the command line" named
// neither it nor the cause.
TEST_CASE("pd-mesh names an argument beyond the geometry file, such as a unit typed after a space",
          "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  expect_pd_mesh_failure(geo + " --spacing 0.5 mm --horizon 1.5mm", out,
                         "pd-mesh: error: unexpected argument 'mm' after '" + geo +
                             "', the one argument pd-mesh takes besides its options: an option's value is one "
                             "word, with no space before its unit (0.5mm, 80us) or around '=', and in quotes "
                             "where it holds spaces");
  // Two geometry files: both named, each in its place.
  expect_pd_mesh_failure(geo + " " + geo + " extra.geo --spacing 0.5mm --horizon 1.5mm", out,
                         "pd-mesh: error: unexpected arguments '" + geo + "', 'extra.geo' after '" + geo + "'");
  // --help still answers with a stray argument beside it.
  const auto help = run_pd_mesh("--help stray");
  CHECK(help.status == 0);
}

// 1e-300 mm squared is 0 in double: the size estimate printed "about inf
// particles and -nan bonds, -nan MB of memory" and refused with those.
// Spacings outside the particle file's 1 nm to 1 km are refused at once, and
// no count beyond the range of numbers is printed (a plate 1e200 mm across).
TEST_CASE("pd-mesh refuses a spacing beyond the particle file's range by name and never prints inf or nan",
          "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  for (const std::string spacing : {"1e-300mm", "1e300mm"}) {
    std::filesystem::remove(out);
    const auto run = run_pd_mesh(geo + " --spacing " + spacing + " --horizon-factor 3 -o " + out);
    INFO(run.err);
    CHECK(run.status == 1);
    CHECK_THAT(run.err, Catch::StartsWith("pd-mesh: error: --spacing " + spacing + " is 1e") &&
                            Catch::Contains(" spacing a particle file holds (1 nm to 1 km)"));
    CHECK_THAT(run.err, !Catch::Contains("inf") && !Catch::Contains("nan"));
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  const auto huge = write_text_file("huge.geo", quadrilateral_plate("0, 0, 0", "1e200, 0, 0", "1e200, 1e200, 0",
                                                                    "0, 1e200, 0"));
  const auto run = run_pd_mesh(huge + " --spacing 1mm --horizon-factor 3 -o " + out);
  INFO(run.err);
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::Contains(huge + ": this grid would have more particles or bonds than can be counted"));
  CHECK_THAT(run.err, !Catch::Contains("inf ") && !Catch::Contains("nan"));
}

// The spacing pd-mesh suggests is printed to ten digits: 50 mm / 110 as
// 0.4545454545 mm, 5e-11 mm short, so that the lattice's right side missed
// the plate's by 1e-10 spacings. Before, that failed with "internal error: a
// free region's boundary does not close near (50, 0) mm"; now the lattice
// takes the exact division the print meant (its spacing in the file is
// 50 mm / 110 to round-off).
TEST_CASE("pd-mesh meshes with the spacing it suggests", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c3a_pores.geo";
  const auto out = mesher_temp("suggested.pdp");
  const auto refused = run_pd_mesh(geo + " --spacing 0.45mm --horizon 1.8mm -o " + out);
  REQUIRE(refused.status != 0);
  const std::string flag = "(--spacing ";
  const auto at = refused.err.find(flag);
  REQUIRE(at != std::string::npos);
  const std::string suggested = refused.err.substr(at + flag.size(), refused.err.find(')', at) - at - flag.size());
  CHECK(suggested == "0.4545454545mm");
  const auto run = run_pd_mesh(geo + " --spacing " + suggested + " --horizon 1.8mm -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  CHECK(pd::read_particle_file(out).spacing == Approx(50e-3 / 110).epsilon(1e-14));
}

TEST_CASE("pd-mesh output is byte-identical across runs and opens", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto a = mesher_temp("c1_a.pdp"), b = mesher_temp("c1_b.pdp"), vtp = mesher_temp("c1_a.vtp");
  REQUIRE(run_pd_mesh(geo + " --spacing 0.2mm --horizon 0.8mm -o " + a + " --vtk " + vtp).status == 0);
  REQUIRE(run_pd_mesh(geo + " --spacing 0.2mm --horizon 0.8mm -o " + b).status == 0);
  CHECK(file_text(a) == file_text(b));
  const auto p = pd::read_particle_file(a);
  // The .vtp opens in VTK's own reader with one point per particle and the documented arrays.
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(vtp.c_str());
  reader->Update();
  REQUIRE(reader->GetOutput()->GetNumberOfPoints() == static_cast<vtkIdType>(p.size()));
  for (const char* name : {"volume", "region", "horizon", "neighbors", "neighborhood_area"})
    CHECK(reader->GetOutput()->GetPointData()->GetArray(name) != nullptr);
  CHECK(reader->GetOutput()->GetPointData()->GetArray("volume")->GetTuple1(0) == p.volume[0]);
  CHECK(p.find_set("hole_1") != nullptr);
  CHECK(p.find_set("top") != nullptr);
  CHECK_THAT(p.provenance, Catch::Contains("c1_plate_hole.geo") && Catch::Contains("\"grid\": \"nbnug\""));
}

// The provenance is JSON text naming the geometry file by its path. Before 7
// December 2026 a tab in the path and a byte of another encoding (é in
// Latin-1, 0xE9) were written as they were, which JSON readers refuse.
TEST_CASE("a geometry folder named with a tab or a byte of another encoding is written to the provenance as JSON text",
          "[mesher][cli]") {
  const std::string folder = "geometry_a\tb\xe9" "c";
  const auto geo = mesher_temp(folder + "/plate_no_pores.geo");
  fs::create_directories(fs::path(geo).parent_path());
  fs::copy_file(std::string(PD_GEOMETRY_DIR) + "/plate_no_pores.geo", geo, fs::copy_options::overwrite_existing);
  const auto out = mesher_temp("json_path.pdp");
  const auto run = run_pd_mesh("\"" + geo + "\" --spacing 2.5mm --horizon-factor 3 --grid uniform -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  const std::string provenance = pd::read_particle_file(out).provenance;
  CHECK_THAT(provenance, Catch::Contains("\"geometry\": \"" + mesher_temp("geometry_a\\tb\\ufffdc") +
                                         "/plate_no_pores.geo\", "));
  CHECK(std::none_of(provenance.begin(), provenance.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }));
  CHECK(provenance.find('\xe9') == std::string::npos);
}

namespace {
// The C1 plates of the determinism tests below: gmsh meshed the box, and
// every plate equals the first in all but the provenance.
void check_same_c1_plates(const std::vector<pd::ParticleSet>& plates) {
  const auto& a = plates[0];
  CHECK(std::count(a.region.begin(), a.region.end(), std::uint8_t{1}) > 1000);
  for (std::size_t k = 1; k < plates.size(); ++k) {
    INFO("plate " << k << " against the first");
    const auto& b = plates[k];
    REQUIRE(a.size() == b.size());
    CHECK(a.region == b.region);
    CHECK(a.x == b.x);
    CHECK(a.y == b.y);
    CHECK(a.volume == b.volume);
    CHECK(a.horizon == b.horizon);
    CHECK(a.family_offsets == b.family_offsets);
    CHECK(a.neighbors == b.neighbors);
    CHECK(a.partial_volume == b.partial_volume);
  }
}
}  // namespace

TEST_CASE("pd-mesh gives the same particles whichever folder holds the geometry file", "[mesher][cli]") {
  // Reference: the same geometry meshed from another folder. The C1 plate
  // with its box meshed at dx / 4 (free quads from gmsh, whose last bits
  // follow the addresses of the mesh worker's allocations) from folders whose
  // names differ in length by 8 to 24 characters, which used to change the
  // sizes of the worker's blocks. Only the provenance (the path) may differ.
  const std::string source = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  std::vector<pd::ParticleSet> plates;
  for (const std::size_t longer : {0, 8, 24}) {
    const std::string folder = "geometry" + std::string(longer, 'x');
    const auto geo = mesher_temp(folder + "/c1_plate_hole.geo");
    fs::create_directories(fs::path(geo).parent_path());
    fs::copy_file(source, geo, fs::copy_options::overwrite_existing);
    const auto out = mesher_temp(folder + ".pdp");
    const auto run = run_pd_mesh(geo + " --spacing 0.4mm --horizon-factor 3 --box-spacing 0.1mm -o " + out);
    INFO(run.err);
    REQUIRE(run.status == 0);
    plates.push_back(pd::read_particle_file(out));
  }
  check_same_c1_plates(plates);
}

TEST_CASE("pd-mesh gives the same particles wherever the program is and whichever folder it runs in",
          "[mesher][cli]") {
  // Reference: the same program, geometry and options run from another
  // place. gmsh keeps its executable's path and the working directory in
  // heap strings, whose lengths used to move the mesh worker's allocations
  // and with them the last bits of the free quads (the C1 box at dx / 4).
  // Copies of pd-mesh in folders whose names differ in length by 40 and 80
  // characters, each started from its own folder.
  const std::string geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  std::vector<pd::ParticleSet> plates;
  for (const std::size_t longer : {0, 40, 80}) {
    const auto folder = mesher_temp("program" + std::string(longer, 'x'));
    fs::create_directories(folder);
    const auto program = folder + "/pd-mesh";
    fs::copy_file(PD_MESH_EXE, program, fs::copy_options::overwrite_existing);
    const auto out = folder + ".pdp", err = folder + ".err";
    const std::string command = "cd " + folder + " && timeout 600 " + program + " " + geo +
                                " --spacing 0.4mm --horizon-factor 3 --box-spacing 0.1mm -o " + out +
                                " > /dev/null 2> " + err;
    const int status = run_shell(command);
    INFO(file_text(err));
    REQUIRE(status == 0);
    plates.push_back(pd::read_particle_file(out));
  }
  check_same_c1_plates(plates);
}

TEST_CASE("named physical curve groups become boundary sets", "[mesher][cli]") {
  const auto geo = write_text_file("named.geo", rectangle_20 + circle_hole(10, 10, 3) +
                                              "Plane Surface(1) = {1, 2};\n"
                                              "Physical Curve(\"clamp\") = {4};\n"
                                              "Physical Curve(\"pore\") = {10, 11};\n");
  const auto out = mesher_temp("named.pdp");
  const auto run = run_pd_mesh(geo + " --spacing 0.5mm --horizon 1.5mm -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  const auto p = pd::read_particle_file(out);
  // Curve 4 is the left edge and curves 10, 11 the hole: the same particles
  // as the automatic sets, found through the user's names.
  REQUIRE(p.find_set("clamp") != nullptr);
  REQUIRE(p.find_set("pore") != nullptr);
  CHECK(p.find_set("clamp")->particles == p.find_set("left")->particles);
  CHECK(p.find_set("pore")->particles == p.find_set("hole_1")->particles);
  // Within one horizon (1.5 mm) of x = 0: the first three 0.5 mm columns.
  CHECK(p.find_set("left")->particles.size() == 3 * 40);
}

// Sets are made of curves: a named group of points or of the surface gives
// none, and is said to once (before 7 December 2026 it was dropped without a
// word, and a scene's set = "grip" learnt from pd-solve only that no such set
// exists). Unnamed groups, which give no name to look for, are quiet.
TEST_CASE("a named physical group of points or of the surface is warned to give no set", "[mesher][cli]") {
  const auto out = mesher_temp("point_group.pdp");
  const auto geo = write_text_file("point_group.geo", rectangle_20 + "Plane Surface(1) = {1};\n"
                                                                     "Physical Point(\"grip\") = {3};\n"
                                                                     "Physical Surface(\"plate\") = {1};\n"
                                                                     "Physical Point(7) = {1};\n"
                                                                     "Physical Curve(\"clamp\") = {4};\n");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon 3mm -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  const std::string point_warning =
      "pd-mesh: warning: " + geo + ": Physical Point(\"grip\") makes no boundary set: pd-mesh makes sets of Physical "
      "Curve groups only (docs/mesher.md, \"Boundary sets\"); a scene acts on the particle nearest a point with "
      "nearest = [x, y] (docs/scenes.md)\n";
  const std::string surface_warning =
      "pd-mesh: warning: " + geo + ": Physical Surface(\"plate\") makes no boundary set: pd-mesh makes sets of "
      "Physical Curve groups only (docs/mesher.md, \"Boundary sets\"); a scene's set = \"all\" is every particle of "
      "the plate\n";
  CHECK_THAT(run.err, Catch::Contains(point_warning));
  CHECK_THAT(run.err, Catch::Contains(surface_warning));
  // Once each, and nothing about the unnamed group or the curve group.
  CHECK(run.err.size() == point_warning.size() + surface_warning.size());
  const auto p = pd::read_particle_file(out);
  CHECK(p.find_set("grip") == nullptr);
  CHECK(p.find_set("plate") == nullptr);
  CHECK(p.find_set("clamp") != nullptr);
}

// A group of curves beside the plate (30 mm off a 20 mm square) gives a set
// without a particle: warned about with the curves' place (before 7 December
// 2026 written without a word, and a scene loading it refused by pd-solve:
// "set 'far' contains no particle"). A group of a curve across the plate's
// inside (not on the boundary) holds the particles near it, quietly.
TEST_CASE("a physical curve group beside the plate is warned to hold no particle", "[mesher][cli]") {
  const auto out = mesher_temp("far_group.pdp");
  const auto geo = write_text_file("far_group.geo", rectangle_20 + "Plane Surface(1) = {1};\n"
                                                                  "Point(5) = {50, 10, 0}; Point(6) = {60, 10, 0};\n"
                                                                  "Line(5) = {5, 6};\n"
                                                                  "Point(7) = {5, 10, 0}; Point(8) = {15, 10, 0};\n"
                                                                  "Line(6) = {7, 8};\n"
                                                                  "Physical Curve(\"far\") = {5};\n"
                                                                  "Physical Curve(\"midline\") = {6};\n");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon 3mm -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  CHECK(run.err == "pd-mesh: warning: " + geo + ": Physical Curve(\"far\") holds no particle: its curves (x 50 to 60 "
                   "mm, y 10 to 10 mm) lie farther than 3 mm (the horizon) from every particle that sees them "
                   "through the material; a scene that loads the set 'far' is refused\n");
  const auto p = pd::read_particle_file(out);
  REQUIRE(p.find_set("far") != nullptr);
  CHECK(p.find_set("far")->particles.empty());
  REQUIRE(p.find_set("midline") != nullptr);
  CHECK_FALSE(p.find_set("midline")->particles.empty());
}

// A group named after an automatic set replaces it (docs/mesher.md,
// "Boundary sets"): a stretch of that side or the side redrawn is quiet; a
// group on another side (curve 2 is the right edge) shares no particle with
// the set it replaces and is warned about. Before the third sitting of 5 December 2026 the
// scene's "left" then pulled the right edge without a word.
TEST_CASE("a physical group that replaces an automatic set on another side is warned about", "[mesher][cli]") {
  const auto out = mesher_temp("renamed.pdp");
  const auto mesh = [&](const std::string& groups) {
    const auto geo = write_text_file("renamed.geo", rectangle_20 + "Plane Surface(1) = {1};\n" + groups);
    return run_pd_mesh(geo + " --spacing 0.5mm --horizon 1.5mm -o " + out);
  };
  const auto elsewhere = mesh("Physical Curve(\"left\") = {2};\n");
  INFO(elsewhere.err);
  REQUIRE(elsewhere.status == 0);
  CHECK_THAT(elsewhere.err, Catch::Contains("renamed.geo: Physical Curve(\"left\") replaces the automatic set 'left' "
                                            "(120 particles) and has no particle in common with it: its 120 particles "
                                            "lie in x 18.75 to 19.75 mm, y 0.25 to 19.75 mm"));
  CHECK(pd::read_particle_file(out).find_set("left")->particles ==
        pd::read_particle_file(out).find_set("right")->particles);
  const auto same_side = mesh("Physical Curve(\"left\") = {4};\nPhysical Curve(\"top\") = {3};\n");
  REQUIRE(same_side.status == 0);
  CHECK_THAT(same_side.err, !Catch::Contains("replaces the automatic set"));
}

TEST_CASE("the summary says curved only for curved boundaries", "[mesher][cli]") {
  const auto out = mesher_temp("summary.pdp");
  const auto summary = mesher_temp("summary.txt");
  const auto run_to = [&](const std::string& arguments) {
    const std::string command = std::string(PD_MESH_EXE) + " " + arguments + " -o " + out + " > " + summary + " 2>&1";
    REQUIRE(std::system(command.c_str()) == 0);
    return file_text(summary);
  };
  // A square hole turned by 45 degrees: straight edges off the lattice lines.
  const auto diamond = write_text_file("diamond_hole.geo", rectangle_20 +
                                                         "Point(10) = {10, 7, 0}; Point(11) = {13, 10, 0}; Point(12) = {10, 13, 0};"
                                                         " Point(13) = {7, 10, 0};\n"
                                                         "Line(10) = {10, 11}; Line(11) = {11, 12}; Line(12) = {12, 13};"
                                                         " Line(13) = {13, 10};\n"
                                                         "Curve Loop(2) = {10, 11, 12, 13}; Plane Surface(1) = {1, 2};\n");
  const auto straight = run_to(diamond + " --spacing 0.5mm --horizon 1.5mm");
  INFO(straight);
  CHECK_THAT(straight, !Catch::Contains("curved") && Catch::Contains("straight boundary off the lattice lines"));
  const auto curved = run_to(std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo --spacing 0.5mm --horizon 1.5mm");
  INFO(curved);
  CHECK_THAT(curved, Catch::Contains("smallest centroid distance to a curved boundary") &&
                         Catch::Contains("edges on curved boundaries") && !Catch::Contains("straight boundary"));
}

// A 40 mm x 20 mm plate with two holes, meshed at 20 mm (m = 3): a 60 mm
// horizon on a 20 mm plate, and a sliver cell beside the smaller hole whose
// every bond would cross it. It still meshes, with a warning for each; at
// 1 mm neither warning comes.
// The reported cases: --horizon-factor 1e9 (and 1e5) counted the family of
// the size estimate cell by cell, (2m + 3)^2 cells, for minutes without a
// word; 1000 was refused with 4.4e9 bonds for 1,400 particles, more than every
// particle bonded with every other.
TEST_CASE("a horizon beyond the particle file's 64 spacings is refused at once, and no estimate exceeds N(N-1) bonds",
          "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";
  const auto out = mesher_temp("never.pdp");
  for (const std::string factor : {"1e9", "1e5", "1000", "65"}) {
    std::filesystem::remove(out);
    const auto run = run_pd_mesh(geo + " --spacing 0.5mm --horizon-factor " + factor + " -o " + out, 60);
    INFO("--horizon-factor " << factor << "\nstderr: " << run.err);
    CHECK(run.status == 1);
    CHECK(run.seconds < 5);  // before, 100 s and more
    const std::string written = factor == "1e9" ? "1e+09" : factor == "1e5" ? "100000" : factor;
    const std::string spacings = factor == "1e9" ? "1e+09" : factor == "1e5" ? "1e+05" : factor;
    CHECK_THAT(run.err, Catch::StartsWith("pd-mesh: error: --horizon-factor " + written + ": the horizon ") &&
                            Catch::Contains(" is " + spacings + " spacings of 0.5 mm, more than the 64 a particle "
                                            "file holds"));
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  expect_pd_mesh_failure(geo + " --spacing 0.5mm --horizon 300mm", out,
                         "--horizon 300mm: the horizon 300 mm is 600 spacings of 0.5 mm");
  // 64 spacings, wider than the plate: the memory check sees at most N(N-1)
  // directed bonds (1,399 particles estimated here), not 1,399 x 12,900.
  const auto wide = run_pd_mesh(geo + " --spacing 0.5mm --horizon-factor 64 --max-memory 1MB -o " + out, 60);
  INFO(wide.err);
  CHECK(wide.status == 1);
  CHECK_THAT(wide.err, Catch::Contains("about 1.4e+03 particles and 1.96e+06 bonds"));
}

TEST_CASE("pd-mesh warns of particles without bonds and of a horizon of half the plate or more", "[mesher][cli]") {
  const auto geo = write_text_file("coarse_grid.geo",
                                   "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 40, 20};\n"
                                   "Disk(2) = {15, 13.3, 0, 2};\nDisk(3) = {27, 7.1, 0, 1.2};\n"
                                   "BooleanDifference{ Surface{1}; Delete; }{ Surface{2, 3}; Delete; }\n");
  const auto coarse = run_pd_mesh(geo + " --spacing 20mm --horizon-factor 3 -o " + mesher_temp("coarse_grid.pdp"));
  INFO(coarse.err);
  REQUIRE(coarse.status == 0);
  CHECK_THAT(coarse.err, Catch::Contains("pd-mesh: warning: 1 particle has no bond (e.g. particle ") &&
                             Catch::Contains("it takes no part in a run"));
  CHECK_THAT(coarse.err, Catch::Contains("pd-mesh: warning: the horizon 60 mm is at least half the plate's narrower "
                                         "side (20 mm)"));
  // 15 mm on a 20 mm side: no particle is a horizon from both edges either.
  const auto half = run_pd_mesh(geo + " --spacing 5mm --horizon-factor 3 -o " + mesher_temp("coarse_grid.pdp"));
  CHECK_THAT(half.err, Catch::Contains("the horizon 15 mm is at least half the plate's narrower side (20 mm)"));
  const auto fine = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 -o " + mesher_temp("coarse_grid.pdp"));
  REQUIRE(fine.status == 0);
  CHECK_THAT(fine.err, !Catch::Contains("warning"));
}

// The reported case: a hole of radius 4 mm 0.4 mm below the top edge of a
// 40 x 20 mm plate. On a 1 mm lattice no cell centre lies in the ligament,
// so the uniform grid opens the hole to the edge: said on stderr, the file is
// still written (the uniform grid's staircase is by design). The NB-NUG and
// free grids keep the ligament and say nothing.
TEST_CASE("a uniform grid that drops a ligament narrower than dx says where and how wide", "[mesher][cli]") {
  const auto geo = write_text_file(
      "ligament_04.geo",
      "Point(1) = {0,0,0}; Point(2) = {40,0,0}; Point(3) = {40,20,0}; Point(4) = {0,20,0};\n"
      "Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,1};\n"
      "Point(5) = {20,15.6,0}; Point(6) = {24,15.6,0}; Point(7) = {20,19.6,0}; Point(8) = {16,15.6,0}; "
      "Point(9) = {20,11.6,0};\n"
      "Circle(5) = {6,5,7}; Circle(6) = {7,5,8}; Circle(7) = {8,5,9}; Circle(8) = {9,5,6};\n"
      "Curve Loop(1) = {1:4}; Curve Loop(2) = {5:8};\nPlane Surface(1) = {1,2};\n");
  const std::string settings = " --spacing 1mm --horizon 3mm -o " + mesher_temp("ligament_04.pdp");
  const auto uniform = run_pd_mesh(geo + settings + " --grid uniform");
  INFO(uniform.err);
  CHECK(uniform.status == 0);
  CHECK(fs::is_regular_file(mesher_temp("ligament_04.pdp")));
  CHECK_THAT(uniform.err, Catch::Contains("pd-mesh: warning: " + geo + ": the uniform grid has no particle in the "
                                          "material between hole_1 and the outer boundary near (20, 19.8) mm, 0.4 mm "
                                          "wide (0.4 dx), narrower than the spacing 1 mm") &&
                              Catch::Contains("the hole becomes a notch open to the boundary") &&
                              Catch::Contains("--grid nbnug keeps it") && Catch::Contains("--spacing below 0.4 mm"));
  for (const std::string grid : {"nbnug", "free"}) {
    const auto kept = run_pd_mesh(geo + settings + " --grid " + grid);
    INFO(grid << ": " << kept.err);
    CHECK(kept.status == 0);
    CHECK_THAT(kept.err, !Catch::Contains("no particle in the material"));
  }
}

TEST_CASE("a uniform grid that drops the neck between two parts of a plate says it leaves two pieces",
          "[mesher][cli]") {
  // Two 10 mm squares joined by a neck 0.3 mm high and 2 mm long: at
  // dx = 0.5 mm no cell centre lies in the neck, and the horizon (1.5 mm)
  // does not reach across it. Before, pd-mesh wrote the two halves without
  // a word (the lost-ligament check looks between two different voids).
  const auto geo = write_text_file(
      "neck.geo",
      "Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {10, 4.85, 0}; Point(4) = {12, 4.85, 0};\n"
      "Point(5) = {12, 0, 0}; Point(6) = {22, 0, 0}; Point(7) = {22, 10, 0}; Point(8) = {12, 10, 0};\n"
      "Point(9) = {12, 5.15, 0}; Point(10) = {10, 5.15, 0}; Point(11) = {10, 10, 0}; Point(12) = {0, 10, 0};\n"
      "For k In {1:11}\n  Line(k) = {k, k+1};\nEndFor\nLine(12) = {12, 1};\n"
      "Curve Loop(1) = {1:12};\nPlane Surface(1) = {1};\n");
  const std::string settings = " --horizon-factor 3 -o " + mesher_temp("neck.pdp");
  const auto uniform = run_pd_mesh(geo + settings + " --spacing 0.5mm --grid uniform");
  INFO(uniform.err);
  CHECK(uniform.status == 0);
  CHECK_THAT(uniform.err, Catch::Contains("pd-mesh: warning: " + geo + ": the particles fall into 2 pieces that no "
                                          "bond joins (400 particles in x 0.25 to 9.75 mm, y 0.25 to 9.75 mm; 400 "
                                          "particles in x 12.25 to 21.75 mm, y 0.25 to 9.75 mm)") &&
                              Catch::Contains("--grid nbnug"));
  // A spacing whose cell centres lie in the neck, and the grids that follow the boundary, keep it.
  for (const std::string options : {" --spacing 0.25mm --grid uniform", " --spacing 0.5mm --grid nbnug",
                                    " --spacing 0.5mm --grid free"}) {
    const auto kept = run_pd_mesh(geo + settings + options);
    INFO(options << ": " << kept.err);
    CHECK(kept.status == 0);
    CHECK_THAT(kept.err, !Catch::Contains("pieces"));
  }
}

// The NB-NUG grid left in pieces (two cells beside a hole 0.002 mm wide on a
// 1 mm grid, whose bonds to the rest cross the hole) is not advised to take
// the grid it has (before 7 December 2026: "or --grid nbnug, keeps it").
TEST_CASE("the pieces warning of an NB-NUG grid does not advise --grid nbnug", "[mesher][cli]") {
  const auto geo = write_text_file(
      "tiny_hole.geo",
      "Point(1) = {0, 0, 0}; Point(2) = {100, 0, 0}; Point(3) = {100, 50, 0}; Point(4) = {0, 50, 0};\n"
      "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4};\n"
      "r = 0.001;\nPoint(5) = {50, 25, 0}; Point(6) = {50 + r, 25, 0}; Point(7) = {50, 25 + r, 0};\n"
      "Point(8) = {50 - r, 25, 0}; Point(9) = {50, 25 - r, 0};\n"
      "Circle(5) = {6, 5, 7}; Circle(6) = {7, 5, 8}; Circle(7) = {8, 5, 9}; Circle(8) = {9, 5, 6};\n"
      "Curve Loop(2) = {5, 6, 7, 8};\nPlane Surface(1) = {1, 2};\n");
  const auto run = run_pd_mesh(geo + " --spacing 1mm --horizon-factor 3 -o " + mesher_temp("tiny_hole.pdp"));
  INFO(run.err);
  CHECK(run.status == 0);
  CHECK_THAT(run.err, Catch::Contains("the particles fall into 2 pieces that no bond joins") &&
                          Catch::Contains("a smaller --spacing may keep it") && !Catch::Contains("--grid nbnug"));
}

// A 40 mm x 20 mm plate written in metres, read as mm: 0.04 mm across. The
// spacing check then fails with sizes only the unit explains, so the
// warning comes first and names --geo-unit.
TEST_CASE("a geometry in another unit than --geo-unit is warned about before the spacing check", "[mesher][cli]") {
  const auto geo = write_text_file("in_metres.geo", "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 0.04, 0.02};\n");
  const auto run = run_pd_mesh(geo + " --spacing 0.5mm --horizon 1.5mm -o " + mesher_temp("in_metres.pdp"));
  INFO(run.err);
  CHECK(run.status != 0);
  CHECK_THAT(run.err, Catch::Contains("warning: " + geo + ": the plate is 4e-05 m x 2e-05 m, read with --geo-unit mm") &&
                          Catch::Contains("is not an integer number of spacings"));
  CHECK(run.err.find("warning") < run.err.find("error"));
  const auto right = run_pd_mesh(geo + " --geo-unit m --spacing 0.5mm --horizon 1.5mm -o " + mesher_temp("in_metres.pdp"));
  CHECK(right.status == 0);
  CHECK_THAT(right.err, !Catch::Contains("warning"));
}

TEST_CASE("pd-mesh makes its output folders and never writes over its input or one file twice", "[mesher][cli]") {
  const auto geo = write_text_file("square_for_outputs.geo", rectangle_20 + "Plane Surface(1) = {1};\n");
  const std::string geometry_text = file_text(geo);
  const auto folder = fs::path(mesher_temp("outputs"));
  fs::remove_all(folder);
  const std::string settings = " --spacing 1mm --horizon 3mm";
  SECTION("folders that do not exist yet are made") {
    const auto pdp = (folder / "a" / "plate.pdp").string(), vtp = (folder / "b" / "plate.vtp").string();
    const auto run = run_pd_mesh(geo + settings + " -o " + pdp + " --vtk " + vtp);
    INFO(run.err);
    CHECK(run.status == 0);
    CHECK(fs::is_regular_file(pdp));
    CHECK(fs::is_regular_file(vtp));
  }
  SECTION("the particle file or the VTK view over the geometry file") {
    for (const std::string& arguments : {" -o " + geo, " -o " + (folder / "x.pdp").string() + " --vtk " + geo}) {
      const auto run = run_pd_mesh(geo + settings + arguments);
      INFO(arguments << "\n" << run.err);
      CHECK(run.status != 0);
      CHECK_THAT(run.err, Catch::Contains("is the geometry file"));
      CHECK(file_text(geo) == geometry_text);
    }
  }
  SECTION("a particle file named as VTK, a VTK view not named .vtp") {
    for (const char* name : {"view.vtp", "view.VTK"})
      expect_pd_mesh_failure(geo + settings, (folder / name).string(),
                             "the particle file is binary (.pdp, docs/formats.md), not VTK");
    fs::create_directories(folder);
    const auto scene = (folder / "scene.toml").string();
    std::ofstream(scene) << "a scene of the user's";
    expect_pd_mesh_failure(geo + settings + " --vtk " + scene, (folder / "p.pdp").string(),
                           "a VTK view is written as NAME.vtp");
    CHECK(file_text(scene) == "a scene of the user's");
  }
  SECTION("-o naming a user's file, a folder or a FIFO: refused, left as it was") {
    // Before 5 December 2026 the atomic rename put the particle file in
    // their place, exit 0: a scene overwritten, and, run as root with
    // -o /dev/null, the device itself replaced by a regular file.
    fs::create_directories(folder / "a_folder");
    const auto scene = (folder / "scene.toml").string();
    std::ofstream(scene) << "a scene of the user's";
    const auto fifo = (folder / "pipe.pdp").string();
    REQUIRE(pd::test_support::run_shell("mkfifo '" + fifo + "'") == 0);
    for (const auto& [output, fragment] :
         std::vector<std::pair<std::string, std::string>>{
             {scene, "the file exists and is not a particle file"},
             {(folder / "a_folder").string(), "is a folder, not a file"},
             {fifo, "is a FIFO, not a file"}}) {
      const auto run = run_pd_mesh(geo + settings + " -o " + output);
      INFO(output << "\n" << run.err);
      CHECK(run.status != 0);
      CHECK_THAT(run.err, Catch::Contains("-o " + output + ": " + fragment));
    }
    CHECK(file_text(scene) == "a scene of the user's");
    CHECK(fs::is_directory(folder / "a_folder"));
    CHECK(fs::is_fifo(fifo));
    // A particle file of an earlier run is replaced.
    const auto pdp = (folder / "again.pdp").string();
    CHECK(run_pd_mesh(geo + settings + " -o " + pdp).status == 0);
    CHECK(run_pd_mesh(geo + settings + " -o " + pdp).status == 0);
  }
  SECTION("-o naming a folder by a trailing '/': refused before the meshing, no folder made") {
    // Before 7 December 2026 the folder was made and the grid meshed, and
    // only the write was refused ("is a folder, not a file").
    const auto named = (folder / "new").string() + "/";
    const auto run = run_pd_mesh(geo + settings + " -o " + named);
    CHECK(run.status == 1);
    CHECK(run.err == "pd-mesh: error: -o " + named + ": names a folder (it ends in '/'), not the particle file: give "
                     "the file's name in it, e.g. -o " + named + "plate.pdp\n");
    CHECK_FALSE(fs::exists(folder / "new"));
  }
  SECTION("-o ending in '..' or '.' through a folder not made yet: refused before the meshing, no folder made") {
    // Before 7 December 2026 the folder was made and the grid meshed, and
    // only the write was refused ("is a folder, not a file").
    for (const std::string last : {"..", "."}) {
      const auto named = (folder / "new").string() + "/" + last;
      const auto run = run_pd_mesh(geo + settings + " -o " + named);
      CHECK(run.status == 1);
      CHECK(run.err == "pd-mesh: error: -o " + named + ": names a folder (it ends in '" + last +
                           "'), not the particle file: give the file's name in it, e.g. -o " + named + "/plate.pdp\n");
      CHECK_FALSE(fs::exists(folder / "new"));
    }
  }
  SECTION("the VTK view and the particle file the same file") {
    const auto pdp = (folder / "same.pdp").string();
    expect_pd_mesh_failure(geo + settings + " --vtk " + pdp, pdp, "name the same file");
  }
  SECTION("a VTK view whose folder is a file: one error line, no particle file") {
    fs::create_directories(folder);
    std::ofstream((folder / "file").string()) << "a file, not a folder";
    const auto pdp = (folder / "plate.pdp").string();
    expect_pd_mesh_failure(geo + settings + " --vtk " + (folder / "file" / "plate.vtp").string(), pdp,
                           "cannot make its folder");
    // Nor the particle file's folder that the command made for it.
    const auto nested = (folder / "new" / "deeper" / "plate.pdp").string();
    expect_pd_mesh_failure(geo + settings + " --vtk " + (folder / "file" / "plate.vtp").string(), nested,
                           "cannot make its folder");
    CHECK_FALSE(fs::exists(folder / "new"));
  }
  SECTION("a particle file that cannot be written takes its view back") {
    // A file size limit of 64 KiB (the shell's `ulimit -f`, with SIGXFSZ
    // ignored so that the write fails with EFBIG as on a full disk): the
    // view (11 KB) is written first, then the particle file (229 KB) fails.
    // Before 7 December 2026 the view stayed, showing a grid that no
    // particle file holds (or, over an earlier run's pair, beside a particle
    // file of another grid).
    fs::create_directories(folder);
    const auto view = (folder / "orphan.vtp").string(), pdp = (folder / "orphan.pdp").string();
    REQUIRE(run_pd_mesh(geo + settings + " --vtk " + view + " -o " + (folder / "earlier.pdp").string()).status == 0);
    const auto err = mesher_temp("limited_stderr.txt");
    const int status = run_shell("trap '' XFSZ; ulimit -f 64; " + std::string(PD_MESH_EXE) + " " + geo + settings +
                                 " --vtk " + view + " -o " + pdp + " > /dev/null 2> " + err);
    INFO(file_text(err));
    CHECK(status != 0);
    // The option is named with the path (since 7 December 2026; before, the path alone).
    CHECK_THAT(file_text(err), Catch::Contains("pd-mesh: error: -o " + pdp + ": write failed"));
    CHECK_FALSE(fs::exists(pdp));
    CHECK_FALSE(fs::exists(view));
  }
  SECTION("--vtk naming a run's results or a user's file: refused, left as it was; a view is replaced") {
    // Before 7 December 2026 any file of that name was replaced, exit 0: a
    // run's arrival.vtp (here one made as pd-solve's, with its arrival
    // array) or a user's file named .vtp.
    fs::create_directories(folder);
    const auto arrival = (folder / "arrival.vtp").string(), mine = (folder / "mine.vtp").string();
    pd::write_vtp(arrival, {1e-3, 2e-3}, {1e-3, 1e-3}, {pd::PointArray{"arrival_time_0.35", 1, {1e-6, 2e-6}}});
    std::ofstream(mine) << "a file of the user's";
    const std::string arrival_text = file_text(arrival);
    for (const auto& view : {arrival, mine})
      expect_pd_mesh_failure(geo + settings + " --vtk " + view, (folder / "p.pdp").string(),
                             "pd-mesh: error: --vtk " + view + ": the file exists and is not a particle view of "
                             "pd-mesh (a run's arrival.vtp or snapshot, or a file of yours); pd-mesh replaces only "
                             "a view of an earlier run: name a new file\n");
    CHECK(file_text(arrival) == arrival_text);
    CHECK(file_text(mine) == "a file of the user's");
    // A view of an earlier run is replaced.
    const auto view = (folder / "again.vtp").string();
    CHECK(run_pd_mesh(geo + settings + " --vtk " + view + " -o " + (folder / "v1.pdp").string()).status == 0);
    CHECK(run_pd_mesh(geo + settings + " --vtk " + view + " -o " + (folder / "v2.pdp").string()).status == 0);
  }
  SECTION("a view that cannot be written is named by --vtk, and no particle file is written") {
    // 4 KiB: the view (11 KB) fails first.
    fs::create_directories(folder);
    const auto view = (folder / "big.vtp").string(), pdp = (folder / "small_limit.pdp").string();
    const auto err = mesher_temp("limited_view_stderr.txt");
    const int status = run_shell("trap '' XFSZ; ulimit -f 4; " + std::string(PD_MESH_EXE) + " " + geo + settings +
                                 " --vtk " + view + " -o " + pdp + " > /dev/null 2> " + err);
    INFO(file_text(err));
    CHECK(status == 1);
    CHECK_THAT(file_text(err), Catch::StartsWith("pd-mesh: error: --vtk " + view + ": "));
    CHECK_FALSE(fs::exists(pdp));
    CHECK_FALSE(fs::exists(view));
  }
  SECTION("an output folder that takes no file is refused before the meshing") {
    // /proc takes no new file, /proc/sys/pd_mesh_test no folder (as any user,
    // root included). Before 7 December 2026 pd-mesh found out only when it
    // wrote, after the meshing: "/proc/x.pdp: cannot open for writing", and
    // pd-solve's check of its output folder had no counterpart here.
    const auto run = run_pd_mesh(geo + settings + " -o /proc/pd_mesh_test_never.pdp");
    CHECK(run.status != 0);
    CHECK(run.err == "pd-mesh: error: -o /proc/pd_mesh_test_never.pdp: cannot write in its folder /proc: No such "
                     "file or directory\n");
    expect_pd_mesh_failure(geo + settings + " --vtk /proc/sys/pd_mesh_test/deeper/never.vtp",
                           (folder / "never.pdp").string(),
                           "pd-mesh: error: --vtk /proc/sys/pd_mesh_test/deeper/never.vtp: cannot write in its "
                           "folder /proc/sys: ");
  }
}

// A file where a folder of an output's path must be (`-o plate.geo/x.pdp`,
// `--vtk /dev/null/v.vtp`): before 7 December 2026 the grid was meshed, and
// only the write refused ("cannot make its folder plate.geo: Not a
// directory"), which for a large grid came hours later.
TEST_CASE("an output path through a file is refused before the meshing and names the file", "[mesher][cli]") {
  const auto geo = write_text_file("through_file.geo", rectangle_20 + "Plane Surface(1) = {1};\n");
  const std::string settings = " --spacing 1mm --horizon 3mm";
  const std::string pdp = geo + "/deeper/plate.pdp", pdp_beside = mesher_temp("through_file.pdp");
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {" -o " + pdp, "-o " + pdp + ": cannot make its folder " + geo + "/deeper: " + geo + " is a file"},
           {" -o " + pdp_beside + " --vtk /dev/null/v.vtp",
            "--vtk /dev/null/v.vtp: cannot make its folder /dev/null: /dev/null is no folder"}}) {
    std::filesystem::remove(pdp_beside);
    const auto run = run_pd_mesh(geo + settings + arguments);
    INFO(arguments);
    CHECK(run.status == 1);
    CHECK(run.err == "pd-mesh: error: " + message +
                         ", and a folder of the path cannot be inside it; give a path through folders\n");
    CHECK_FALSE(std::filesystem::exists(pdp_beside));
  }
}

// pd-solve reads a particle file by the name its scene gives, whatever its
// ending; before 7 December 2026 `-o plate` (the .pdp left off) wrote a file
// named `plate` without a word, which a scene's particles = "plate.pdp" then
// did not find.
TEST_CASE("a particle file named without .pdp is written with a warning naming it", "[mesher][cli]") {
  const auto geo = write_text_file("square_for_names.geo", rectangle_20 + "Plane Surface(1) = {1};\n");
  const std::string settings = " --spacing 1mm --horizon 3mm -o ";
  for (const std::string name : {"plate", "plate.bin"}) {
    const auto out = mesher_temp(name);
    fs::remove(out);
    const auto run = run_pd_mesh(geo + settings + out);
    INFO(run.err);
    CHECK(run.status == 0);
    CHECK(fs::is_regular_file(out));
    CHECK(run.err == "pd-mesh: warning: -o " + out + ": the particle file's name does not end in .pdp; it is written "
                     "under this name, and a scene's particles = must give the same name (or write -o " + out +
                     ".pdp)\n");
  }
  for (const std::string name : {"plate.pdp", "PLATE.PDP", ".pdp"}) {
    const auto run = run_pd_mesh(geo + settings + mesher_temp(name));
    CHECK(run.status == 0);
    CHECK(run.err.empty());
  }
}

// A name with another ending after .pdp, or with .pdp cut short, is warned
// about with the name it most likely meant: before 7 December 2026 the
// advice added .pdp after all of it (plate.pdp.tmp.pdp, plate..pdp,
// plate.pd.pdp), and a file named .pdp was said not to end in .pdp.
TEST_CASE("a particle file name with an ending after .pdp or .pdp cut short is told the name it meant",
          "[mesher][cli]") {
  const auto geo = write_text_file("square_for_names.geo", rectangle_20 + "Plane Surface(1) = {1};\n");
  const std::string settings = " --spacing 1mm --horizon 3mm -o ";
  const std::vector<std::pair<std::string, std::string>> names = {
      {"plate.pdp.tmp", "plate.pdp"}, {"plate.PDP.bak", "plate.PDP"}, {"plate.", "plate.pdp"},
      {"plate.pd", "plate.pdp"},      {"plate.P", "plate.pdp"},       {"plate.pdp.", "plate.pdp"}};
  for (const auto& [name, meant] : names) {
    const auto out = mesher_temp(name);
    const auto run = run_pd_mesh(geo + settings + out);
    INFO(name);
    CHECK(run.status == 0);
    CHECK(run.err == "pd-mesh: warning: -o " + out + ": the particle file's name does not end in .pdp; it is written "
                     "under this name, and a scene's particles = must give the same name (or write -o " +
                         mesher_temp(meant) + ")\n");
  }
}

// A box around a hole is the hole's bounding box grown by the padding and
// clipped to the plate: from the plate's larger side on, it is the whole
// plate, and a larger padding changes nothing. Before 7 December 2026 a
// padding of up to ten plates (30mm for 0.3mm, say) meshed the whole plate
// free without a word.
TEST_CASE("a padding larger than the plate is warned about, naming it and the plate", "[mesher][cli]") {
  const auto geo = std::string(PD_GEOMETRY_DIR) + "/c1_plate_hole.geo";  // 20 x 20 mm, a hole of radius 4 mm
  const std::string settings = " --spacing 1mm -m 3 -o ";
  const auto wide = mesher_temp("padding_wide.pdp"), wider = mesher_temp("padding_wider.pdp");
  const std::string warning = "pd-mesh: warning: " + geo + ": --padding 30mm is more than the plate's larger side "
                              "(the plate is 20 mm x 20 mm): every box around a curve off the lattice lines covers "
                              "the whole plate, so the grid is a free mesh of all of it, without the squares the "
                              "NB-NUG grid is for; a padding is a horizon (the default, 3 mm) or a few; for a free "
                              "mesh of the whole plate use --grid free\n";
  const auto run = run_pd_mesh(geo + " --padding 30mm" + settings + wide);
  INFO(run.err);
  REQUIRE(run.status == 0);
  CHECK(run.err == warning);
  REQUIRE(run_pd_mesh(geo + " --padding 190mm" + settings + wider).status == 0);
  // The same grid, and no lattice square in it.
  const auto a = pd::read_particle_file(wide), b = pd::read_particle_file(wider);
  CHECK(a.x == b.x);
  CHECK(a.y == b.y);
  CHECK(std::count(a.region.begin(), a.region.end(), std::uint8_t{0}) == 0);
  // A padding within the plate is quiet.
  const auto quiet = run_pd_mesh(geo + " --padding 5mm" + settings + mesher_temp("padding_5mm.pdp"));
  CHECK(quiet.status == 0);
  CHECK(quiet.err.empty());
}

// gmsh meshes every free region in mm, whatever the geometry file's unit:
// its nodes are rounded to 2^-20 mm (about 1 nm). Before 5 December 2026 a
// plate written in m was meshed in m and its free nodes rounded to 2^-20 m
// (about 1 um: 0.2 % of this plate's 0.5 mm cells), every one of them on
// that grid.
TEST_CASE("a geometry in metres is meshed to the nanometre as one in mm is", "[mesher][cli]") {
  const auto geo = write_text_file("hole_in_metres.geo", "SetFactory(\"OpenCASCADE\");\n"
                                                         "Rectangle(1) = {0, 0, 0, 0.02, 0.01};\n"
                                                         "Disk(2) = {0.01, 0.005, 0, 0.003, 0.003};\n"
                                                         "BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };\n");
  const auto out = mesher_temp("hole_in_metres.pdp");
  const auto run = run_pd_mesh(geo + " --geo-unit m --spacing 0.5mm --horizon 1.5mm -o " + out);
  INFO(run.err);
  REQUIRE(run.status == 0);
  const auto p = pd::read_particle_file(out);
  const double micro_grid = std::ldexp(1.0, -20);  // [m]
  const auto on_micro_grid = [&](double v) { return std::round(v / micro_grid) * micro_grid == v; };
  std::size_t free_vertices = 0, on_grid = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.region[i] == 0) continue;  // lattice squares
    for (std::uint64_t k = p.cell_offsets[i]; k < p.cell_offsets[i + 1]; ++k) {
      ++free_vertices;
      on_grid += on_micro_grid(p.cell_vx[k]) && on_micro_grid(p.cell_vy[k]) ? 1 : 0;
    }
  }
  INFO(on_grid << " of " << free_vertices << " free cells' vertices on the 2^-20 m grid");
  REQUIRE(free_vertices > 500);
  CHECK(on_grid < free_vertices / 50);
}
