// The validation tools' command line (pd-validate-c1, pd-validate-c2,
// pd-validate-crack), run as a user runs them: every refusal is one line
// "TOOL: error: ..." naming the option or file and the value, exit status 1,
// before any mesh or solve, and no output folder made. Before 7 December
// 2026 their numbers were read by Boost or std::stod ("stod"), a negative
// --threads was ignored, and a file named by -o ended in a filesystem
// exception's text.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "error.hpp"
#include "plate_grid.hpp"
#include "results_format.hpp"
#include "units.hpp"
#include "vtk_output.hpp"
#include "../test_commands.hpp"
#include "../test_folder.hpp"

namespace fs = std::filesystem;
using pd::test_support::file_text;
using pd::test_support::run_shell;

namespace {

struct ToolRun {
  int status = 0;
  std::string err;
};

// TOOL ARGUMENTS run in `folder`, under `timeout` (a refusal is at once;
// a tool that started a solve instead fails the test in bounded time).
ToolRun run_in(const std::string& folder, const std::string& tool, const std::string& arguments) {
  const std::string err = folder + "/stderr.txt";
  ToolRun run;
  run.status = run_shell("cd '" + folder + "' && timeout 60 " + tool + " " + arguments + " > /dev/null 2> '" + err + "'");
  run.err = file_text(err);
  return run;
}

struct Refusal {
  std::string arguments, message;
};

// Each case refused with its message alone, exit 1, and no output folder
// `out` (the cases' -o, relative to `folder`) made.
void expect_refusals(const std::string& folder, const std::string& tool, const std::string& name,
                     const std::vector<Refusal>& cases) {
  for (const auto& c : cases) {
    INFO(name << " " << c.arguments);
    const ToolRun run = run_in(folder, tool, c.arguments);
    CHECK(run.status == 1);
    CHECK(run.err == name + ": error: " + c.message + "\n");
    CHECK_FALSE(fs::exists(folder + "/out"));
  }
}

std::string fresh(const std::string& name) { return pd::test_support::fresh_folder_under(PD_QS_TEST_TMPDIR, name); }

}  // namespace

TEST_CASE("pd-validate-c1 refuses bad options and numbers before any solve", "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c1_cli");
  const std::string geo = PD_C1_GEOMETRY;
  const std::string run = geo + " -o out ";
  expect_refusals(
      folder, PD_VALIDATE_C1_EXECUTABLE, "pd-validate-c1",
      {{"--spacing 0.1mm -o out",
        "no geometry file given: give the plate's .geo file as the command's one argument, e.g. pd-validate-c1 "
        "geometries/c1_plate_hole.geo --spacing 0.1mm -m 4"},
       {run + "--spaceing 0.1mm", "--spaceing: no such option; did you mean --spacing?"},
       {run + "--bogus 1", "--bogus: no such option (pd-validate-c1 --help lists them)"},
       {run + "--spacing", "--spacing: no value after it: give one (--spacing VALUE, pd-validate-c1 --help says what "
                           "it takes), or leave --spacing out"},
       // Factors: std::stod said "stod", and read "4x" as 4. A number that
       // is none, and one out of range, in pd-mesh's words (before 7
       // December 2026's later change "--horizon-factor: 'abc' is not a
       // number").
       {run + "-m abc", "--horizon-factor abc: expected a number of spacings (delta = m dx, e.g. -m 4) from 1 to 64"},
       {run + "-m 4x", "--horizon-factor 4x: expected a number of spacings (delta = m dx, e.g. -m 4) from 1 to 64"},
       {run + "-m 0.5", "--horizon-factor 0.5: expected a number of spacings (delta = m dx, e.g. -m 4) from 1 to 64"},
       {run + "-m 4,nan", "--horizon-factor nan: expected a number of spacings (delta = m dx, e.g. -m 4) from 1 to 64"},
       // An empty item named by its place, blanks around an item not part of
       // it (before 7 December 2026 "an empty item", the place unsaid, and
       // -m '3, 4' was "--horizon-factor  4: expected a number ...").
       {run + "--spacing 0.1mm,,0.05mm", "--spacing '0.1mm,,0.05mm': item 2 is empty: give a comma-separated list "
                                         "without empty items, e.g. --spacing 0.1mm,0.05mm"},
       {run + "--spacing '0.1mm, ,0.05mm'", "--spacing '0.1mm, ,0.05mm': item 2 is empty: give a comma-separated "
                                            "list without empty items, e.g. --spacing 0.1mm,0.05mm"},
       {run + "-m 3,4,", "--horizon-factor '3,4,': item 3 is empty: give a comma-separated list without empty items, "
                         "e.g. --horizon-factor 3,4"},
       {run + "--spacing '0.1mm , 0.05mm' -m '3, 4 ' --fem-size 0.0001mm",
        "--fem-size 0.0001mm: less than 1/32 of the finest spacing (0.05 mm): more elements than a reference needs, "
        "which gmsh would mesh for hours; give at least 0.0015625 mm"},
       {run + "--spacing 0mm", "--spacing must be positive, got '0mm' (e.g. --spacing 0.1mm)"},
       {run + "--spacing 1e300mm", "--spacing 1e300mm is 1e+297 m, above the largest spacing a particle file holds "
                                   "(1 nm to 1 km): is the exponent or the unit a slip? (e.g. --spacing 0.1mm)"},
       {run + "--spacing 0.1", "--spacing: '0.1' has no unit; write it as e.g. '0.1mm' or '0.1m'"}});
}

