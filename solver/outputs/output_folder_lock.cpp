#include "output_folder_lock.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <utility>

#include "error.hpp"
#include "run_lock.hpp"

namespace pd::solver {
namespace {

// Whether the open file is still the one under `path`: a run that ended
// between our open and our lock has removed it (and another run may have
// made a new one, whose lock is the one that counts).
bool still_named(int descriptor, const std::string& path) {
  struct stat held {}, named {};
  return ::fstat(descriptor, &held) == 0 && ::stat(path.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
         held.st_ino == named.st_ino;
}

}  // namespace

OutputFolderLock::OutputFolderLock(const std::string& folder, std::ostream& log) {
  const std::string path = (std::filesystem::path(folder) / run_lock_file).string();
  // (Retried only when the file was replaced under us, which takes a run ending at that moment.)
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int descriptor = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (descriptor < 0)
      throw Error("-o " + clipped(folder) + ": cannot open its lock file " + run_lock_file + ": " +
                  std::strerror(errno));
    int why = 0;
    const LockAttempt locked = try_run_lock(descriptor, true, why);
    if (locked != LockAttempt::taken) {
      if (locked == LockAttempt::held) {
        const std::string holder = run_lock_holder(descriptor);
        ::close(descriptor);
        throw Error("-o " + clipped(folder) + ": another pd-solve run" +
                    (holder.empty() ? std::string() : " (PID " + holder + ")") +
                    " is writing into this folder; wait for it to end, or give another -o");
      }
      ::close(descriptor);
      log << "warning: -o " << clipped(folder) << ": the file system cannot lock the output folder ("
          << std::strerror(why) << "): a second run into it at the same time would not be refused\n";
      return;
    }
    if (!still_named(descriptor, path)) {
      ::close(descriptor);
      continue;
    }
    const std::string pid = std::to_string(static_cast<long>(::getpid())) + "\n";
    // The PID is for the messages of a second run and of pd-post only: the lock holds without it.
    const bool emptied = ::ftruncate(descriptor, 0) == 0;
    const ssize_t written = emptied ? ::pwrite(descriptor, pid.data(), pid.size(), 0) : 0;
    static_cast<void>(written);
    descriptor_ = descriptor;
    path_ = path;
    return;
  }
  throw Error("-o " + clipped(folder) + ": its lock file " + run_lock_file +
              " keeps being replaced by other runs; wait for them to end, or give another -o");
}

void OutputFolderLock::release() {
  if (descriptor_ < 0) return;
  ::unlink(path_.c_str());
  ::close(descriptor_);
  descriptor_ = -1;
}

OutputFolderLock::~OutputFolderLock() { release(); }

OutputFolderLock::OutputFolderLock(OutputFolderLock&& other) noexcept
    : descriptor_(std::exchange(other.descriptor_, -1)), path_(std::move(other.path_)) {}

OutputFolderLock& OutputFolderLock::operator=(OutputFolderLock&& other) noexcept {
  if (this != &other) {
    release();
    descriptor_ = std::exchange(other.descriptor_, -1);
    path_ = std::move(other.path_);
  }
  return *this;
}

}  // namespace pd::solver
