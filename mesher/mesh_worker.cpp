#include "mesh_worker.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/personality.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "error.hpp"
#include "gmsh_session.hpp"

namespace pd {

namespace {

// gmsh's free meshes depend, in their last bits, on the addresses its
// allocations get (hence address randomisation off in the worker below). The
// worker's allocations before and during the meshing must therefore not
// depend on the geometry file's path, or the same geometry meshes slightly
// differently from different folders: its name travels in a field of a
// fixed size (whole 4 KiB blocks, one for any ordinary path) and is read
// into a string of that capacity.
std::size_t path_field_size(std::size_t length) {
  constexpr std::size_t block = 4096;
  return (length / block + 1) * block;
}

// Plain binary records, native byte order (both ends are this program).
class Writer {
public:
  template <class T>
  void put(const T& v) {
    const auto* b = reinterpret_cast<const char*>(&v);
    bytes.insert(bytes.end(), b, b + sizeof v);
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put<std::uint64_t>(v.size());
    const auto* b = reinterpret_cast<const char*>(v.data());
    bytes.insert(bytes.end(), b, b + sizeof(T) * v.size());
  }
  void put_string(const std::string& s) { put_vector(std::vector<char>(s.begin(), s.end())); }
  // The geometry file's name in a field of path_field_size(s.size()) bytes.
  void put_path(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes.insert(bytes.end(), s.begin(), s.end());
    bytes.insert(bytes.end(), path_field_size(s.size()) - s.size(), '\0');
  }
  std::vector<char> bytes;
};

class Reader {
public:
  explicit Reader(const std::vector<char>& bytes) : bytes_(bytes) {}
  template <class T>
  T get() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<std::uint64_t>();
    if (n > (bytes_.size() - at_) / sizeof(T)) throw std::runtime_error("mesh worker: truncated message");
    std::vector<T> v(n);
    take(v.data(), sizeof(T) * n);
    return v;
  }
  std::string get_string() {
    const auto v = get_vector<char>();
    return std::string(v.begin(), v.end());
  }
  // put_path's field, into a string of the field's capacity: no allocation
  // of a size that depends on the name.
  std::string get_path() {
    const auto n = get<std::uint64_t>();
    const std::size_t field = n < bytes_.size() ? path_field_size(static_cast<std::size_t>(n)) : bytes_.size() + 1;
    if (bytes_.size() - at_ < field) throw std::runtime_error("mesh worker: truncated message");
    std::string path;
    path.reserve(field);
    path.assign(bytes_.data() + at_, static_cast<std::size_t>(n));
    at_ += field;
    return path;
  }

private:
  void take(void* to, std::size_t n) {
    if (bytes_.size() - at_ < n) throw std::runtime_error("mesh worker: truncated message");
    std::memcpy(to, bytes_.data() + at_, n);
    at_ += n;
  }
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

constexpr std::uint32_t request_tag = 0x57444d50;  // "PMDW"

std::vector<char> encode(const std::string& file, const std::vector<RegionShape>& shapes) {
  Writer w;
  w.put(request_tag);
  w.put_path(file);
  w.put<std::uint64_t>(shapes.size());
  for (const auto& shape : shapes) {
    w.put(shape.unit);
    w.put(shape.spacing);
    w.put_vector(shape.vertices);
    w.put<std::uint64_t>(shape.loops.size());
    for (const auto& loop : shape.loops) w.put_vector(loop);
    w.put<std::uint64_t>(shape.curved.size());
    for (const auto& flags : shape.curved) w.put_vector(flags);
    w.put(shape.fine_size);
    w.put(shape.grading_length);
  }
  return std::move(w.bytes);
}

std::vector<char> read_all(int fd) {
  std::vector<char> bytes;
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n > 0) bytes.insert(bytes.end(), buffer, buffer + n);
    else if (n == 0 || errno != EINTR) break;
  }
  return bytes;
}

