#include "atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include "checksum.hpp"
#include "error.hpp"

namespace pd {
namespace {

namespace fs = std::filesystem;

constexpr char temporary_marker[] = ".tmp.";

std::string process_id() { return std::to_string(static_cast<long>(::getpid())); }

std::string temporary_name(const std::string& path) { return path + temporary_marker + process_id(); }

// The reason of the last failed system call, if there was one.
std::string reason(int error) { return error != 0 ? std::string(": ") + std::strerror(error) : std::string(); }

// Checks the finished temporary file before it may take the final name: it
// holds `expected_bytes` (when known; otherwise it must not be empty), and it
// reaches the disk (fsync: some file systems report a full disk only there).
void check_and_sync(const std::string& temporary, const std::string& path, long long expected_bytes) {
  std::error_code error;
  const auto size = fs::file_size(temporary, error);
  if (error) throw file_error(path, "writer produced no file: " + error.message());
  if (expected_bytes >= 0 && size != static_cast<std::uintmax_t>(expected_bytes))
    throw file_error(path, "only " + std::to_string(size) + " of " + std::to_string(expected_bytes) +
                               " bytes reached the file (disk full?)");
  if (expected_bytes < 0 && size == 0) throw file_error(path, "writer produced an empty file (disk full?)");
  const int fd = ::open(temporary.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) throw file_error(path, "cannot reopen the written file" + reason(errno));
  const bool synced = ::fsync(fd) == 0;
  const int sync_error = errno;
  const bool closed = ::close(fd) == 0;
  if (!synced || !closed) throw file_error(path, "cannot flush to disk" + reason(synced ? errno : sync_error));
}

void rename_or_throw(const std::string& from, const std::string& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(from.c_str());
    throw file_error(to, "cannot move finished file into place: " + why);
  }
}

bool all_digits(const std::string& s) {
  if (s.empty() || s.size() > 18) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

// The PID in a temporary file name ("NAME.tmp.PID" or ".tmp.PID.NAME", NAME
// not empty), or 0 if the name is not one.
long temporary_owner(const std::string& name) {
  const std::string marker = temporary_marker;
  if (name.compare(0, marker.size(), marker) == 0) {
    const auto dot = name.find('.', marker.size());
    if (dot != std::string::npos && dot + 1 < name.size()) {
      const std::string pid = name.substr(marker.size(), dot - marker.size());
      if (all_digits(pid)) return std::stol(pid);
    }
  }
  const auto at = name.rfind(marker);
  if (at != std::string::npos && at > 0) {
    const std::string pid = name.substr(at + marker.size());
    if (all_digits(pid)) return std::stol(pid);
  }
  return 0;
}

// True if a process with this id runs (ours or anyone's).
bool process_running(long pid) {
  if (pid <= 0 || pid != static_cast<pid_t>(pid)) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

}  // namespace

void write_atomically(const std::string& path, const std::function<void(std::ofstream&)>& write) {
  check_replaceable_file(path, "");
  const std::string tmp = temporary_name(path);
  try {
    long long bytes = -1;
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) throw file_error(path, "cannot open for writing" + reason(errno));
      errno = 0;
      write(out);
      // The stream's whole length (writers may have gone back to rewrite a
      // header), then close: it flushes, so a full disk shows here at the latest.
      out.seekp(0, std::ios::end);
      bytes = static_cast<long long>(out.tellp());
      out.close();
      if (!out || bytes < 0) throw file_error(path, "write failed (disk full?)" + reason(errno));
    }
    check_and_sync(tmp, path, bytes);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  rename_or_throw(tmp, path);
}

void write_atomically_via(const std::string& path,
                          const std::function<void(const std::string&)>& write) {
  // Keep the extension last: some writers (VTK) look at it.
  check_replaceable_file(path, "");
  const fs::path p(path);
  const std::string tmp = (p.parent_path() / (temporary_marker + process_id() + "." + p.filename().string())).string();
  try {
    write(tmp);
    check_and_sync(tmp, path, -1);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  rename_or_throw(tmp, path);
}

std::vector<std::string> create_folder_for(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) return {};
  std::vector<std::string> missing;  // innermost first
  std::error_code error;
  for (fs::path f = folder; !f.empty() && !fs::exists(f, error); f = f.parent_path()) {
    missing.push_back(f.string());
    if (f == f.parent_path()) break;
  }
  fs::create_directories(folder, error);
  if (error || !fs::is_directory(folder, error)) {
    remove_made_folders({missing.rbegin(), missing.rend()});
    throw file_error(clipped(path), "cannot make its folder " + clipped(folder.string()) +
                                        (error ? ": " + error.message() : std::string(": a file has that name")));
  }
  return {missing.rbegin(), missing.rend()};
}

std::string outermost_missing_folder(const std::string& folder) {
  std::error_code error;
  fs::path missing;
  for (fs::path f = fs::absolute(folder, error).lexically_normal(); !error && !f.empty(); f = f.parent_path()) {
    std::error_code status_error;  // (set by not_found too: only another answer, or none, stops here)
    if (fs::symlink_status(f, status_error).type() != fs::file_type::not_found) break;
    missing = f;
    if (f == f.parent_path()) break;  // (the root)
  }
  return missing.string();
}

void remove_made_folders(const std::vector<std::string>& made) {
  std::error_code error;
  for (auto f = made.rbegin(); f != made.rend(); ++f)
    if (fs::is_directory(*f, error) && fs::is_empty(*f, error)) fs::remove(*f, error);
}

namespace {

// "a space", "a tab", "a line break" or "white space": what `c` is.
std::string white_space_name(char c) {
  return c == ' ' ? "a space" : c == '\t' ? "a tab" : c == '\n' || c == '\r' ? "a line break" : "white space";
}

// A name with white space at either end that names nothing (`-o "plate.pdp "`,
// a name copied with the space after it) is refused: the space is invisible in
// a listing and in every message that quotes the name. Before 7 December 2026
// pd-solve and pd-post made such a folder, pd-mesh wrote such a file with the
// advice to name it "plate.pdp .pdp", and an input was "not found" with the
// space unseen. A name that exists is the user's and is taken.
// Where a name (not white space only) has white space at its ends: "ends
// in a space", "begins with a tab and ends in a space"; empty for neither.
std::string white_space_at_ends(const std::string& name) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  if (name.empty() || (!blank(name.front()) && !blank(name.back()))) return "";
  return blank(name.front()) && blank(name.back())
             ? "begins with " + white_space_name(name.front()) + " and ends in " + white_space_name(name.back())
         : blank(name.front()) ? "begins with " + white_space_name(name.front())
                               : "ends in " + white_space_name(name.back());
}

bool names_something(const std::string& path) {
  std::error_code error;
  return fs::symlink_status(path, error).type() != fs::file_type::not_found && !error;
}

// An option's value as the key rule takes it: `-o 'run '` read from the
// working directory, the fix written "-o run".
std::string option_label(const std::string& path, const std::string& option) {
  return (option.empty() ? "" : option + " ") + "'" + clipped(path) + "'";
}
std::function<std::string(const std::string&)> option_given_as(const std::string& option) {
  return [option](const std::string& name) { return (option.empty() ? "" : option + " ") + name; };
}

void check_white_space_around(const std::string& path, const std::string& option) {
  static_cast<void>(white_space_name_check(path, "", option_label(path, option), option_given_as(option)));
}

// The same for a folder of the path (`-o "out /x.pdp"` where out exists and
// "out " does not; before 7 December 2026 only the ends of the whole name
// were looked at, and the tools made the folder "out "): each part from the
// first one that names nothing on, with the path's fix, every such part
// without its white space. `at` reads a name where the key's file is
// (scene.toml's particles = "out /plate.pdp" from the scene's folder; before
// 7 December 2026 that was "no such file", the space unseen). Where the
// fixed path names nothing either, the folder of the trimmed part that
// exists is named ("(the folder out, without it, exists)").
void check_white_space_in_parts(const std::string& path, const std::string& label,
                                const std::function<std::string(const std::string&)>& given_as,
                                const std::function<std::string(const std::string&)>& at) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  const char* const spaces = " \t\n\r\f\v";
  std::string fixed, culprit, trimmed_culprit, fixed_to_culprit;
  bool exists = true;
  std::error_code error;
  for (std::size_t start = 0; start <= path.size();) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    const std::string part = path.substr(start, end - start);
    if (exists && end > 0) exists = names_something(at(path.substr(0, end)));
    std::string shown = part;
    bool is_culprit = false;
    if (!exists && !part.empty() && (blank(part.front()) || blank(part.back()))) {
      const std::size_t first = part.find_first_not_of(spaces);
      shown = first == std::string::npos ? "" : part.substr(first, part.find_last_not_of(spaces) - first + 1);
      if (culprit.empty()) culprit = part, trimmed_culprit = shown, is_culprit = true;
    }
    // A part of white space only goes, with its '/'.
    if (!(shown.empty() && !part.empty())) fixed += shown + (end < path.size() ? "/" : "");
    if (is_culprit) fixed_to_culprit = fixed;
    start = end + 1;
  }
  if (culprit.empty()) return;
  const std::string where = trimmed_culprit.empty()         ? "is white space only"
                            : blank(culprit.front()) && blank(culprit.back())
                                ? "begins with " + white_space_name(culprit.front()) + " and ends in " +
                                      white_space_name(culprit.back())
                            : blank(culprit.front()) ? "begins with " + white_space_name(culprit.front())
                                                     : "ends in " + white_space_name(culprit.back());
  // The trimmed part's folder, without its '/' ("out"), where it is one.
  while (fixed_to_culprit.size() > 1 && fixed_to_culprit.back() == '/') fixed_to_culprit.pop_back();
  const bool folder_is_last = fixed_to_culprit.size() == fixed.size();
  const std::string note =
      names_something(at(fixed)) ? " (" + clipped(fixed) + ", without it, exists)"
      : !trimmed_culprit.empty() && !folder_is_last && fs::is_directory(at(fixed_to_culprit), error)
          ? " (the folder " + clipped(fixed_to_culprit) + ", without it, exists)"
          : std::string();
  throw Error(label + ": its part '" + clipped(culprit) + "' " + where + ", and no folder or file has that name" +
              note + ": give it without, " + given_as(clipped(fixed)));
}

}  // namespace

