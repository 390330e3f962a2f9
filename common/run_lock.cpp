#include "run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>

namespace pd {

LockAttempt try_run_lock(int descriptor, bool exclusive, int& error) {
  // pd-post's look holds the lock for microseconds: a run that meets it
  // tries again rather than refuse itself (20 tries, 1 ms apart).
  const int tries = exclusive ? 20 : 1;
  for (int attempt = 1;; ++attempt) {
    if (::flock(descriptor, (exclusive ? LOCK_EX : LOCK_SH) | LOCK_NB) == 0) return LockAttempt::taken;
    error = errno;
    if (error == EINTR) continue;
    if (error != EWOULDBLOCK) return LockAttempt::unsupported;
    if (attempt >= tries) return LockAttempt::held;
    ::usleep(1000);
  }
}

std::string run_lock_holder(int descriptor) {
  char text[32] = {};
  const ssize_t read = ::pread(descriptor, text, sizeof text - 1, 0);
  std::string pid(text, read > 0 ? static_cast<std::size_t>(read) : 0);
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.find_first_not_of("0123456789") == std::string::npos ? pid : std::string();
}

RunLockStatus run_lock_status(const std::string& folder) {
  RunLockStatus status;
  status.path = (std::filesystem::path(folder) / run_lock_file).string();
  // Read-only (a shared lock needs no more; another user's run is seen
  // too); non-blocking, so that a FIFO of that name cannot hold pd-post.
  const int descriptor = ::open(status.path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0) {
    status.state = errno == ENOENT || errno == ENOTDIR ? RunLockStatus::State::absent
                                                       : RunLockStatus::State::unknown;
    return status;
  }
  struct stat file {};
  int error = 0;
  if (::fstat(descriptor, &file) != 0 || !S_ISREG(file.st_mode)) {
    status.state = RunLockStatus::State::unknown;
  } else {
    switch (try_run_lock(descriptor, false, error)) {
      case LockAttempt::taken: status.state = RunLockStatus::State::free; break;  // (released by the close)
      case LockAttempt::held:
        status.state = RunLockStatus::State::held;
        status.pid = run_lock_holder(descriptor);
        break;
      case LockAttempt::unsupported: status.state = RunLockStatus::State::unknown; break;
    }
  }
  ::close(descriptor);
  return status;
}

}  // namespace pd
