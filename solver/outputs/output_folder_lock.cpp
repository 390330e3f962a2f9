#include "output_folder_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <utility>

#include "error.hpp"

namespace pd::solver {
namespace {

// The PID the lock file holds, as written; empty if none yet (its holder
// writes it just after it took the lock).
std::string holder_of(int descriptor) {
  char text[32] = {};
  const ssize_t read = ::pread(descriptor, text, sizeof text - 1, 0);
  std::string pid(text, read > 0 ? static_cast<std::size_t>(read) : 0);
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.find_first_not_of("0123456789") == std::string::npos ? pid : std::string();
}

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
  const std::string path = (std::filesystem::path(folder) / output_lock_file).string();
  // (Retried only when the file was replaced under us, which takes a run ending at that moment.)
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int descriptor = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (descriptor < 0)
      throw Error("-o " + clipped(folder) + ": cannot open its lock file " + output_lock_file + ": " +
                  std::strerror(errno));
    if (::flock(descriptor, LOCK_EX | LOCK_NB) != 0) {
      const int why = errno;
      if (why == EWOULDBLOCK) {
        const std::string holder = holder_of(descriptor);
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
    // The PID is for the message of a second run only: the lock holds without it.
    const bool emptied = ::ftruncate(descriptor, 0) == 0;
    const ssize_t written = emptied ? ::pwrite(descriptor, pid.data(), pid.size(), 0) : 0;
    static_cast<void>(written);
    descriptor_ = descriptor;
    path_ = path;
    return;
  }
  throw Error("-o " + clipped(folder) + ": its lock file " + output_lock_file +
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