// More threads than the machine has: before 7 December 2026 (the first
// change of that day) refused; now capped with a note, as pd-solve caps them.
// The run is then refused on a later option, so no solve starts.
TEST_CASE("pd-validate-c1 caps --threads above the machine's hardware threads with a note",
          "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c1_threads");
  const long most = std::max(1u, std::thread::hardware_concurrency());
  const ToolRun run =
      run_in(folder, PD_VALIDATE_C1_EXECUTABLE, std::string(PD_C1_GEOMETRY) + " -o out --threads 100000 --tolerance abc");
  CHECK(run.status == 1);
  CHECK(run.err == "pd-validate-c1: note: --threads 100000 is more than the " + std::to_string(most) +
                       " hardware threads of this machine; using " + std::to_string(most) +
                       "\npd-validate-c1: error: --tolerance abc: expected a relative residual from 2.22045e-16 "
                       "to 0.5\n");
  CHECK_FALSE(fs::exists(folder + "/out"));
}

TEST_CASE("pd-validate-c1 refuses bad lengths, counts and lists before any solve", "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c1_lists");
  const std::string run = std::string(PD_C1_GEOMETRY) + " -o out ";
  expect_refusals(
      folder, PD_VALIDATE_C1_EXECUTABLE, "pd-validate-c1",
      {       {run + "--fem-size -1mm", "--fem-size: -1mm is not a positive length (e.g. --fem-size 1mm)"},
       // gmsh meshed without end.
       {run + "--spacing 0.5mm,1mm --fem-size 1e-6mm", "--fem-size 1e-6mm: less than 1/32 of the finest spacing "
                                                       "(0.5 mm): more elements than a reference needs, which gmsh "
                                                       "would mesh for hours; give at least 0.015625 mm"},
       // Boost's "the argument ('abc') for option '--tolerance' is invalid".
       {run + "--tolerance abc", "--tolerance abc: expected a relative residual from 2.22045e-16 to 0.5"},
       {run + "--tolerance 1e-300", "--tolerance 1e-300: expected a relative residual from 2.22045e-16 to 0.5"},
       // A negative count of threads was ignored.
       {run + "--threads -1", "--threads -1: expected a whole number of OpenMP threads (0: the default; this "
                              "machine has " + std::to_string(std::max(1u, std::thread::hardware_concurrency())) +
                              " hardware threads) from 0 to 1048576"},
       // Read after the first solve.
       {run + "--near-hole-band 2", "--near-hole-band: '2' has no unit; write it as e.g. '2mm' or '2m'"},
       {run + "--box-refinement 3", "--box-refinement: '3' in '3' is not a power of two from 2 to 64"},
       {run + "--box-refinement 2x", "--box-refinement 2x: expected a whole number of refinements from 2 to 64"},
       {run + "--grids uniform,nbnugg", "--grids: unknown grid 'nbnugg' (use uniform, free or nbnug)"}});
}

