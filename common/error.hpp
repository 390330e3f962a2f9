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

// A long key or value quoted in a message: its start and its length, so that
// a 100 kB key (a pasted file, a runaway script) still gives a one-line error.
inline std::string clipped(std::string text) {
  constexpr std::size_t shown = 80;
  if (text.size() <= 2 * shown) return text;
  const std::size_t length = text.size();
  text.resize(shown);
  return text + "... (" + std::to_string(length) + " characters)";
}

// Error about a specific file: "FILE: message".
inline Error file_error(const std::string& file, const std::string& message) {
  return Error(file + ": " + message);
}

}  // namespace pd
