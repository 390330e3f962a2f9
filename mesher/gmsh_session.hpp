#pragma once
// A gmsh session that never ends the process by itself: gmsh's own
// abort-on-error is switched off, its log is captured, and logged errors
// become pd::Error (see docs/mesher.md, "gmsh in practice"). Optionally,
// every gmsh call is bounded in time.
#include <memory>
#include <string>

namespace pd {

class GmshSession {
public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  // Throws pd::Error("FILE: STAGE failed: <gmsh's error lines>") if gmsh
  // logged errors since the last call; clears the log either way.
  void throw_on_logged_errors(const std::string& file, const std::string& stage);

  // Sets the session's options again. A geometry file may change gmsh
  // options (General.AbortOnError, General.NumThreads, ...); this undoes it.
  void restore_options();

  // gmsh cannot be interrupted: a geometry file with a loop of 10^9
  // iterations, or a mesh far too large, would hang the tool. With a limit
  // set, each Deadline below ends the process (status 1, one line on stderr
  // naming the file, the stage and the limit) if gmsh has not returned in
  // time. Nothing has been written then: outputs are written after meshing.
  // `seconds` <= 0: no limit (the default, e.g. inside tests).
  void set_time_limit(double seconds, const std::string& tool, const std::string& option);

  // The longest limit a tool's option accepts [s]: a year. gmsh takes
  // minutes; a larger value is a slip (1e300), and the waits below, in whole
  // nanoseconds or milliseconds, would overflow on it.
  static constexpr double longest_time_limit = 365.0 * 24 * 3600;
  // The shortest limit a tool's option accepts [s]. gmsh's reading of a
  // small geometry, and the start of the free regions' worker, take tens to
  // hundreds of ms as the machine is loaded: below a second, whether a run
  // meshes would depend on the machine's load, not on the geometry.
  static constexpr double shortest_time_limit = 1;

  class Deadline {
  public:
    ~Deadline();
    Deadline(Deadline&&) noexcept;
    Deadline(const Deadline&) = delete;
    Deadline& operator=(const Deadline&) = delete;

    struct Watch;  // defined in the .cpp

  private:
    friend class GmshSession;
    explicit Deadline(std::unique_ptr<Watch> watch);
    std::unique_ptr<Watch> watch_;
  };
  // Starts the clock for one gmsh call: the limit plus `extra_seconds`.
  Deadline deadline(const std::string& file, const std::string& stage, double extra_seconds = 0) const;

private:
  double limit_seconds_ = 0;
  std::string tool_, option_;
};

}  // namespace pd
