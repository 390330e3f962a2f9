#pragma once
// One exception type for every user-facing failure. The message is printed
// as-is by the tools, so it must name the file, key and value involved.
#include <stdexcept>
#include <string>

namespace pd {

class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Error about a specific file: "FILE: message".
inline Error file_error(const std::string& file, const std::string& message) {
  return Error(file + ": " + message);
}

}  // namespace pd
