#include "gmsh_session.hpp"

#include <gmsh.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "error.hpp"

namespace pd {

GmshSession::GmshSession() {
  gmsh::initialize(0, nullptr, false);
  restore_options();
  gmsh::logger::start();
}

GmshSession::~GmshSession() {
  try {
    gmsh::logger::stop();
    gmsh::finalize();
  } catch (...) {
  }
}

void GmshSession::restore_options() {
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 2);  // errors and warnings only
  // Default 2 would exit the process on a meshing error, uncatchable.
  gmsh::option::setNumber("General.AbortOnError", 0);
  // One thread: the same input gives the same mesh, byte for byte.
  gmsh::option::setNumber("General.NumThreads", 1);
}

void GmshSession::throw_on_logged_errors(const std::string& file, const std::string& stage) {
  std::vector<std::string> log;
  gmsh::logger::get(log);
  gmsh::logger::stop();
  gmsh::logger::start();  // restarting clears the log
  std::string errors;
  int count = 0;
  for (const auto& line : log)
    if (line.rfind("Error", 0) == 0 && count++ < 5) errors += "\n  gmsh: " + line;
  if (count > 0) throw file_error(file, stage + " failed:" + errors);
}

void GmshSession::set_time_limit(double seconds, const std::string& tool, const std::string& option) {
  limit_seconds_ = seconds;
  tool_ = tool;
  option_ = option;
}

// A watchdog thread that waits for the Deadline to end, or for the time to run out.
struct GmshSession::Deadline::Watch {
  std::mutex mutex;
  std::condition_variable done_signal;
  bool done = false;
  std::thread thread;
};

GmshSession::Deadline::Deadline(std::unique_ptr<Watch> watch) : watch_(std::move(watch)) {}
GmshSession::Deadline::Deadline(Deadline&&) noexcept = default;

GmshSession::Deadline::~Deadline() {
  if (!watch_) return;
  {
    std::lock_guard<std::mutex> lock(watch_->mutex);
    watch_->done = true;
  }
  watch_->done_signal.notify_one();
  watch_->thread.join();
}

GmshSession::Deadline GmshSession::deadline(const std::string& file, const std::string& stage,
                                            double extra_seconds) const {
  if (!(limit_seconds_ > 0)) return Deadline(nullptr);
  auto watch = std::make_unique<Deadline::Watch>();
  const double seconds = limit_seconds_ + std::max(0.0, extra_seconds);
  char limit_text[64], option_text[64];
  std::snprintf(limit_text, sizeof limit_text, "%.3g s", seconds);
  std::snprintf(option_text, sizeof option_text, "%g", limit_seconds_);
  const std::string message = tool_ + ": error: " + file + ": gmsh did not finish " + stage + " within " +
                              limit_text + " (" + option_ + " " + option_text +
                              (extra_seconds > 0 ? " plus an allowance for the mesh size" : "") +
                              "); stopped, nothing was written\n";
  Deadline::Watch* w = watch.get();
  w->thread = std::thread([w, seconds, message] {
    std::unique_lock<std::mutex> lock(w->mutex);
    // In waits of at most the longest limit: the limit plus the allowance for
    // a huge mesh may exceed the steady clock's range in nanoseconds.
    for (double left = seconds; left > 0; left -= GmshSession::longest_time_limit)
      if (w->done_signal.wait_for(lock, std::chrono::duration<double>(std::min(left, GmshSession::longest_time_limit)),
                                  [w] { return w->done; }))
        return;
    // gmsh is still running and cannot be stopped from outside: end the
    // process here, with the message the tool would have printed.
    const ssize_t ignored = ::write(2, message.data(), message.size());
    (void)ignored;
    ::_exit(1);
  });
  return Deadline(std::move(watch));
}

}  // namespace pd