std::string unusable_path_reason(const std::string& path) {
  std::error_code error;
  static_cast<void>(fs::status(path, error));
  // Missing (or under a file, which the writer names when it tries): the tool's own message later.
  if (!error || error == std::errc::no_such_file_or_directory || error == std::errc::not_a_directory) return "";
  // What to do, where the system's words leave it unsaid (before 7 December
  // 2026 a link that leads back to itself was "Too many levels of symbolic
  // links" alone).
  const std::string advice =
      error == std::errc::filename_too_long ? "; give a shorter path"
      : error == std::errc::too_many_symbolic_link_levels
          ? ": a symbolic link on the path leads back to itself, or through more than 40 links (ls -l shows where "
            "each leads); mend or remove the link, or give a path without it"
          : std::string();
  return error.message() + advice;
}

void check_usable_path(const std::string& path, const std::string& option) {
  check_white_space_around(path, option);
  if (const std::string why = unusable_path_reason(path); !why.empty())
    throw Error((option.empty() ? std::string() : option + " ") + clipped(path) + ": " + why);
}

std::string white_space_name_warning(const std::string& path, const std::string& option) {
  // (Before 7 December 2026 taken without a word.)
  if (!names_something(path)) return "";
  return white_space_name_check(path, "", option_label(path, option), option_given_as(option));
}

