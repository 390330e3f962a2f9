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
    if (slots_.empty()) return nullptr;
    const std::uint64_t h = hash(key);
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = h & mask;; s = (s + 1) & mask) {
      const std::uint64_t slot = slots_[s];
      if (slot == 0) return nullptr;
      const Entry& e = entries_[(slot & 0xffffffffu) - 1];
      if ((slot >> 32) == (h >> 32) && same_bits(e.key, key)) return &e.value;
    }
  }
  void add(const Found& found) {
    for (const auto& [key, value] : found) {
      if (entries_.size() >= capacity) return;
      if (find(key)) continue;  // found twice (by two threads, or two bonds of one loop)
      if (2 * (entries_.size() + 1) > slots_.size()) grow();
      entries_.push_back({key, value});
      place(hash(key), entries_.size());
    }
  }
  std::size_t size() const { return entries_.size(); }
  // Bounds the memory (about 100 bytes an entry); later values are computed.
  static constexpr std::size_t capacity = std::size_t{1} << 20;

private:
  // An open-addressed table (linear probing, at most half full) of indices
  // into the entries, each slot (the hash's upper half << 32) | (index + 1),
  // 0 for empty: a look-up reads one slot and, when the upper halves agree,
  // one entry, where a node-based map's chases a bucket, a node before and
  // the node, and divides by a prime.
  struct Entry {
    Key key;
    double value;
  };
  static std::uint64_t hash(const Key& k) {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (double v : k) {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h = (h ^ bits) * 0x100000001b3ull;
      h ^= h >> 29;
    }
    // Every bit into the low ones that pick the slot (splitmix64's finaliser).
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return h ^ (h >> 31);
  }
  // Bitwise: -0.0 and 0.0 are different inputs of atan2.
  static bool same_bits(const Key& a, const Key& b) { return std::memcmp(a.data(), b.data(), sizeof(Key)) == 0; }
  void place(std::uint64_t h, std::size_t index_plus_one) {
    const std::size_t mask = slots_.size() - 1;
    std::size_t s = h & mask;
    while (slots_[s] != 0) s = (s + 1) & mask;
    slots_[s] = (h >> 32 << 32) | index_plus_one;
  }
  void grow() {
    slots_.assign(slots_.empty() ? 1024 : 2 * slots_.size(), 0);
    for (std::size_t e = 0; e < entries_.size(); ++e) place(hash(entries_[e].key), e + 1);
  }
  std::vector<std::uint64_t> slots_;  // a power of two of them
  std::vector<Entry> entries_;        // in the order added
};

}  // namespace pd
