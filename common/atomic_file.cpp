#include "atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "checksum.hpp"
#include "error.hpp"

namespace pd {
namespace {
std::string temporary_name(const std::string& path) {
  return path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
}

void sync_file(const std::string& path) {
  if (FILE* f = std::fopen(path.c_str(), "rb+")) {
    ::fsync(::fileno(f));
    std::fclose(f);
  }
}

void rename_or_throw(const std::string& from, const std::string& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(from.c_str());
    throw file_error(to, "cannot move finished file into place: " + why);
  }
}
}  // namespace

void write_atomically(const std::string& path, const std::function<void(std::ofstream&)>& write) {
  const std::string tmp = temporary_name(path);
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) throw file_error(path, std::string("cannot open for writing: ") + std::strerror(errno));
      write(out);
      out.flush();
      if (!out) throw file_error(path, "write failed (disk full?)");
    }
    sync_file(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  rename_or_throw(tmp, path);
}

void write_atomically_via(const std::string& path,
                          const std::function<void(const std::string&)>& write) {
  // Keep the extension last: some writers (VTK) look at it.
  const std::filesystem::path p(path);
  const std::string tmp = (p.parent_path() / (".tmp." + std::to_string(::getpid()) + "." +
                                               p.filename().string())).string();
  try {
    write(tmp);
    if (!std::filesystem::exists(tmp)) throw file_error(path, "writer produced no file");
    sync_file(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  rename_or_throw(tmp, path);
}

std::string file_hash_hex(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open for reading");
  Checksum c;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    c.update(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(c.value()));
  return hex;
}

}  // namespace pd
