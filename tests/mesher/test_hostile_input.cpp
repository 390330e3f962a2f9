// Hostile and oversized input: a geometry file is data, gmsh's time is
// bounded, and a grid that cannot fit in memory is refused before meshing,
// with its estimated size. Each case runs pd-mesh as a user would.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "pd_mesh_run.hpp"

namespace fs = std::filesystem;

namespace {

using namespace pd::test_support;

const std::string plate =
    "Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {10, 10, 0}; Point(4) = {0, 10, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n";

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
