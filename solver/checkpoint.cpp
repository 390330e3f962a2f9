#include "checkpoint.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "atomic_file.hpp"
#include "checksum.hpp"
#include "error.hpp"

namespace pd::solver {
namespace {
constexpr char magic[8] = {'P', 'D', 'C', 'H', 'K', '0', '0', '1'};

class PayloadWriter {
public:
  explicit PayloadWriter(std::ofstream& out) : out_(out) {}
  void bytes(const void* p, std::size_t n) {
    out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    checksum_.update(p, n);
  }
  template <class T> void scalar(T v) { bytes(&v, sizeof v); }
  template <class T> void array(const std::vector<T>& v) {
    scalar<std::uint64_t>(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  std::uint64_t checksum() const { return checksum_.value(); }

private:
  std::ofstream& out_;
  Checksum checksum_;
};

class PayloadReader {
public:
  PayloadReader(const std::string& data, const std::string& path) : data_(data), path_(path) {}
  void bytes(void* p, std::size_t n) {
    if (n > data_.size() - pos_) throw file_error(path_, "checkpoint is truncated");
    std::memcpy(p, data_.data() + pos_, n);
    pos_ += n;
  }
  template <class T> T scalar() { T v; bytes(&v, sizeof v); return v; }
  template <class T> std::vector<T> array() {
    const auto n = scalar<std::uint64_t>();
    if (n > (data_.size() - pos_) / sizeof(T)) throw file_error(path_, "checkpoint is truncated");
    std::vector<T> v(n);
    bytes(v.data(), n * sizeof(T));
    return v;
  }
  bool at_end() const { return pos_ == data_.size(); }

private:
  const std::string& data_;
  const std::string& path_;
  std::size_t pos_ = 0;
};
}  // namespace

void write_checkpoint(const std::string& path, const std::string& key, const Checkpoint& c) {
  write_atomically(path, [&](std::ofstream& out) {
    out.write(magic, 8);
    const std::uint64_t key_size = key.size();
    out.write(reinterpret_cast<const char*>(&key_size), 8);
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    PayloadWriter w(out);
    const auto& s = c.state;
    w.scalar<std::int64_t>(s.step);
    w.scalar(s.time);
    w.scalar(s.external_work);
    for (const auto* v : {&s.kinematics.x, &s.kinematics.y, &s.kinematics.vx, &s.kinematics.vy, &s.kinematics.fx,
                          &s.kinematics.fy, &s.damage.damage, &s.arrival})
      w.array(*v);
    w.array(s.damage.intact);
    w.scalar<std::uint64_t>(c.energy_rows.size());
    for (const auto& row : c.energy_rows) w.array(std::vector<char>(row.begin(), row.end()));
    const std::uint64_t checksum = w.checksum();
    out.write(reinterpret_cast<const char*>(&checksum), 8);
  });
}

Checkpoint read_checkpoint(const std::string& path, const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open checkpoint (run without --restart first)");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.size() < 24 || std::memcmp(data.data(), magic, 8) != 0) throw file_error(path, "not a pd-solve checkpoint");
  std::uint64_t key_size = 0;
  std::memcpy(&key_size, data.data() + 8, 8);
  if (key_size > data.size() - 24) throw file_error(path, "checkpoint is truncated");
  if (data.compare(16, key_size, key) != 0)
    throw file_error(path, "checkpoint belongs to a different scene or particle file (settings changed since it was written)");
  const std::size_t payload_begin = 16 + key_size, payload_end = data.size() - 8;
  std::uint64_t stored = 0;
  std::memcpy(&stored, data.data() + payload_end, 8);
  if (checksum_of(data.data() + payload_begin, payload_end - payload_begin) != stored)
    throw file_error(path, "checkpoint checksum mismatch (file corrupted)");
  const std::string payload = data.substr(payload_begin, payload_end - payload_begin);
  PayloadReader r(payload, path);
  Checkpoint c;
  auto& s = c.state;
  s.step = static_cast<long>(r.scalar<std::int64_t>());
  s.time = r.scalar<double>();
  s.external_work = r.scalar<double>();
  for (auto* v : {&s.kinematics.x, &s.kinematics.y, &s.kinematics.vx, &s.kinematics.vy, &s.kinematics.fx,
                  &s.kinematics.fy, &s.damage.damage, &s.arrival})
    *v = r.array<double>();
  s.damage.intact = r.array<std::uint8_t>();
  const auto rows = r.scalar<std::uint64_t>();
  for (std::uint64_t k = 0; k < rows; ++k) {
    const auto chars = r.array<char>();
    c.energy_rows.emplace_back(chars.begin(), chars.end());
  }
  if (!r.at_end()) throw file_error(path, "checkpoint has trailing data");
  return c;
}

}  // namespace pd::solver
