#pragma once
// Atomic output: write to "<path>.tmp.<pid>", then rename onto <path>.
// A crash or a kill leaves at most a temporary file, never a truncated
// result under the final name.
#include <fstream>
#include <functional>
#include <string>

namespace pd {

// Calls `write` with a binary output stream on a temporary file next to
// `path`, checks the stream, flushes to disk and renames. On any failure the
// temporary file is removed and pd::Error names `path`.
void write_atomically(const std::string& path, const std::function<void(std::ofstream&)>& write);

// Same for writers that want a file name (e.g. VTK writers): `write` must
// create the file at the given temporary path.
void write_atomically_via(const std::string& path,
                          const std::function<void(const std::string& temporary_path)>& write);

// Hash of a file's bytes (the particle-file checksum function), for provenance.
std::string file_hash_hex(const std::string& path);

}  // namespace pd
