#pragma once
// Running pd-mesh from a test as a user does: a scratch file per test
// process, the exit status and what the tool wrote to stderr.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "../test_commands.hpp"

namespace pd::test_support {

// PD_TEST_TMPDIR / process id / name (CTest runs test cases in parallel).
inline std::string mesher_temp(const std::string& name) {
  const auto dir = std::filesystem::path(PD_TEST_TMPDIR) / std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

struct MeshRun {
  int status = 0;
  std::string err;
  double seconds = 0;  // wall time of the whole command
};

// pd-mesh under coreutils' `timeout`, so that a hang fails the test in
// bounded time (status 124) instead of stalling the suite.
inline MeshRun run_pd_mesh(const std::string& arguments, int timeout_seconds = 600) {
  const std::string err = mesher_temp("pd_mesh_stderr.txt");
  const std::string command = "timeout " + std::to_string(timeout_seconds) + " " + std::string(PD_MESH_EXE) + " " +
                              arguments + " > /dev/null 2> " + err;
  const auto start = std::chrono::steady_clock::now();
  MeshRun run;
  run.status = run_shell(command);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.err = file_text(err);
  return run;
}

// pd-mesh ARGUMENTS -o OUTPUT must fail: non-zero exit, `fragment` in what
// it wrote to stderr, and no OUTPUT left behind.
inline void expect_pd_mesh_failure(const std::string& arguments, const std::string& output,
                                   const std::string& fragment) {
  std::filesystem::remove(output);
  const auto run = run_pd_mesh(arguments + " -o " + output);
  INFO("pd-mesh " << arguments << "\nstderr: " << run.err);
  CHECK(run.status != 0);
  CHECK_THAT(run.err, Catch::Contains(fragment));
  CHECK_FALSE(std::filesystem::exists(output));
}

// pd-mesh ARGUMENTS -o OUTPUT must be refused with `error` alone: exit 1,
// the one line "pd-mesh: error: ERROR" on stderr (no warning before it) and
// no OUTPUT left behind.
inline void expect_pd_mesh_refusal_alone(const std::string& arguments, const std::string& output,
                                         const std::string& error) {
  std::filesystem::remove(output);
  const auto run = run_pd_mesh(arguments + " -o " + output);
  INFO("pd-mesh " << arguments);
  CHECK(run.status == 1);
  CHECK(run.err == "pd-mesh: error: " + error + "\n");
  CHECK_FALSE(std::filesystem::exists(output));
}

// pd-mesh ARGUMENTS must mesh (exit 0) with `warning` ("" for none) the
// only line on stderr, "pd-mesh: warning: WARNING".
inline void expect_pd_mesh_warning_alone(const std::string& arguments, const std::string& warning) {
  const auto run = run_pd_mesh(arguments);
  INFO("pd-mesh " << arguments);
  CHECK(run.status == 0);
  CHECK(run.err == (warning.empty() ? "" : "pd-mesh: warning: " + warning + "\n"));
}

inline std::string write_text_file(const std::string& name, const std::string& text) {
  const auto path = mesher_temp(name);
  std::ofstream(path) << text;
  return path;
}

// The .geo text of the plate [0, width] x [0, height] (mm), one plane surface.
inline std::string rectangle_geo(double width_mm, double height_mm) {
  const std::string w = std::to_string(width_mm), h = std::to_string(height_mm);
  return "Point(1) = {0, 0, 0}; Point(2) = {" + w + ", 0, 0}; Point(3) = {" + w + ", " + h + ", 0}; Point(4) = {0, " +
         h + ", 0};\nLine(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
         "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n";
}

// The .geo text of a 40 x 40 mm plate with a hole of radius 4 mm at its
// centre (20, 20) mm (built-in kernel, two half circles).
inline const std::string plate_40_hole_geo =
    "Point(1) = {0, 0, 0}; Point(2) = {40, 0, 0}; Point(3) = {40, 40, 0}; Point(4) = {0, 40, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4};\n"
    "Point(5) = {20, 20, 0}; Point(6) = {24, 20, 0}; Point(7) = {16, 20, 0};\n"
    "Circle(5) = {6, 5, 7}; Circle(6) = {7, 5, 6}; Curve Loop(2) = {5, 6};\n"
    "Plane Surface(1) = {1, 2};\n";

}  // namespace pd::test_support
