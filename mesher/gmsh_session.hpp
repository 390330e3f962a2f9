#pragma once
// A gmsh session that never ends the process: gmsh's own abort-on-error is
// switched off, its log is captured, and logged errors become pd::Error
// (see docs/mesher.md, "gmsh in practice").
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
};

}  // namespace pd
