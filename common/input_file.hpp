#pragma once
// A text file a user names as input (a scene, a geometry, a pore or box
// list): a regular file, or a clear error. A device or a FIFO would be read
// without end (/dev/zero grew a tool to gigabytes in seconds) or block.
#include <filesystem>
#include <string>

#include "error.hpp"

namespace pd {

// pd::Error "PATH: a device, not a file (WHAT)" (a folder, a FIFO, a socket)
// unless `path` names a regular file (or a link to one); a missing path is
// left to the reader, which says so in its own words.
inline void require_regular_input(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status) || fs::is_regular_file(status)) return;
  const char* kind = fs::is_directory(status)       ? "a folder"
                     : fs::is_fifo(status)          ? "a FIFO"
                     : fs::is_socket(status)        ? "a socket"
                     : fs::is_character_file(status) || fs::is_block_file(status) ? "a device"
                                                                                    : "not a regular file";
  throw file_error(clipped(path), std::string(kind) + ", not a file (" + what + ")");
}

}  // namespace pd
