#pragma once
// The lock a pd-solve run holds on its output folder (one run per folder at
// a time): flock(2) on OUTDIR/.pd-solve.lock, which holds the PID of the run
// that has it. The kernel releases it when that process ends, however it
// ends, so whether it is held tells a run that is still going from one that
// stopped: pd-solve takes it (solver/outputs/output_folder_lock), pd-post
// only looks (run_lock_status).
#include <string>

namespace pd {

// Name of the lock file inside OUTDIR.
inline constexpr const char* run_lock_file = ".pd-solve.lock";

enum class LockAttempt {
  taken,        // this process has it now
  held,         // another process holds it
  unsupported,  // the file system cannot lock (the errno is in `error`)
};

// Tries to lock the open lock file `descriptor` without waiting: exclusive
// (a run's) or shared (a look that releases it at once). A shared look by
// another process holds it only for a moment: an exclusive attempt tries a
// few times over some milliseconds before it counts the lock as held.
LockAttempt try_run_lock(int descriptor, bool exclusive, int& error);

// The PID the lock file holds, as written; empty if none yet (its holder
// writes it just after it took the lock).
std::string run_lock_holder(int descriptor);

struct RunLockStatus {
  enum class State {
    absent,   // no lock file: no run has it (or the folder is no run's)
    free,     // the file is there and nobody holds it: its run ended or was killed
    held,     // a live process holds it: its run is still going
    unknown,  // the file cannot be opened or locked here (permissions, a file system without locks)
  };
  State state = State::absent;
  std::string path;  // OUTDIR/.pd-solve.lock
  std::string pid;   // the holder's PID as the file says (held only; may be empty)
};

// Whether a live process holds the lock of `folder`. Takes a shared lock for
// a moment where it is free; never creates the file.
RunLockStatus run_lock_status(const std::string& folder);

}  // namespace pd