std::string white_space_name_check(const std::string& name, const std::string& folder, const std::string& label,
                                   const std::function<std::string(const std::string&)>& given_as) {
  const auto at = [&](const std::string& n) {
    return folder.empty() || fs::path(n).is_absolute() ? n : (fs::path(folder) / n).string();
  };
  const std::string where = white_space_at_ends(name);
  if (where.empty()) {
    check_white_space_in_parts(name, label, given_as, at);
    return "";
  }
  const char* const spaces = " \t\n\r\f\v";
  const std::size_t first = name.find_first_not_of(spaces);
  const bool exists = names_something(at(name));
  if (first == std::string::npos) {
    if (exists) return "";  // (taken: what white space only names is plain to see)
    throw Error(label + ": the name is white space only: give a file or folder's name");
  }
  const std::string trimmed = name.substr(first, name.find_last_not_of(spaces) - first + 1);
  if (exists) {
    std::error_code error;
    return label + ": the name " + where + "; the " + (fs::is_directory(at(name), error) ? "folder" : "file") +
           " of that name exists and is used (" + clipped(trimmed) + ", without it, is another name)";
  }
  throw Error(label + ": the name " + where + ", and no file or folder has that name" +
              (names_something(at(trimmed)) ? " (" + clipped(trimmed) + ", without it, exists)" : std::string()) +
              ": give it without, " + given_as(clipped(trimmed)));
}

