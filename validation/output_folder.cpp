#include "output_folder.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <iostream>
#include <optional>

#include "atomic_file.hpp"
#include "error.hpp"

namespace pd::validation {
namespace {

namespace fs = std::filesystem;

// The entries of `folder` (none if it is not there).
std::vector<fs::path> entries_of(const fs::path& folder) {
  std::vector<fs::path> entries;
  std::error_code error;
  for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error))
    entries.push_back(it->path());
  return entries;
}

}  // namespace

// Not following a link (a link is the entry); none if it is gone.
std::optional<RunOutputFolder::Stamp> RunOutputFolder::stamp_of(const std::string& path) {
  struct stat s {};
  if (::lstat(path.c_str(), &s) != 0) return std::nullopt;
  Stamp stamp;
  stamp.device = static_cast<unsigned long long>(s.st_dev);
  stamp.inode = static_cast<unsigned long long>(s.st_ino);
  stamp.seconds = static_cast<long long>(s.st_mtim.tv_sec);
  stamp.nanoseconds = static_cast<long long>(s.st_mtim.tv_nsec);
  return stamp;
}

RunOutputFolder::RunOutputFolder(const std::string& out, const std::string& tool, std::vector<std::string> subfolders)
    : out_(out), subfolders_(std::move(subfolders)) {
  if (out.empty()) throw Error("-o: the value is empty: give the output folder, e.g. -o out/c1");
  check_usable_path(out, "-o");
  if (const std::string w = white_space_name_warning(out, "-o"); !w.empty())
    std::cerr << tool << ": warning: " << w << "\n";
  std::error_code error;
  const auto status = fs::status(out, error);
  if (fs::exists(status) && !fs::is_directory(status))
    throw Error("-o " + clipped(out) + ": is a file, not a folder: the tables and pictures are written into a "
                "folder; name one (it may exist)");
  if (fs::is_directory(status)) {
    if (const std::string why = why_cannot_write_in(out); !why.empty())
      throw Error("-o " + clipped(out) + ": cannot write in it: " + why);
    std::vector<fs::path> folders{fs::path(out)};
    for (const auto& sub : subfolders_) folders.push_back(fs::path(out) / sub);
    for (const auto& folder : folders)
      for (const auto& entry : entries_of(folder))
        if (const auto stamp = stamp_of(entry.string())) before_[entry.string()] = *stamp;
    return;
  }
  check_writable_folder_for(out, "-o");
  made_ = outermost_missing_folder(out);
  fs::create_directories(out, error);
  if (error) {
    std::error_code ignored;  // (the parents it made on the way)
    if (!made_.empty()) fs::remove_all(made_, ignored);
    throw Error("-o " + clipped(out) + ": cannot make the folder: " + error.message());
  }
}

RunOutputFolder::~RunOutputFolder() {
  if (finished_) return;
  try {
    take_back();
  } catch (...) {
    // (Nothing to add to the error that ended the run.)
  }
}

void RunOutputFolder::take_back() const {
  std::error_code ignored;
  if (!made_.empty()) {
    fs::remove_all(made_, ignored);
    return;
  }
  const auto made_or_rewritten = [&](const fs::path& entry) {
    const auto found = before_.find(entry.string());
    if (found == before_.end()) return true;
    const auto now = stamp_of(entry.string());
    return now && !(*now == found->second);
  };
  // The subfolders first: one that existed keeps what the run did not write.
  for (const auto& sub : subfolders_) {
    const fs::path folder = fs::path(out_) / sub;
    if (!before_.count(folder.string())) continue;  // made by the run: removed whole below
    for (const auto& entry : entries_of(folder))
      if (made_or_rewritten(entry)) fs::remove_all(entry, ignored);
  }
  for (const auto& entry : entries_of(out_)) {
    if (before_.count(entry.string()) && fs::is_directory(fs::symlink_status(entry, ignored))) continue;
    if (made_or_rewritten(entry)) fs::remove_all(entry, ignored);
  }
}

}  // namespace pd::validation