TEST_CASE("pd-validate-c1 refuses a geometry file that is none and an output folder it cannot make",
          "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c1_files");
  const std::string geo = PD_C1_GEOMETRY;
  std::ofstream(folder + "/empty.geo").close();
  std::ofstream(folder + "/file.txt") << "a file\n";
  fs::create_directories(folder + "/plate.geo");
  // The output: a file, a folder under a file, a name ending in a space.
  expect_refusals(folder, PD_VALIDATE_C1_EXECUTABLE, "pd-validate-c1",
                  {{"nothing.geo -o out", "nothing.geo: not found (the geometry file)"},
                   {"plate.geo -o out", "plate.geo: a folder, not a file (the geometry file)"},
                   {"'" + geo + " ' -o out", "'" + geo + " ': the name ends in a space, and no file or folder has "
                                                 "that name (" + geo + ", without it, exists): give it without, " +
                                                 geo},
                   {geo + " -o file.txt", "-o file.txt: is a file, not a folder: the tables and pictures are written "
                                          "into a folder; name one (it may exist)"},
                   {geo + " -o file.txt/out", "-o file.txt/out: cannot make its folder file.txt: file.txt is a file, "
                                              "and a folder of the path cannot be inside it; give a path through "
                                              "folders"},
                   {geo + " -o 'out '", "-o 'out ': the name ends in a space, and no file or folder has that name: "
                                        "give it without, -o out"}});
  CHECK(file_text(folder + "/file.txt") == "a file\n");
  // An empty geometry file is refused before the output folder is made.
  const ToolRun empty = run_in(folder, PD_VALIDATE_C1_EXECUTABLE, "empty.geo --spacing 1mm -m 3 -o out");
  CHECK(empty.status == 1);
  CHECK_THAT(empty.err, Catch::StartsWith("pd-validate-c1: error: empty.geo: ") &&
                            Catch::Contains("empty") && Catch::EndsWith("\n"));
  CHECK(std::count(empty.err.begin(), empty.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(folder + "/out"));
}