void check_replaceable_file(const std::string& path, const std::string& option, const std::string& advice) {
  std::error_code error;
  const fs::file_type type = fs::symlink_status(path, error).type();
  if (error || type == fs::file_type::not_found || type == fs::file_type::regular || type == fs::file_type::symlink)
    return;
  const char* what = type == fs::file_type::directory                                         ? "a folder"
                     : type == fs::file_type::block || type == fs::file_type::character ? "a device"
                     : type == fs::file_type::fifo                                            ? "a FIFO"
                     : type == fs::file_type::socket                                          ? "a socket"
                                                                                               : "not a regular file";
  throw Error((option.empty() ? std::string() : option + " ") + clipped(path) + ": is " + what +
              ", not a file: the result would take its place; " +
              (advice.empty() ? "name a file (it may exist: a result of an earlier run is replaced)" : advice));
}

std::string resolved_path(const std::string& path) {
  std::error_code error;
  fs::path resolved = fs::weakly_canonical(fs::absolute(path), error);
  if (error) resolved = fs::absolute(path).lexically_normal();
  // A path through a folder that does not exist yet ("RUN/new/..") keeps a
  // trailing separator ("RUN/"), which compares unequal to "RUN" (before 7
  // December 2026 pd-post -o RUN/new/.. wrote its summary.json over the run's).
  if (!resolved.has_filename() && resolved.has_relative_path()) resolved = resolved.parent_path();
  return resolved.string();
}

std::string why_cannot_write_in(const std::string& folder) {
  const fs::path probe = fs::path(folder) / (".write_test.tmp." + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  std::error_code ignored;
  fs::remove(probe, ignored);
  return {};
}

void check_writable_folder_for(const std::string& path, const std::string& option) {
  std::error_code error;
  fs::path folder = fs::absolute(path, error).parent_path();
  while (!folder.empty() && !fs::exists(folder, error) && folder != folder.parent_path()) folder = folder.parent_path();
  if (folder.empty()) return;
  // A file where a folder of the path must be (-o plate.geo/x.pdp): its
  // folder can never be made, which create_folder_for found only when the
  // result was written, after the work (before 7 December 2026).
  if (!fs::is_directory(folder, error)) {
    fs::path typed = fs::path(path).parent_path();  // the part at fault as typed, where it can be
    while (!typed.empty() && !fs::exists(typed, error)) typed = typed.parent_path();
    const std::string culprit = clipped((typed.empty() ? folder : typed).string());
    throw Error((option.empty() ? std::string() : option + " ") + clipped(path) + ": cannot make its folder " +
                clipped(fs::path(path).parent_path().string()) + ": " + culprit +
                (fs::is_regular_file(folder, error) ? " is a file" : " is no folder") +
                ", and a folder of the path cannot be inside it; give a path through folders");
  }
  const std::string why = why_cannot_write_in(folder.string());
  if (!why.empty())
    throw Error((option.empty() ? std::string() : option + " ") + clipped(path) + ": cannot write in its folder " +
                clipped(folder.string()) + ": " + why);
}

bool same_path(const std::string& a, const std::string& b) { return resolved_path(a) == resolved_path(b); }

bool path_within(const std::string& inner, const std::string& outer) {
  // By components: /run/snapshots2 is not inside /run/snapshots.
  const fs::path relative = fs::path(resolved_path(inner)).lexically_relative(resolved_path(outer));
  return !relative.empty() && *relative.begin() != "..";
}

std::vector<std::string> remove_stale_temporaries(const std::string& folder) {
  std::vector<std::string> removed;
  std::error_code error;
  if (!fs::is_directory(folder, error)) return removed;
  const long own = static_cast<long>(::getpid());
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file(error)) continue;
    const std::string name = entry.path().filename().string();
    const long owner = temporary_owner(name);
    if (owner == 0 || (owner != own && process_running(owner))) continue;
    if (!fs::remove(entry.path(), error) && error)
      throw file_error(entry.path().string(), "cannot remove a stale temporary file: " + error.message());
    removed.push_back(name);
  }
  return removed;
}

std::string file_hash_hex(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open for reading");
  Checksum c;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    c.update(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(c.value()));
  return hex;
}

}  // namespace pd
