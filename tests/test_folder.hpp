#pragma once
// A fresh, empty folder for one test: root / process id / name, where root is
// the suite's folder in the build tree (one parent per process: CTest runs
// test cases in parallel).
#include <unistd.h>

#include <filesystem>
#include <string>

namespace pd::test_support {

inline std::string fresh_folder_under(const std::string& root, const std::string& name) {
  const auto path = std::filesystem::path(root) / std::to_string(::getpid()) / name;
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path.string();
}

}  // namespace pd::test_support