TEST_CASE("pd-validate-c2 refuses bad options, numbers and run folders before any solve",
          "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c2_cli");
  const std::string geo = PD_C1_GEOMETRY;
  fs::create_directories(folder + "/run");
  std::ofstream(folder + "/run/final_state.vtp") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"";
  const std::string run = geo + " -o out ";
  expect_refusals(
      folder, PD_VALIDATE_C2_EXECUTABLE, "pd-validate-c2",
      {{"-o out",
        "no geometry file given: give the plate's .geo file as the command's one argument, e.g. pd-validate-c2 "
        "geometries/c1_plate_hole.geo --spacing 0.1mm -m 4"},
       {run + "--first-step 2", "--first-step: no such option; did you mean --first-steps?"},
       // Boost's "the argument ('2.5') for option '--first-steps' is invalid".
       {run + "--first-steps 2.5", "--first-steps 2.5: expected a whole number of load steps from 0 to 1000000"},
       {run + "--max-small-steps -1", "--max-small-steps -1: expected a whole number of load steps from 0 to 1000000"},
       {run + "-m 1e9", "--horizon-factor 1e9: expected a number of spacings (delta = m dx, e.g. -m 4) from 1 to 64"},
       {run + "--increment 0mm", "--increment: 0mm is not a positive length (e.g. --increment 1mm)"},
       {run + "--first-increment -0.01mm", "--first-increment: -0.01mm is not a positive length (e.g. "
                                           "--first-increment 1mm)"},
       // Found after the uniform grid's run.
       {run + "--grids uniform,nbnugg", "--grids: unknown grid 'nbnugg' (use uniform, free or nbnug)"},
       {run + "--grids uniform,", "--grids 'uniform,': item 2 is empty: give a comma-separated list without empty "
                                  "items, e.g. --grids uniform,free,nbnug"},
       {run + "--grids 'uniform, nbnugg'", "--grids: unknown grid 'nbnugg' (use uniform, free or nbnug)"},
       {geo + " --count-cracks nothing", "nothing: solver output directory not found"}});
  // A grid beyond the memory: before 7 December 2026 built until time or
  // memory ran out.
  const ToolRun huge = run_in(folder, PD_VALIDATE_C2_EXECUTABLE, geo + " --spacing 0.3um --grids uniform -o huge");
  CHECK(huge.status == 1);
  CHECK_THAT(huge.err, Catch::StartsWith("pd-validate-c2: error: " + geo + ": the uniform grid at the spacing 0.0003 "
                                         "mm would have about 3.89e+09 particles and need ") &&
                           Catch::EndsWith(" available: give a larger --spacing\n"));
  // ... and before its output folder is made (before 7 December 2026's later
  // change after it, which stayed, empty).
  CHECK_FALSE(fs::exists(folder + "/huge"));
  // A truncated final state is named.
  const ToolRun truncated = run_in(folder, PD_VALIDATE_C2_EXECUTABLE, geo + " --spacing 0.5mm --count-cracks run");
  CHECK(truncated.status == 1);
  CHECK_THAT(truncated.err, Catch::StartsWith("pd-validate-c2: error: run/final_state.vtp") && Catch::EndsWith("\n"));
  CHECK(std::count(truncated.err.begin(), truncated.err.end(), '\n') == 1);
}

TEST_CASE("pd-validate-crack refuses bad options and numbers before any solve", "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_crack_cli");
  const std::string geo = PD_CRACK_GEOMETRY;
  const std::string run = geo + " -o out ";
  expect_refusals(
      folder, PD_VALIDATE_CRACK_EXECUTABLE, "pd-validate-crack",
      {{run + "--step 3", "--step: no such option; did you mean --steps?"},
       {run + "--steps 0", "--steps 0: expected a whole number of load steps from 1 to 100000"},
       {run + "--steps abc", "--steps abc: expected a whole number of load steps from 1 to 100000"},
       // Boost read it; 'nan' passed.
       {run + "--fracture-energy nan", "--fracture-energy nan: expected a fracture energy in J/m^2 from 0.1 to 1e+07"},
       {run + "--fracture-energy 2e9", "--fracture-energy 2e9: expected a fracture energy in J/m^2 from 0.1 to 1e+07"},
       {run + "--fracture-energy 0", "--fracture-energy 0: expected a fracture energy in J/m^2 from 0.1 to 1e+07"},
       {run + "--displacement 0mm", "--displacement: 0mm is not a positive length (e.g. --displacement 1mm)"},
       // Found after the FEM solves of the sizes before it; none ended in an
       // opening read from no FEM solution.
       {run + "--fem-tip-sizes 4mm,2", "--fem-tip-sizes: '2' has no unit; write it as e.g. '2mm' or '2m'"},
       {run + "--fem-tip-sizes 4mm,1um", "--fem-tip-sizes 1um: less than 1/32 of the finest spacing (2.5 mm): more "
                                         "elements than a reference needs, which gmsh would mesh for hours; give at "
                                         "least 0.078125 mm"},
       {run + "--fem-tip-sizes ,", "--fem-tip-sizes ',': item 1 is empty: give a comma-separated list without empty "
                                   "items, e.g. --fem-tip-sizes 4mm,2mm,1mm"},
       {run + "--variants force_only,", "--variants 'force_only,': item 2 is empty: give a comma-separated list "
                                        "without empty items, e.g. --variants force_and_dilatation,force_only"},
       {run + "--variants ' , '", "--variants ' , ': item 1 is empty: give a comma-separated list without empty "
                                  "items, e.g. --variants force_and_dilatation,force_only"},
       {run + "--variants ' '", "--variants: the list is empty: give at least one item, e.g. --variants "
                                "force_and_dilatation,force_only"},
       {run + "--variants force", "--variants: unknown variant 'force' (use force_and_dilatation, force_only or "
                                  "bond_term_only)"}});
}

