#include "gmsh_session.hpp"

#include <gmsh.h>

#include <vector>

#include "error.hpp"

namespace pd {

GmshSession::GmshSession() {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 2);  // errors and warnings only
  // Default 2 would exit the process on a meshing error, uncatchable.
  gmsh::option::setNumber("General.AbortOnError", 0);
  // One thread: the same input gives the same mesh, byte for byte.
  gmsh::option::setNumber("General.NumThreads", 1);
  gmsh::logger::start();
}

GmshSession::~GmshSession() {
  try {
    gmsh::logger::stop();
    gmsh::finalize();
  } catch (...) {
  }
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

}  // namespace pd
