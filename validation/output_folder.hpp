#pragma once
// The output folder -o of a validation tool's run (pd-validate-c1, -c2,
// -crack): checked and made before the work, and taken back if the work
// fails, so that a failed run leaves nothing that looks like a result.
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pd::validation {

// Made, after every option is checked and before the work: a usable name, a
// folder or nothing yet (not a file), writable. An existing folder whose name
// ends in white space is taken, with a warning of `tool`'s.
//
// A run that leaves the scope of this object without finished() (an error:
// gmsh refusing the FEM's geometry, ccx missing or failing, a write that
// fails) takes back what it wrote: the folder with everything in it where
// the run made it (and any parents it made); in a folder that existed, the
// files and folders the run made or rewrote there and in `subfolders` (the
// tools' fem/), while what was there before, and not rewritten, stays.
// Before 7 December 2026 the folder stayed with its partial contents: the
// FEM's files, the tables of the runs before the failure.
class RunOutputFolder {
 public:
  RunOutputFolder(const std::string& out, const std::string& tool, std::vector<std::string> subfolders);
  ~RunOutputFolder();
  RunOutputFolder(const RunOutputFolder&) = delete;
  RunOutputFolder& operator=(const RunOutputFolder&) = delete;

  // The run wrote its results: they stay.
  void finished() { finished_ = true; }

 private:
  // What tells a file this run made or rewrote from the one found before it:
  // its inode (an atomic write renames a new file onto the name) and the
  // time it was last written (ccx writes its files in place).
  struct Stamp {
    unsigned long long device = 0, inode = 0;
    long long seconds = 0, nanoseconds = 0;
    bool operator==(const Stamp& o) const {
      return device == o.device && inode == o.inode && seconds == o.seconds && nanoseconds == o.nanoseconds;
    }
  };
  static std::optional<Stamp> stamp_of(const std::string& path);
  void take_back() const;

  std::string out_, made_;
  std::vector<std::string> subfolders_;
  std::map<std::string, Stamp> before_;  // the entries of out_ and its subfolders when the run began
  bool finished_ = false;
};

}  // namespace pd::validation