// Blanks around the items of --variants and --fem-tip-sizes are not part of
// them (before 7 December 2026 "--variants: unknown variant
// ' force_and_dilatation'", "--fem-tip-sizes: '4mm ' has characters after
// the length"): both read, the run is refused on its grid, after them.
TEST_CASE("pd-validate-crack reads its lists with blanks around the items", "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_crack_blanks");
  const std::string geo = PD_CRACK_GEOMETRY;
  const ToolRun run = run_in(folder, PD_VALIDATE_CRACK_EXECUTABLE,
                             geo + " -o out --spacing 0.3um --variants 'force_only, force_and_dilatation' "
                                   "--fem-tip-sizes '4mm , 2mm'");
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::StartsWith("pd-validate-crack: error: " + geo + ": the uniform grid at the spacing "
                                        "0.0003 mm would have about ") &&
                          Catch::EndsWith(" available: give a larger --spacing\n"));
  CHECK_FALSE(fs::exists(folder + "/out"));
}

// A run's final state edited to a horizon that is no length: before 7
// December 2026 pd-validate-c2 --count-cracks found no particle in its ring
// and printed "0 cracks at the hole", exit 0.
TEST_CASE("pd-validate-c2 --count-cracks refuses a final state whose horizon is no positive length",
          "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c2_horizon");
  const std::string geo = PD_C1_GEOMETRY;
  // A ring of damaged particles round the plate's hole (centre (10, 10) mm, radius 4 mm).
  std::vector<double> x, y, damage, first;
  for (int k = 0; k < 72; ++k) {
    const double angle = k * M_PI / 36;
    x.push_back(10e-3 + 4.2e-3 * std::cos(angle));
    y.push_back(10e-3 + 4.2e-3 * std::sin(angle));
    damage.push_back(k == 18 || k == 54 ? 0.9 : 0.0);
    first.push_back(k == 18 || k == 54 ? 0.5 : -1.0);
  }
  for (const double horizon : {-1e-3, 0.0}) {
    fs::create_directories(folder + "/run");
    pd::write_vtp(folder + "/run/" + pd::results::final_state_file, x, y,
                  {{pd::results::damage, 1, damage}, {pd::results::damage_load_factor, 1, first}},
                  {{pd::results::field_horizon, {horizon}}});
    const ToolRun run = run_in(folder, PD_VALIDATE_C2_EXECUTABLE, geo + " --spacing 0.5mm --count-cracks run");
    INFO(run.err);
    CHECK(run.status == 1);
    CHECK(run.err == "pd-validate-c2: error: run/final_state.vtp: field 'horizon' is " + pd::shortest_text(horizon) +
                         ": not a positive length (pd-solve writes the run's horizon there; an edited or damaged "
                         "file)\n");
  }
}

// A plate a tool cannot compare (C1 and C2 without their hole, the centre
// crack on a plate with one): refused before the output folder is made, its
// missing parents included. Before 7 December 2026 the folder was made
// first and stayed, empty (the crack's with an empty fem/ in it).
TEST_CASE("the validation tools refuse a plate they cannot compare before making the output folder",
          "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_plates");
  const std::string c1 = PD_C1_GEOMETRY, crack = PD_CRACK_GEOMETRY;
  expect_refusals(folder, PD_VALIDATE_C1_EXECUTABLE, "pd-validate-c1",
                  {{crack + " --spacing 25mm -m 3 --fem-size 5mm -o out/c1",
                    crack + ": C1 expects exactly one hole, and the plate has 0: give a plate with one (e.g. "
                            "geometries/c1_plate_hole.geo)"}});
  expect_refusals(folder, PD_VALIDATE_C2_EXECUTABLE, "pd-validate-c2",
                  {{crack + " --spacing 25mm -m 3 -o out",
                    crack + ": no hole: C2 counts the cracks that start at the plate's hole (e.g. "
                            "geometries/c1_plate_hole.geo)"}});
  expect_refusals(folder, PD_VALIDATE_CRACK_EXECUTABLE, "pd-validate-crack",
                  {{c1 + " --spacing 1mm -m 3 -o out",
                    c1 + ": the cracked-plate FEM reference handles plates without holes (found hole_1)"}});
}

