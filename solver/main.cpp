// pd-solve: dynamic PMB peridynamics on a particle file, driven by a TOML scene
// (docs/scenes.md, docs/solver.md). The logic lives in pd_solver_core.
#include <boost/program_options.hpp>
#include <omp.h>

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "atomic_file.hpp"
#include "cli.hpp"
#include "pd/version.hpp"
#include "peak_memory.hpp"
#include "processes.hpp"
#include "run.hpp"
#include "scene.hpp"

namespace {

// Waiting OpenMP threads sleep instead of spinning, unless OMP_WAIT_POLICY
// or GOMP_SPINCOUNT says otherwise. The OpenMP runtime's threads spin at a
// barrier by default; where other processes use the cores too (a shared
// machine, tests run side by side) a spinning thread holds its core while the
// thread it waits for is off the other one, and a step's barriers each cost a
// scheduler time slice. With one core of two busy elsewhere that made the main
// job's grid 1.7 times slower (5.6 times beside a profiler), where sleeping
// costs it 9 % on a quiet machine (docs/performance.md, "Shared machines").
// The runtime reads the variable once, as it loads, before main: so pd-solve
// sets it and starts itself again, once. Not under valgrind, whose tools
// would lose the program at the exec (and which runs the threads one at a
// time anyway).
constexpr const char* kept_stderr_variable = "PD_SOLVE_KEPT_STDERR";

void sleep_while_waiting(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;  // the user's choice
  const char* preload = std::getenv("LD_PRELOAD");
  if (preload && std::strstr(preload, "vgpreload")) return;
  // Started by the dynamic loader itself (ld-linux-x86-64.so.2 pd-solve ...):
  // /proc/self/exe is the loader, which would not find the program again.
  char exe[4096];
  const ssize_t length = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (length <= 0) return;
  exe[length] = '\0';
  const char* name = std::strrchr(exe, '/');
  if (std::strncmp(name ? name + 1 : exe, "ld-", 3) == 0) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 0) != 0) return;
  // The runtime has warned already, in this image, about values of its
  // variables it cannot read (OMP_NUM_THREADS=abc); the new image would warn
  // again. So stderr points to /dev/null until the new image's main takes it
  // back (restore_stderr_after_start below); only the runtime writes there
  // before main.
  const int kept_stderr = dup(STDERR_FILENO);
  const int null_device = kept_stderr >= 0 ? open("/dev/null", O_WRONLY | O_CLOEXEC) : -1;
  if (null_device >= 0 && dup2(null_device, STDERR_FILENO) >= 0)
    setenv(kept_stderr_variable, std::to_string(kept_stderr).c_str(), 1);
  // The program's own path, not /proc/self/exe: the process takes its name
  // from the path it runs (ps, top and pkill would show `exe`).
  execv(exe, argv);
  // Not started again: stderr back, and the runtime's default stands, as the plan says.
  if (kept_stderr >= 0) dup2(kept_stderr, STDERR_FILENO), close(kept_stderr);
  if (null_device >= 0) close(null_device);
  unsetenv(kept_stderr_variable);
  unsetenv("OMP_WAIT_POLICY");
}

// In the image sleep_while_waiting started: stderr back where the user had it.
void restore_stderr_after_start() {
  const char* kept = std::getenv(kept_stderr_variable);
  if (!kept) return;
  const int fd = std::atoi(kept);
  unsetenv(kept_stderr_variable);
  if (fd > STDERR_FILENO && dup2(fd, STDERR_FILENO) >= 0) close(fd);
}

// The hardware threads this process may run on (its CPU affinity: mpirun
// binds each process to a core by default, taskset binds any), 0 if unknown.
int processors_allowed() {
  cpu_set_t set;
  CPU_ZERO(&set);
  return sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 0;
}

