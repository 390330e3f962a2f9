#pragma once
// 64-bit checksum of the particle-file payload (docs/formats.md, "Checksum").
// FNV-1a applied to 8-byte little-endian words instead of bytes: one multiply
// per 8 bytes, fast enough for files of hundreds of MB, and it detects any
// single-byte change and any truncation. Not a cryptographic hash.
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace pd {

class Checksum {
public:
  void update(const void* data, std::size_t bytes) {
    if (bytes == 0) return;  // an empty array may have a null data pointer, which memcpy must not get
    const auto* p = static_cast<const unsigned char*>(data);
    total_ += bytes;
    // Complete a pending partial word first.
    while (pending_size_ > 0 && pending_size_ < 8 && bytes > 0) {
      pending_[pending_size_++] = *p++;
      --bytes;
      if (pending_size_ == 8) {
        mix(load(pending_));
        pending_size_ = 0;
      }
    }
    while (bytes >= 8) {
      mix(load(p));
      p += 8;
      bytes -= 8;
    }
    // Here either pending_size_ == 0 or bytes == 0, and bytes < 8.
    std::memcpy(pending_ + pending_size_, p, bytes);
    pending_size_ += bytes;
  }

  std::uint64_t value() const {
    std::uint64_t h = hash_;
    if (pending_size_ > 0) {
      unsigned char last[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      std::memcpy(last, pending_, pending_size_);
      h = (h ^ load(last)) * prime;
    }
    return (h ^ total_) * prime;
  }

private:
  static constexpr std::uint64_t prime = 0x100000001b3ULL;
  static std::uint64_t load(const unsigned char* p) {
    std::uint64_t w;
    std::memcpy(&w, p, 8);  // the format is little-endian; so is every supported host
    return w;
  }
  void mix(std::uint64_t w) { hash_ = (hash_ ^ w) * prime; }

  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
  std::uint64_t total_ = 0;
  unsigned char pending_[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t pending_size_ = 0;
};

inline std::uint64_t checksum_of(const void* data, std::size_t bytes) {
  Checksum c;
  c.update(data, bytes);
  return c.value();
}

}  // namespace pd