// gmsh reads two paths into heap strings when it starts: its executable's
// (/proc/self/exe) and the working directory. Their lengths move the
// worker's later allocations, so the same pd-mesh meshed slightly
// differently when installed in another folder or started from one. The
// worker therefore runs in "/" and from a hard link to (or, across file
// systems, a copy of) this program at a path of fixed length,
// /tmp/pd-mesh-XXXXXX/pd-mesh, removed when the worker is done. Where that
// cannot be made (no writable /tmp, or one that forbids running programs)
// the worker runs from the given path: the mesh is as right, just not
// byte-identical across installations.
class FixedLengthCopy {
public:
  explicit FixedLengthCopy(const std::string& executable) {
    char folder[] = "/tmp/pd-mesh-XXXXXX";
    if (!::mkdtemp(folder)) return;
    folder_ = folder;
    path_ = folder_ + "/pd-mesh";
    char target[4096];
    const ssize_t length = ::readlink(executable.c_str(), target, sizeof target - 1);
    const std::string source = length > 0 ? std::string(target, static_cast<std::size_t>(length)) : executable;
    if (::link(source.c_str(), path_.c_str()) != 0 && !copy(source, path_)) path_.clear();
  }
  ~FixedLengthCopy() {
    if (!path_.empty()) ::unlink(path_.c_str());
    if (!folder_.empty()) ::rmdir(folder_.c_str());
  }
  FixedLengthCopy(const FixedLengthCopy&) = delete;
  FixedLengthCopy& operator=(const FixedLengthCopy&) = delete;
  // Empty when there is none.
  const std::string& path() const { return path_; }

private:
  static bool copy(const std::string& from, const std::string& to) {
    const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
    if (in < 0) return false;
    const int out = ::open(to.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0700);
    bool ok = out >= 0;
    char buffer[1 << 16];
    while (ok) {
      const ssize_t n = ::read(in, buffer, sizeof buffer);
      if (n == 0) break;
      if (n < 0) {
        ok = errno == EINTR;
        continue;
      }
      for (ssize_t done = 0; ok && done < n;) {
        const ssize_t w = ::write(out, buffer + done, static_cast<std::size_t>(n - done));
        if (w > 0) done += w;
        else ok = w < 0 && errno == EINTR;
      }
    }
    ::close(in);
    if (out >= 0 && ::close(out) != 0) ok = false;
    if (!ok) ::unlink(to.c_str());
    return ok;
  }
  std::string folder_, path_;
};