// The most OpenMP threads a process gets: its share of the machine's hardware
// threads (all of them on one process), and no more than it is bound to.
// More would only take turns on the same processors (and the runtime's
// spinning barriers make that slow), and thousands of threads exhaust the
// process's thread or stack limits, where the OpenMP runtime crashes instead
// of reporting. `binding`: the process's binding set the cap.
struct ThreadCap {
  int threads = 1;
  bool binding = false;
};
ThreadCap thread_cap() {
  const unsigned hardware = std::thread::hardware_concurrency();
  ThreadCap cap;
  cap.threads = (hardware > 0 ? static_cast<int>(hardware) : 1) / pd::solver::processes_on_this_machine();
  const int allowed = processors_allowed();
  if (allowed > 0 && allowed < cap.threads) cap = {allowed, true};
  cap.threads = std::max(cap.threads, 1);
  return cap;
}

// What caps the threads, after "more than" in the note: "the 2 hardware
// threads of this machine", on several processes of this machine each one's
// share of them, or the hardware threads the process is bound to.
std::string thread_cap_text() {
  const ThreadCap cap = thread_cap();
  const int processes = pd::solver::processes_on_this_machine();
  const std::string hardware = std::to_string(std::thread::hardware_concurrency());
  if (cap.binding)
    return "the " + std::to_string(cap.threads) + " of this machine's " + hardware +
           " hardware threads this process is bound to (its CPU affinity: mpirun's --bind-to, taskset)";
  if (processes == 1) return "the " + std::to_string(cap.threads) + " hardware threads of this machine";
  return "each of the " + std::to_string(processes) + " processes' share (" + std::to_string(cap.threads) +
         ") of the " + hardware + " hardware threads of this machine";
}

// The same after "from 1 up to" in the refusal of --threads: "this machine's
// 2 hardware threads", or the cap and what sets it.
std::string thread_range_text() {
  const ThreadCap cap = thread_cap();
  if (!cap.binding && pd::solver::processes_on_this_machine() == 1)
    return "this machine's " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
  return std::to_string(cap.threads) + ", " + thread_cap_text();
}

// --threads as typed: a whole number of threads, 0 for the default. A count
// beyond an int's range is a count above the machine's like any other
// (capped_threads caps it, with its note); anything else is refused with
// the range and what the machine has (before 7 December 2026 Boost's "the
// argument ('abc') for option '--threads' is invalid" said neither, and so
// did it of 99999999999).
int thread_count_option(const std::string& text) {
  const std::size_t sign = !text.empty() && text[0] == '+' ? 1 : 0;
  if (text.size() == sign || text.find_first_not_of("0123456789", sign) != std::string::npos)
    throw pd::Error("--threads '" + pd::clipped(text) + "': expected a whole number of threads per process: 0 for "
                    "the default (OMP_NUM_THREADS if set, else the machine's, fewer for a small plate), or from 1 up "
                    "to " + thread_range_text() + " (a larger count is capped to them)");
  errno = 0;
  const long long count = std::strtoll(text.c_str(), nullptr, 10);
  return errno == ERANGE || count > std::numeric_limits<int>::max() ? std::numeric_limits<int>::max()
                                                                     : static_cast<int>(count);
}

// The thread count to ask OpenMP for (0 = its default), capped with a note on
// stderr (by the first process). `requested` is --threads (`typed` as the
// user wrote it); with 0 the default comes from OMP_NUM_THREADS (its first
// entry), which is capped the same way, or else from the OpenMP runtime (the
// processors the process may use), which is capped without a note.
int capped_threads(int requested, const std::string& typed) {
  std::string source = "--threads " + typed;
  long wanted = requested;
  const int cap = thread_cap().threads;
  if (requested == 0) {
    const char* environment = std::getenv("OMP_NUM_THREADS");
    if (!environment) return omp_get_max_threads() <= cap ? 0 : cap;
    wanted = std::strtol(environment, nullptr, 10);
    source = std::string("OMP_NUM_THREADS=") + environment;
  }
  if (wanted <= cap) return requested;
  if (pd::solver::process_rank() == 0)
    std::cerr << "pd-solve: note: " << source << " is more than " << thread_cap_text() << "; using " << cap << "\n";
  return cap;
}

