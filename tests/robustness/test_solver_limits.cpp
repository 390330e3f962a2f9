// pd-solve's command-line limits (docs/robustness.md): an absurd thread count,
// from --threads or from OMP_NUM_THREADS, used to crash the OpenMP runtime
// while it created the threads. It is capped to the machine's hardware
// threads with a note, and the run completes.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "lattice.hpp"
#include "particle_file.hpp"
#include "../test_folder.hpp"
#include "../test_commands.hpp"

namespace fs = std::filesystem;

namespace {

using namespace pd::test_support;

std::string fresh_folder(const std::string& name) { return pd::test_support::fresh_folder_under(PD_TEST_TMPDIR, name); }

// Runs `command` through the shell with stdout and stderr to `log`; the exit
// status, or -1 after a signal.
int run(const std::string& command, const std::string& log) {
  return run_shell(command + " > " + log + " 2>&1");
}

// A small plate and a scene of a few steps.
std::string plate_scene(const std::string& folder) {
  pd::write_particle_file(folder + "/plate.pdp",
                          pd::make_rectangle_lattice(10e-3, 6e-3, 1e-3, 3e-3, pd::Quadrature::analytic));
  std::ofstream(folder + "/scene.toml") << "particles = \"plate.pdp\"\n"
                                           "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\n"
                                           "fracture_energy = 200\n"
                                           "[time]\nstep = \"auto\"\nend = 1e-6\n"
                                           "[[loads]]\nset = \"top\"\ntype = \"velocity\"\ny = 0.3\n";
  return folder + "/scene.toml";
}

}  // namespace

TEST_CASE("pd-solve caps an absurd thread count at the hardware threads", "[robustness][threads]") {
  if (pd::test_support::processors_allowed() < static_cast<int>(std::thread::hardware_concurrency())) {
    WARN("bound to fewer hardware threads than the machine has (taskset, a container's CPU set): the cap and its "
         "message are the binding's, tests/mpi/test_mpi_runs.cpp");
    return;
  }
  const auto folder = fresh_folder("threads");
  const auto scene = plate_scene(folder);
  const std::string cap = std::to_string(std::max(1u, std::thread::hardware_concurrency()));
  const std::string solve = std::string(PD_SOLVE_EXECUTABLE) + " " + scene + " -q -o " + folder;

  SECTION("--threads 100000") {
    const auto log = folder + "/threads.log";
    const int status = run(solve + "/out_option --threads 100000", log);
    INFO(file_text(log));
    REQUIRE(status == 0);
    CHECK_THAT(file_text(log), Catch::Contains("pd-solve: note: --threads 100000 is more than the " + cap +
                                             " hardware threads of this machine; using " + cap));
    CHECK_THAT(file_text(folder + "/out_option/summary.json"), Catch::Contains("\"threads\": " + cap + ","));
  }
  SECTION("OMP_NUM_THREADS=100000") {
    const auto log = folder + "/environment.log";
    const int status = run("env OMP_NUM_THREADS=100000 " + solve + "/out_environment", log);
    INFO(file_text(log));
    REQUIRE(status == 0);
    CHECK_THAT(file_text(log), Catch::Contains("pd-solve: note: OMP_NUM_THREADS=100000 is more than the " + cap +
                                             " hardware threads"));
  }
  SECTION("a count within the cap is used as given, without a note") {
    const auto log = folder + "/one.log";
    REQUIRE(run(solve + "/out_one --threads 1", log) == 0);
    CHECK(file_text(log).find("note:") == std::string::npos);
    CHECK_THAT(file_text(folder + "/out_one/summary.json"), Catch::Contains("\"threads\": 1,"));
  }
}
