#pragma once
// One run at a time in an output folder: two pd-solve runs writing the same
// files would leave a folder of neither run (docs/formats.md, "Solver output
// directory"). The lock and its test are common/run_lock's (pd-post looks
// at it too): flock(2) on OUTDIR/.pd-solve.lock, which holds the PID of the
// run that has it. The kernel releases it when that process ends, however it
// ends: a killed run's lock file never blocks the next run.
#include <iosfwd>
#include <string>

namespace pd::solver {

class OutputFolderLock {
public:
  OutputFolderLock() = default;  // holds nothing
  // Takes the lock of `folder`, which must exist. pd::Error naming -o (and
  // the other run's PID) when another process holds it. Where the file
  // system cannot lock at all, a warning on `log`, and the run goes on.
  OutputFolderLock(const std::string& folder, std::ostream& log);
  // Removes the lock file, then releases the lock (in this order: a run that
  // opened the file meanwhile finds its name gone and makes it anew).
  ~OutputFolderLock();
  OutputFolderLock(OutputFolderLock&& other) noexcept;
  OutputFolderLock& operator=(OutputFolderLock&& other) noexcept;
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;

private:
  void release();
  int descriptor_ = -1;
  std::string path_;
};

}  // namespace pd::solver