bool write_all(int fd, const std::vector<char>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

double meshing_time_limit(double seconds, const std::vector<RegionShape>& shapes) {
  double expected_cells = 0;
  for (const auto& shape : shapes) {
    double twice_area = 0;
    for (const auto& loop : shape.loops)
      for (std::size_t k = 0; k < loop.size(); ++k)
        twice_area += cross(shape.vertices[loop[k]], shape.vertices[loop[(k + 1) % loop.size()]]);
    expected_cells += 0.5 * std::fabs(twice_area) / (shape.smallest_size() * shape.smallest_size());
  }
  return seconds + gmsh_seconds_per_expected_cell * expected_cells;
}

MeshWorker::MeshWorker(std::string executable, double seconds, std::string option)
    : executable_(std::move(executable)), option_(std::move(option)), seconds_(seconds) {}

std::vector<RegionMesh> MeshWorker::mesh(const std::string& file, const std::vector<RegionShape>& shapes) const {
  if (shapes.empty()) return {};
  const FixedLengthCopy fixed(executable_);
  // The worker runs with an empty environment (nothing of the user's shell
  // reaches gmsh), but for the sanitizers' settings of an instrumented build
  // (docs/robustness.md: leak checking off, since gmsh keeps memory until
  // exit), which change no mesh. Made before the fork: the child only execs.
  std::vector<std::string> kept_variables;
  for (const char* name : {"ASAN_OPTIONS", "LSAN_OPTIONS", "UBSAN_OPTIONS"})
    if (const char* value = std::getenv(name)) kept_variables.push_back(std::string(name) + "=" + value);
  std::vector<char*> envp;
  for (auto& variable : kept_variables) envp.push_back(variable.data());
  envp.push_back(nullptr);
  int sockets[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0)
    throw file_error(file, std::string("cannot start the mesh worker: ") + std::strerror(errno));
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(sockets[0]), ::close(sockets[1]);
    throw file_error(file, std::string("cannot start the mesh worker: ") + std::strerror(errno));
  }
  if (child == 0) {
    // In the child only async-signal-safe calls until exec. Address
    // randomisation off where the system allows it (otherwise the mesh is
    // still right, just not always byte-identical).
    const int persona = ::personality(0xffffffff);
    if (persona != -1) ::personality(static_cast<unsigned long>(persona) | ADDR_NO_RANDOMIZE);
    ::dup2(sockets[1], 0);
    ::dup2(sockets[1], 1);
    char name[] = "pd-mesh";
    char argument[64];
    std::strncpy(argument, mesh_worker_argument, sizeof argument - 1);
    argument[sizeof argument - 1] = 0;
    char* argv[] = {name, argument, nullptr};
    if (::chdir("/") != 0) ::_exit(127);
    if (!fixed.path().empty()) ::execve(fixed.path().c_str(), argv, envp.data());
    ::execve(executable_.c_str(), argv, envp.data());
    ::_exit(127);
  }
  ::close(sockets[1]);
  const int fd = sockets[0];
  const auto finish = [&](bool kill_child) {
    if (kill_child) ::kill(child, SIGKILL);
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    ::close(fd);
    return status;
  };
  if (!write_all(fd, encode(file, shapes))) {
    const int status = finish(true);
    throw file_error(file, "the mesh worker did not accept its input (status " + std::to_string(status) + ")");
  }
  ::shutdown(fd, SHUT_WR);

  // Read the answer within the time limit and the allowance for the cells.
  const double limit = meshing_time_limit(seconds_, shapes);
  const auto start = std::chrono::steady_clock::now();
  std::vector<char> answer;
  char buffer[1 << 16];
  while (true) {
    const double left = limit - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    pollfd p{fd, POLLIN, 0};
    // poll's timeout is an int of ms (24.8 days at most): a longer wait
    // polls again until the limit has passed.
    const double wait_ms = std::min(std::ceil(left * 1e3), static_cast<double>(std::numeric_limits<int>::max()));
    const int ready = left > 0 ? ::poll(&p, 1, static_cast<int>(wait_ms)) : 0;
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0 && left * 1e3 > wait_ms) continue;
    if (ready <= 0) {
      finish(true);
      char text[200];
      std::snprintf(text, sizeof text, "gmsh did not finish meshing the free regions within %.3g s (%s %g, plus %g "
                    "ms per expected cell)", limit, option_.c_str(), seconds_, gmsh_seconds_per_expected_cell * 1e3);
      throw file_error(file, text);
    }
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    answer.insert(answer.end(), buffer, buffer + n);
  }
  const int status = finish(false);
  if (WIFSIGNALED(status))
    throw file_error(file, "gmsh crashed (signal " + std::to_string(WTERMSIG(status)) +
                               ") while meshing the free regions");
  try {
    Reader r(answer);
    if (r.get<std::uint8_t>() != 0) throw Error(r.get_string());
    std::vector<RegionMesh> meshes(shapes.size());
    for (auto& mesh : meshes) {
      mesh.nodes = r.get_vector<Vec2>();
      mesh.vertex_of_node = r.get_vector<std::int64_t>();
      mesh.element_offsets = r.get_vector<std::uint32_t>();
      mesh.element_nodes = r.get_vector<std::uint32_t>();
    }
    return meshes;
  } catch (const Error&) {
    throw;
  } catch (const std::exception&) {
    throw file_error(file, "the mesh worker ended without a mesh (exit status " +
                               std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  }
}

int run_mesh_worker() {
  Writer w;
  try {
    const auto request = read_all(0);
    Reader r(request);
    if (r.get<std::uint32_t>() != request_tag) throw Error("mesh worker: not a mesh request");
    const std::string file = r.get_path();
    const auto count = r.get<std::uint64_t>();
    GmshSession session;
    w.put<std::uint8_t>(0);
    for (std::uint64_t k = 0; k < count; ++k) {
      RegionShape shape;
      shape.unit = r.get<double>();
      shape.spacing = r.get<double>();
      shape.vertices = r.get_vector<Vec2>();
      const auto loops = r.get<std::uint64_t>();
      for (std::uint64_t l = 0; l < loops; ++l) shape.loops.push_back(r.get_vector<std::uint32_t>());
      const auto flagged = r.get<std::uint64_t>();
      for (std::uint64_t l = 0; l < flagged; ++l) shape.curved.push_back(r.get_vector<std::uint8_t>());
      shape.fine_size = r.get<double>();
      shape.grading_length = r.get<double>();
      const RegionMesh mesh = mesh_region(session, file, shape);
      w.put_vector(mesh.nodes);
      w.put_vector(mesh.vertex_of_node);
      w.put_vector(mesh.element_offsets);
      w.put_vector(mesh.element_nodes);
    }
  } catch (const std::exception& e) {
    w.bytes.clear();
    w.put<std::uint8_t>(1);
    w.put_string(e.what());
  }
  std::size_t done = 0;
  while (done < w.bytes.size()) {
    const ssize_t n = ::write(1, w.bytes.data() + done, w.bytes.size() - done);
    if (n <= 0) return 1;
    done += static_cast<std::size_t>(n);
  }
  return 0;
}

}  // namespace pd