// NB-NUG boxes meshed 64 times finer than the spacing hold 4096 times its
// cells: the memory estimate counts them, as pd-mesh's does for
// --box-spacing, and the run is refused before any solve or folder (before
// 7 December 2026 the plate at dx alone was estimated: the runs at dx were
// solved, then the boxes built until time or memory ran out).
TEST_CASE("pd-validate-c1 counts boxes meshed finer in its memory estimate", "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c1_box_memory");
  const std::string geo = PD_C1_GEOMETRY;
  const double dx = 0.1e-3;
  const pd::PlateGeometry plate = pd::validation::plate_geometry_of(geo, dx);
  pd::validation::PlateGridSpec at_dx{geo, pd::GridKind::nbnug, dx, 16 * dx, pd::Quadrature::analytic, 1};
  pd::validation::PlateGridSpec boxed = at_dx;
  boxed.box_refinement = 64;
  // The plate at dx fits in this machine's memory, its boxes at dx / 64 do not.
  REQUIRE_NOTHROW(pd::validation::check_grid_fits_memory(at_dx, plate));
  std::string why;
  try {
    pd::validation::check_grid_fits_memory(boxed, plate);
  } catch (const pd::Error& e) {
    why = e.what();
  }
  if (why.empty()) {
    WARN("this machine has the memory for the boxes at dx / 64: nothing to refuse");
    return;
  }
  const std::string counted = why.substr(0, why.find(" and need "));
  CHECK_THAT(counted, Catch::StartsWith(geo + ": the NB-NUG grid at the spacing 0.1 mm, its boxes at 0.0015625 mm "
                                              "(--box-refinement 64), would have about "));
  const ToolRun run = run_in(folder, PD_VALIDATE_C1_EXECUTABLE,
                             geo + " --spacing 0.1mm -m 16 --grids nbnug --box-refinement 64 -o out");
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::StartsWith("pd-validate-c1: error: " + counted + " and need ") &&
                          Catch::EndsWith(" available: give a larger --spacing or a smaller --box-refinement\n"));
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(folder + "/out"));
}

// A near-hole band beyond the plate (a unit or an exponent gone wrong) is
// refused with the range, as pd-post's --angle-length is (before 7 December
// 2026 1e300mm and 1e-300mm were taken).
TEST_CASE("pd-validate-c1 refuses a near-hole band beyond the plate's diagonal", "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_c1_band");
  const std::string run = std::string(PD_C1_GEOMETRY) + " --spacing 0.5mm,1mm -o out ";
  expect_refusals(
      folder, PD_VALIDATE_C1_EXECUTABLE, "pd-validate-c1",
      {{run + "--near-hole-band 1e300mm",
        "--near-hole-band 1e+300 mm is longer than the plate's diagonal (28.2843 mm): give a length from the finest "
        "spacing to the plate's diagonal, 0.5 to 28.2843 mm, with its unit (e.g. --near-hole-band 1mm)"},
       {run + "--near-hole-band 30mm",
        "--near-hole-band 30 mm is longer than the plate's diagonal (28.2843 mm): give a length from the finest "
        "spacing to the plate's diagonal, 0.5 to 28.2843 mm, with its unit (e.g. --near-hole-band 1mm)"},
       {run + "--near-hole-band 1e-300mm",
        "--near-hole-band 1e-300 mm is shorter than the finest --spacing (0.5 mm): give a length from the finest "
        "spacing to the plate's diagonal, 0.5 to 28.2843 mm, with its unit (e.g. --near-hole-band 1mm)"}});
}

