#include "checkpoint.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "atomic_file.hpp"
#include "checksum.hpp"
#include "error.hpp"

namespace pd::solver {
namespace {
constexpr char magic[8] = {'P', 'D', 'C', 'H', 'K', '0', '0', '2'};
constexpr char quasi_static_magic[8] = {'P', 'D', 'Q', 'S', 'C', '0', '0', '2'};

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
  void strings(const std::vector<std::string>& rows) {
    scalar<std::uint64_t>(rows.size());
    for (const auto& row : rows) array(std::vector<char>(row.begin(), row.end()));
  }
  std::uint64_t checksum() const { return checksum_.value(); }

private:
  std::ofstream& out_;
  Checksum checksum_;
};

// A checkpoint file read whole and checked; its payload is data[begin, end).
struct Envelope {
  std::string data;
  std::size_t begin = 0, end = 0;
};

class PayloadReader {
public:
  PayloadReader(const Envelope& envelope, const std::string& path)
      : data_(envelope.data), path_(path), pos_(envelope.begin), end_(envelope.end) {}
  void bytes(void* p, std::size_t n) {
    if (n > end_ - pos_) throw file_error(path_, "checkpoint is truncated");
    std::memcpy(p, data_.data() + pos_, n);
    pos_ += n;
  }
  template <class T> T scalar() { T v; bytes(&v, sizeof v); return v; }
  template <class T> std::vector<T> array() {
    const auto n = scalar<std::uint64_t>();
    if (n > (end_ - pos_) / sizeof(T)) throw file_error(path_, "checkpoint is truncated");
    std::vector<T> v(n);
    bytes(v.data(), n * sizeof(T));
    return v;
  }
  std::vector<std::string> strings() {
    std::vector<std::string> rows(scalar<std::uint64_t>());
    for (auto& row : rows) {
      const auto chars = array<char>();
      row.assign(chars.begin(), chars.end());
    }
    return rows;
  }
  bool at_end() const { return pos_ == end_; }

private:
  const std::string& data_;
  const std::string& path_;
  std::size_t pos_, end_;
};
// Magic, key, the payload that `write_payload` writes, checksum; atomically.
template <class WritePayload>
void write_envelope(const std::string& path, const char* file_magic, const std::string& key,
                    WritePayload write_payload) {
  write_atomically(path, [&](std::ofstream& out) {
    out.write(file_magic, 8);
    const std::uint64_t key_size = key.size();
    out.write(reinterpret_cast<const char*>(&key_size), 8);
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    PayloadWriter w(out);
    write_payload(w);
    const std::uint64_t checksum = w.checksum();
    out.write(reinterpret_cast<const char*>(&checksum), 8);
  });
}

// The checkpoint with this magic and key, checked (the payload is not copied
// out: a large run's restart holds the file once, then its state).
Envelope read_envelope(const std::string& path, const char* file_magic, const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open checkpoint (run without --restart first)");
  Envelope envelope;
  in.seekg(0, std::ios::end);
  envelope.data.resize(static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0)));
  in.seekg(0);
  in.read(envelope.data.data(), static_cast<std::streamsize>(envelope.data.size()));
  if (!in) throw file_error(path, "cannot read checkpoint");
  const std::string& data = envelope.data;
  if (data.size() < 24 || std::memcmp(data.data(), file_magic, 8) != 0) {
    const bool other = data.size() >= 8 && (std::memcmp(data.data(), magic, 8) == 0 ||
                                            std::memcmp(data.data(), quasi_static_magic, 8) == 0);
    // Same kind (first five bytes), other format version (last three).
    const bool older = data.size() >= 8 && std::memcmp(data.data(), file_magic, 5) == 0;
    throw file_error(path, other   ? "checkpoint of the other mode (dynamic / quasi-static)"
                           : older ? "checkpoint format " + data.substr(0, 8) + " of another pd-solve version (this one reads " +
                                         std::string(file_magic, 8) + "); run again without --restart"
                                   : "not a pd-solve checkpoint");
  }
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
  envelope.begin = payload_begin;
  envelope.end = payload_end;
  return envelope;
}
}  // namespace

void write_checkpoint(const std::string& path, const std::string& key, const Checkpoint& c) {
  write_envelope(path, magic, key, [&](PayloadWriter& w) {
    const auto& s = c.state;
    w.scalar<std::int64_t>(s.step);
    w.scalar(s.time);
    w.scalar(s.external_work);
    for (const auto* v : {&s.kinematics.ux, &s.kinematics.uy, &s.kinematics.vx, &s.kinematics.vy, &s.kinematics.fx,
                          &s.kinematics.fy, &s.damage, &s.arrival})
      w.array(*v);
    w.array(s.bond_states);
    w.strings(c.energy_rows);
  });
}

Checkpoint read_checkpoint(const std::string& path, const std::string& key) {
  const Envelope envelope = read_envelope(path, magic, key);
  PayloadReader r(envelope, path);
  Checkpoint c;
  auto& s = c.state;
  s.step = static_cast<long>(r.scalar<std::int64_t>());
  s.time = r.scalar<double>();
  s.external_work = r.scalar<double>();
  for (auto* v : {&s.kinematics.ux, &s.kinematics.uy, &s.kinematics.vx, &s.kinematics.vy, &s.kinematics.fx,
                  &s.kinematics.fy, &s.damage, &s.arrival})
    *v = r.array<double>();
  s.bond_states = r.array<std::uint8_t>();
  c.energy_rows = r.strings();
  if (!r.at_end()) throw file_error(path, "checkpoint has trailing data");
  return c;
}

void write_checkpoint(const std::string& path, const std::string& key, const QuasiStaticCheckpoint& c) {
  write_envelope(path, quasi_static_magic, key, [&](PayloadWriter& w) {
    const auto& s = c.state;
    for (const auto* v : {&s.load_factors_done, &s.u, &s.damage_load_factor}) w.array(*v);
    w.scalar(s.largest_reaction_norm);
    w.scalar(s.largest_axial_reaction);
    w.strings({s.stop_reason});
    w.array(c.bond_states);
    w.strings(c.load_step_rows);
    std::vector<double> factors;
    std::vector<std::string> names;
    for (const auto& [factor, name] : c.snapshots) factors.push_back(factor), names.push_back(name);
    w.array(factors);
    w.strings(names);
  });
}

QuasiStaticCheckpoint read_quasi_static_checkpoint(const std::string& path, const std::string& key) {
  const Envelope envelope = read_envelope(path, quasi_static_magic, key);
  PayloadReader r(envelope, path);
  QuasiStaticCheckpoint c;
  auto& s = c.state;
  for (auto* v : {&s.load_factors_done, &s.u, &s.damage_load_factor}) *v = r.array<double>();
  s.largest_reaction_norm = r.scalar<double>();
  s.largest_axial_reaction = r.scalar<double>();
  const auto stop_reason = r.strings();
  if (stop_reason.size() != 1) throw file_error(path, "checkpoint is corrupt (stop reason)");
  s.stop_reason = stop_reason.front();
  c.bond_states = r.array<std::uint8_t>();
  c.load_step_rows = r.strings();
  const auto factors = r.array<double>();
  const auto names = r.strings();
  if (factors.size() != names.size()) throw file_error(path, "checkpoint is corrupt (snapshot list)");
  for (std::size_t k = 0; k < factors.size(); ++k) c.snapshots.emplace_back(factors[k], names[k]);
  if (!r.at_end()) throw file_error(path, "checkpoint has trailing data");
  return c;
}

}  // namespace pd::solver