// The run: the command line and the scene (read by every process, which
// agree on their errors: a bad key is reported once), then the scene's run.
int solve(int argc, char** argv) {
  namespace po = boost::program_options;
  po::options_description options("Usage: pd-solve SCENE.toml [options]\nOptions");
  options.add_options()
      ("help,h", "show this help")
      ("version", "print the version")
      ("set", po::value<std::vector<std::string>>()->composing(),
       "override a scene key: --set section.key=value (TOML value syntax), repeatable")
      ("output,o", po::value<std::string>(), "output directory (default: out/<scene name>)")
      ("restart", "continue from OUTDIR/checkpoint.bin")
      ("threads", po::value<std::string>()->default_value("0"),
       "OpenMP threads per process (0 = default: OMP_NUM_THREADS if set, else the machine's, fewer for a small "
       "plate: one per 400,000 directed bonds; at most the process's share of the machine's hardware threads)")
      ("quiet,q", "no progress lines on stderr")
      ("verbose,v", "with [refinement]: a second line per event, the set-up's counts and the parts' times");
  po::variables_map vm;
  bool go_on = true;
  std::optional<pd::solver::Scene> scene;
  pd::solver::RunOptions run;
  // --help and --version: printed by the root process alone.
  std::ostream silent(nullptr);
  std::ostream& text_out = pd::solver::process_rank() == 0 ? std::cout : silent;
  pd::solver::on_every_process([&] {
    go_on = pd::parse_command_line(argc, argv, "pd-solve", options, "scene", vm,
                                   "Scene keys: docs/scenes.md; output directory: docs/formats.md\n", text_out);
    if (!go_on) return;
    if (!vm.count("scene")) throw pd::Error("no scene file given (usage: pd-solve SCENE.toml [options], see --help)");
    const std::string scene_path = vm["scene"].as<std::string>();
    pd::check_usable_path(scene_path, "");
    std::vector<std::string> overrides;
    if (vm.count("set")) overrides = vm["set"].as<std::vector<std::string>>();
    scene.emplace(pd::solver::read_scene(scene_path, overrides));
    run.output_dir = vm.count("output") ? vm["output"].as<std::string>()
                                        : (std::filesystem::path("out") / std::filesystem::path(scene_path).stem()).string();
    run.restart = vm.count("restart") > 0;
    run.threads = thread_count_option(vm["threads"].as<std::string>());
  });
  if (!go_on) return 0;
  run.threads_by_size = run.threads == 0 && !std::getenv("OMP_NUM_THREADS");
  run.threads = capped_threads(run.threads, vm["threads"].as<std::string>());
  run.show_progress = vm.count("quiet") == 0;
  run.refinement_details = vm.count("verbose") > 0;
  pd::solver::run_scene(*scene, run);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  restore_stderr_after_start();
  sleep_while_waiting(argv);
  pd::solver::return_large_blocks_when_freed();
  // MPI when started by mpirun (docs/solver.md, "Running on several processes (MPI)").
  pd::solver::ProcessSession processes(argc, argv);
  const int status = pd::run_tool("pd-solve", [&] {
    try {
      return solve(argc, argv);
    } catch (const pd::solver::ReportedByAnotherProcess&) {
      return 1;  // another process prints the error
    } catch (const std::exception& e) {
      // An error of this process alone (every process's errors are agreed
      // on, pd::solver::on_every_process): which process says it.
      if (pd::solver::failure_known_to_all()) throw;
      throw pd::Error(pd::solver::with_process_rank(e.what()));
    }
  });
  // A process that failed alone would leave the others waiting for it.
  if (status != 0 && pd::solver::process_count() > 1 && !pd::solver::failure_known_to_all())
    pd::solver::ProcessSession::abort_all(status);
  return status;
}