namespace {

// The names in `folder`, sorted ("fem/" for a folder).
std::vector<std::string> names_in(const std::string& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.push_back(entry.path().filename().string() + (entry.is_directory() ? "/" : ""));
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

// A run that fails after its output folder is made (here CalculiX failing,
// a made-up ccx first on the PATH, and a table that cannot be written) takes
// back what it wrote: a folder it made goes, with the parents it made; in a
// folder that existed, what it made or rewrote goes and the rest stays.
// Before 7 December 2026 the folder stayed with the FEM's files and the
// tables of the runs before the failure, as if a result.
TEST_CASE("a validation run that fails after making its output folder leaves nothing it wrote",
          "[quasistatic][validate-cli]") {
  const std::string folder = fresh("validate_failed_run");
  fs::create_directories(folder + "/bin");
  std::ofstream(folder + "/bin/ccx") << "#!/bin/sh\necho ' *ERROR reading the input: a made-up failure'\nexit 3\n";
  fs::permissions(folder + "/bin/ccx", fs::perms::owner_all);
  const std::string failing_ccx = "env PATH='" + folder + "/bin':\"$PATH\" ";

  // A folder and its parent made by the run: both gone.
  ToolRun run = run_in(folder, failing_ccx + PD_VALIDATE_CRACK_EXECUTABLE,
                       std::string(PD_CRACK_GEOMETRY) + " --spacing 12.5mm -m 3 --fem-tip-sizes 25mm -o out/crack");
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::StartsWith("pd-validate-crack: error: out/crack/fem/crack_h25000um.inp: ccx exited with status 3; "
                                            "end of out/crack/fem/crack_h25000um.log:") &&
                          Catch::Contains("*ERROR reading the input: a made-up failure"));
  CHECK_FALSE(fs::exists(folder + "/out"));

  // A folder of the user's: its files stay, the FEM's files of the run go.
  const std::string mine = folder + "/mine";
  fs::create_directories(mine + "/fem");
  std::ofstream(mine + "/notes.txt") << "keep me\n";
  std::ofstream(mine + "/c1_errors.csv") << "an earlier table\n";
  std::ofstream(mine + "/fem/earlier.inp") << "an earlier mesh\n";
  const std::string c1 = std::string(PD_C1_GEOMETRY) + " --spacing 1mm -m 3 --grids uniform --fem-size 1mm -o mine";
  run = run_in(folder, failing_ccx + PD_VALIDATE_C1_EXECUTABLE, c1);
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::StartsWith("pd-validate-c1: error: mine/fem/fem_clamp_3000000nm.inp: ccx exited with status 3"));
  CHECK(names_in(mine) == std::vector<std::string>{"c1_errors.csv", "fem/", "notes.txt"});
  CHECK(names_in(mine + "/fem") == std::vector<std::string>{"earlier.inp"});
  CHECK(file_text(mine + "/notes.txt") == "keep me\n");
  CHECK(file_text(mine + "/c1_errors.csv") == "an earlier table\n");

  // A table the run rewrote before it failed (c1_errors.md is a folder, so
  // its write fails after c1_errors.csv's): the rewritten table goes too.
  fs::create_directories(mine + "/c1_errors.md");
  run = run_in(folder, PD_VALIDATE_C1_EXECUTABLE, c1);
  CHECK(run.status == 1);
  CHECK_THAT(run.err, Catch::StartsWith("pd-validate-c1: error: ") && Catch::Contains("mine/c1_errors.md"));
  CHECK(names_in(mine) == std::vector<std::string>{"c1_errors.md/", "fem/", "notes.txt"});
  CHECK(names_in(mine + "/fem") == std::vector<std::string>{"earlier.inp"});
  CHECK(file_text(mine + "/notes.txt") == "keep me\n");
}
