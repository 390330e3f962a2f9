#pragma once
// The common frame of the three command-line tools: every failure becomes one
// line on stderr ("pd-mesh: error: ...") and exit status 1.
#include <exception>
#include <iostream>
#include <string>

#include "error.hpp"

namespace pd {

template <class Body>
int run_tool(const char* tool, Body&& body) {
  try {
    return body();
  } catch (const Error& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace pd
