#pragma once
// The one binary encoding of the tools' own files (particle file, checkpoint,
// surface-correction cache; docs/formats.md): fixed-width little-endian
// scalars and arrays of them, written and read through a running checksum
// (checksum.hpp). Reads are bounds-checked against the bytes the caller says
// are there, before anything is allocated, and a short read throws pd::Error
// naming the file and what was being read.
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <type_traits>
#include <vector>

#include "checksum.hpp"

namespace pd {

// Values are copied as they are in memory: the formats are little-endian and
// so is every supported host; a big-endian build must not compile silently.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the binary formats are little-endian");

class BinaryWriter {
public:
  explicit BinaryWriter(std::ostream& out) : out_(out) {}

  void bytes(const void* p, std::size_t n);
  template <class T> void scalar(T v) {
    static_assert(std::is_trivially_copyable<T>::value, "fixed-width values only");
    bytes(&v, sizeof v);
  }
  // The elements only (the count is known from elsewhere, e.g. a header).
  template <class T> void values(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable<T>::value, "fixed-width values only");
    bytes(v.data(), v.size() * sizeof(T));
  }
  // A uint64 count, then the elements.
  template <class T> void counted(const std::vector<T>& v) {
    scalar<std::uint64_t>(v.size());
    values(v);
  }
  // A uint64 count, then each string as a counted array of chars.
  void counted_strings(const std::vector<std::string>& rows);

  std::uint64_t count() const { return count_; }  // bytes written so far
  std::uint64_t checksum() const { return checksum_.value(); }

private:
  std::ostream& out_;
  Checksum checksum_;
  std::uint64_t count_ = 0;
};

class BinaryReader {
public:
  // The next `size` bytes of `in`, read as they are needed (no copy of a
  // file that may be hundreds of MB).
  BinaryReader(std::istream& in, std::uint64_t size, std::string path);
  // The bytes data[0, size) of a buffer that outlives the reader.
  BinaryReader(const char* data, std::uint64_t size, std::string path);

  void bytes(void* p, std::uint64_t n, const char* what);
  template <class T> T scalar(const char* what) {
    static_assert(std::is_trivially_copyable<T>::value, "fixed-width values only");
    if (sizeof(T) > remaining_) truncated(what, sizeof(T));
    T v;
    bytes(&v, sizeof v, what);
    return v;
  }
  // `n` elements into `v`; the room for them is checked before `v` grows.
  template <class T> void values(std::vector<T>& v, std::uint64_t n, const char* what) {
    require_room(n, sizeof(T), 0, what);
    v.resize(static_cast<std::size_t>(n));
    bytes(v.data(), n * sizeof(T), what);
  }
  // The next `n` elements of a section into `destination` (a chunk of a
  // section too large to hold at once).
  template <class T> void elements(T* destination, std::uint64_t n, const char* what) {
    static_assert(std::is_trivially_copyable<T>::value, "fixed-width values only");
    require_room(n, sizeof(T), 0, what);
    bytes(destination, n * sizeof(T), what);
  }
  // A uint64 count, then the elements (BinaryWriter::counted).
  template <class T> std::vector<T> counted(const char* what) {
    std::vector<T> v;
    values(v, scalar<std::uint64_t>(what), what);
    return v;
  }
  std::string string(std::uint64_t n, const char* what);
  std::vector<std::string> counted_strings(const char* what);  // BinaryWriter::counted_strings

  // Throws unless `n` elements of `element_bytes` each fit after the next
  // `skipped` bytes (which must fit themselves).
  void require_room(std::uint64_t n, std::size_t element_bytes, std::uint64_t skipped, const char* what) const;

  std::uint64_t position() const { return size_ - remaining_; }  // bytes read so far
  std::uint64_t remaining() const { return remaining_; }
  // After a read that ran past the end (its pd::Error): what it read and
  // where its bytes would have ended (from the start; at most 2^64 - 1), so
  // that a file cut short can say how long it should be.
  struct ShortRead {
    std::string what;
    std::uint64_t end = 0;
  };
  const ShortRead& short_read() const { return short_read_; }
  std::uint64_t checksum() const { return checksum_.value(); }  // of the bytes read so far
  const std::string& path() const { return path_; }

private:
  // `wanted`: the bytes the read needed from position().
  [[noreturn]] void truncated(const char* what, std::uint64_t wanted) const;

  std::istream* in_ = nullptr;
  const char* data_ = nullptr;
  std::uint64_t size_, remaining_;
  std::string path_;
  Checksum checksum_;
  mutable ShortRead short_read_;
};

// The layout the checkpoint and the surface-correction cache share: an
// 8-byte magic, the key (uint64 length, bytes) that says what the file
// belongs to, the payload `write` writes, and the payload's checksum (uint64).
void write_keyed_payload(std::ostream& out, const char* magic, const std::string& key,
                         const std::function<void(BinaryWriter&)>& write);

}  // namespace pd
