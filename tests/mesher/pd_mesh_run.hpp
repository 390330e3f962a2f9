#pragma once
// Running pd-mesh from a test as a user does: a scratch file per test
// process, the exit status and what the tool wrote to stderr.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

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
};

inline MeshRun run_pd_mesh(const std::string& arguments) {
  const std::string err = mesher_temp("pd_mesh_stderr.txt");
  const std::string command = std::string(PD_MESH_EXE) + " " + arguments + " > /dev/null 2> " + err;
  const int raw = std::system(command.c_str());
  std::ifstream in(err);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, std::string(std::istreambuf_iterator<char>(in), {})};
}

inline std::string write_text_file(const std::string& name, const std::string& text) {
  const auto path = mesher_temp(name);
  std::ofstream(path) << text;
  return path;
}

}  // namespace pd::test_support
