#pragma once
// Integrals over a four-vertex cell ∩ a disk (the distance moment of
// bond_weights.hpp, the partial area of families.hpp), kept for the later
// set-ups and splits of a run (adaptive refinement, theory.md Sec. 8.4): a
// refined plate has few distinct cells at few distinct offsets from the
// centres that bond to them, so the same integral recurs across particles
// and events. The key is everything the polygon functions read (the vertices
// relative to the centre as they form them, bit for bit, and the radius), so
// a remembered value equals the computed one bit for bit, whatever set or
// event asks for it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry.hpp"

namespace pd {

class CellDiskMemo {
public:
  using Key = std::array<double, 9>;  // 4 vertices relative to the centre (x, y), radius
  // Values computed while the memo is only read (inside a parallel loop),
  // added after it (`add`): a value is a function of its key alone, so the
  // order of adding changes nothing.
  using Found = std::vector<std::pair<Key, double>>;

  static Key key(const double* vx, const double* vy, Vec2 center, double radius) {
    return {vx[0] - center.x, vy[0] - center.y, vx[1] - center.x, vy[1] - center.y,
            vx[2] - center.x, vy[2] - center.y, vx[3] - center.x, vy[3] - center.y, radius};
  }
  const double* find(const Key& key) const {
    const auto it = values_.find(key);
    return it == values_.end() ? nullptr : &it->second;
  }
  void add(const Found& found) {
    for (const auto& [key, value] : found)
      if (values_.size() < capacity) values_.emplace(key, value);
  }
  std::size_t size() const { return values_.size(); }
  // Bounds the memory (about 100 bytes an entry); later values are computed.
  static constexpr std::size_t capacity = std::size_t{1} << 20;

private:
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (double v : k) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        h = (h ^ bits) * 0x100000001b3ull;
        h ^= h >> 29;
      }
      return static_cast<std::size_t>(h);
    }
  };
  struct KeyBits {  // bitwise: -0.0 and 0.0 are different inputs of atan2
    bool operator()(const Key& a, const Key& b) const { return std::memcmp(a.data(), b.data(), sizeof(Key)) == 0; }
  };
  std::unordered_map<Key, double, KeyHash, KeyBits> values_;
};

}  // namespace pd
