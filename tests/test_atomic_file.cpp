// Atomic output under a full disk, and the clean-up after killed runs.
//
// A full disk is simulated by RLIMIT_FSIZE in a child process: a write past
// the limit fails with EFBIG after the bytes that fit were written, as a full
// file system fails with ENOSPC. It needs no privileges and no special file
// system, so it behaves the same on every CI machine. Every writer of common/
// must then fail with a pd::Error naming the file and leave nothing under the
// final name (and no temporary file); the same writer without the limit
// succeeds, so the test tells the two apart.
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "atomic_file.hpp"
#include "error.hpp"
#include "lattice.hpp"
#include "particle_file.hpp"
#include "vtk_output.hpp"
#include "test_folder.hpp"

namespace fs = std::filesystem;

namespace {

std::string fresh_folder(const std::string& name) { return pd::test_support::fresh_folder_under(PD_TEST_TMPDIR, name); }

std::set<std::string> names_in(const std::string& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.insert(entry.path().filename().string());
  return names;
}

// What `write` did in a child process whose files cannot grow beyond
// `file_size_limit` bytes: "ok", "pd::Error: MESSAGE", or how it failed otherwise.
std::string outcome_with_file_size_limit(rlim_t file_size_limit, const std::function<void()>& write) {
  int channel[2];
  REQUIRE(::pipe(channel) == 0);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    ::close(channel[0]);
    std::string result;
    ::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead of killing the process
    const rlimit limit{file_size_limit, file_size_limit};
    if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) {
      result = "setrlimit failed";
    } else {
      try {
        write();
        result = "ok";
      } catch (const pd::Error& e) {
        result = std::string("pd::Error: ") + e.what();
      } catch (const std::exception& e) {
        result = std::string("other exception: ") + e.what();
      }
    }
    const auto written = ::write(channel[1], result.data(), result.size());
    ::_exit(written == static_cast<ssize_t>(result.size()) ? 0 : 1);
  }
  ::close(channel[1]);
  std::string result;
  char buffer[512];
  for (ssize_t got; (got = ::read(channel[0], buffer, sizeof buffer)) > 0;) result.append(buffer, got);
  ::close(channel[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  if (!WIFEXITED(status)) return "child killed by signal " + std::to_string(WTERMSIG(status));
  return result;
}

// Runs `write` (which writes `path`) with the file size limit: it must fail
// with a pd::Error naming `path`, and leave the folder as it was. Without the
// limit it must succeed.
void check_full_disk(const std::string& path, rlim_t limit, const std::function<void()>& write) {
  const std::string folder = fs::path(path).parent_path().string();
  const auto before = names_in(folder);
  const auto outcome = outcome_with_file_size_limit(limit, write);
  INFO("outcome with a " << limit << "-byte file size limit: " << outcome);
  CHECK_THAT(outcome, Catch::StartsWith("pd::Error: " + path + ": "));
  CHECK(names_in(folder) == before);  // nothing under the final name, no temporary file
  CHECK(outcome_with_file_size_limit(RLIM_INFINITY, write) == "ok");
  CHECK(fs::exists(path));
}

pd::ParticleSet small_plate() {
  return pd::make_rectangle_lattice(20e-3, 10e-3, 1e-3, 3e-3, pd::Quadrature::analytic);
}

}  // namespace

TEST_CASE("writers of common/ fail loudly on a full disk and leave no file", "[atomic-file]") {
  const auto folder = fresh_folder("full_disk");
  const auto plate = small_plate();  // built here: the children only write

  SECTION("particle file") {
    check_full_disk(folder + "/plate.pdp", 4096, [&] { pd::write_particle_file(folder + "/plate.pdp", plate); });
  }
  SECTION("VTK PolyData snapshot") {
    std::vector<double> values(plate.size(), 1.5);
    const auto path = folder + "/step.vtp";
    check_full_disk(path, 2048, [&] { pd::write_vtp(path, plate.x, plate.y, {{"damage", 1, values}}); });
  }
  SECTION("particle view") {
    check_full_disk(folder + "/plate.vtp", 2048, [&] { pd::write_particles_vtp(folder + "/plate.vtp", plate); });
  }
  SECTION("ParaView collection") {
    std::vector<std::pair<double, std::string>> entries;
    for (int k = 0; k < 100; ++k) entries.push_back({k * 1e-6, "snapshots/step_" + std::to_string(k) + ".vtp"});
    check_full_disk(folder + "/run.pvd", 512, [&] { pd::write_pvd(folder + "/run.pvd", entries); });
  }
  SECTION("any stream writer") {
    const std::string text(100000, 'x');
    check_full_disk(folder + "/table.csv", 10000,
                    [&] { pd::write_atomically(folder + "/table.csv", [&](std::ofstream& out) { out << text; }); });
  }
}

TEST_CASE("a failed rewrite keeps the previous complete file", "[atomic-file]") {
  const auto folder = fresh_folder("rewrite");
  const auto path = folder + "/table.csv";
  pd::write_atomically(path, [](std::ofstream& out) { out << "complete\n"; });
  const std::string longer(100000, 'y');
  const auto outcome = outcome_with_file_size_limit(
      1000, [&] { pd::write_atomically(path, [&](std::ofstream& out) { out << longer; }); });
  CHECK_THAT(outcome, Catch::StartsWith("pd::Error: " + path));
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  CHECK(line == "complete");
  CHECK(names_in(folder) == std::set<std::string>{"table.csv"});
}

TEST_CASE("a writer by name that writes nothing or throws leaves no file", "[atomic-file]") {
  const auto folder = fresh_folder("via");
  const auto path = folder + "/picture.png";
  CHECK_THROWS_WITH(pd::write_atomically_via(path, [](const std::string&) {}),
                    Catch::Contains(path) && Catch::Contains("writer produced no file"));
  CHECK_THROWS_WITH(pd::write_atomically_via(path, [](const std::string& tmp) { std::ofstream{tmp}; }),
                    Catch::Contains(path) && Catch::Contains("empty file"));
  CHECK_THROWS_WITH(pd::write_atomically_via(path,
                                             [&](const std::string& tmp) {
                                               std::ofstream(tmp) << "half";
                                               throw pd::file_error(path, "encoder failed");
                                             }),
                    Catch::Contains("encoder failed"));
  CHECK(names_in(folder).empty());
}

// A result named like a folder, a FIFO (or a device: /dev/null, which the
// rename replaced when run as root) is refused before anything is written,
// and the thing named stays as it was; a symbolic link is replaced, not
// what it points to.
TEST_CASE("a result path that names a folder or a FIFO is refused and left alone", "[atomic-file]") {
  const auto folder = fresh_folder("not_a_file");
  std::filesystem::create_directory(folder + "/sub");
  const auto fifo = folder + "/pipe";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const auto write = [](std::ofstream& out) { out << "result\n"; };
  CHECK_THROWS_WITH(pd::write_atomically(folder + "/sub", write), Catch::Contains("sub: is a folder, not a file"));
  CHECK_THROWS_WITH(pd::write_atomically_via(fifo, [](const std::string& tmp) { std::ofstream(tmp) << "x"; }),
                    Catch::Contains("pipe: is a FIFO, not a file"));
  CHECK_THROWS_WITH(pd::check_replaceable_file(fifo, "-o"), Catch::StartsWith("-o " + fifo + ": is a FIFO"));
  CHECK(std::filesystem::is_directory(folder + "/sub"));
  CHECK(std::filesystem::is_fifo(fifo));
  std::ofstream(folder + "/target") << "kept\n";
  std::filesystem::create_symlink(folder + "/target", folder + "/link");
  pd::write_atomically(folder + "/link", write);
  CHECK(std::filesystem::is_regular_file(std::filesystem::symlink_status(folder + "/link")));
  std::ifstream in(folder + "/target");
  std::string line;
  std::getline(in, line);
  CHECK(line == "kept");
}

// Reference: the temporary names of docs/formats.md, "NAME.tmp.PID" and
// ".tmp.PID.NAME"; a killed run's PID no longer runs. A PID that runs is
// taken from a child process kept alive for the test.
TEST_CASE("stale temporary files of killed runs are removed, nothing else", "[atomic-file]") {
  const auto folder = fresh_folder("stale");
  // A PID that no longer runs: a child that has exited and been reaped.
  const pid_t gone = ::fork();
  REQUIRE(gone >= 0);
  if (gone == 0) ::_exit(0);
  ::waitpid(gone, nullptr, 0);
  // A PID that runs: a child that waits until the test ends.
  int hold[2];
  REQUIRE(::pipe(hold) == 0);
  const pid_t alive = ::fork();
  REQUIRE(alive >= 0);
  if (alive == 0) {
    char c;
    ::close(hold[1]);
    while (::read(hold[0], &c, 1) > 0) {
    }
    ::_exit(0);
  }
  ::close(hold[0]);
  const std::string dead = std::to_string(gone), running = std::to_string(alive), own = std::to_string(::getpid());
  const std::vector<std::string> stale{"energy.csv.tmp." + dead, ".tmp." + dead + ".arrival.vtp",
                                       "checkpoint.bin.tmp." + own, ".tmp." + own + ".step_00000100.vtp"};
  const std::vector<std::string> kept{"energy.csv",           "arrival.vtp",          "energy.csv.tmp." + running,
                                      ".tmp." + running + ".arrival.vtp", "notes.tmp.txt", ".tmp.12ab.vtp",
                                      "x.tmp.",               ".tmp." + dead,         "summary.json.tmp.1x2"};
  for (const auto& name : stale) std::ofstream(folder + "/" + name) << "partial";
  for (const auto& name : kept) std::ofstream(folder + "/" + name) << "keep";
  fs::create_directories(folder + "/snapshots");
  std::ofstream(folder + "/snapshots/.tmp." + dead + ".step_00000000.vtp") << "partial";  // a subfolder: not scanned

  const auto removed = pd::remove_stale_temporaries(folder);
  CHECK(std::set<std::string>(removed.begin(), removed.end()) == std::set<std::string>(stale.begin(), stale.end()));
  auto expected = std::set<std::string>(kept.begin(), kept.end());
  expected.insert("snapshots");
  CHECK(names_in(folder) == expected);
  CHECK(pd::remove_stale_temporaries(folder + "/snapshots").size() == 1);
  CHECK(pd::remove_stale_temporaries(folder + "/does-not-exist").empty());

  ::close(hold[1]);  // lets the waiting child end
  ::waitpid(alive, nullptr, 0);
}
