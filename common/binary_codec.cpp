#include "binary_codec.hpp"

#include <cstring>
#include <limits>
#include <istream>
#include <ostream>
#include <utility>

#include "error.hpp"

namespace pd {

void BinaryWriter::bytes(const void* p, std::size_t n) {
  out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
  checksum_.update(p, n);
  count_ += n;
}

void BinaryWriter::counted_strings(const std::vector<std::string>& rows) {
  scalar<std::uint64_t>(rows.size());
  for (const auto& row : rows) {
    scalar<std::uint64_t>(row.size());
    bytes(row.data(), row.size());
  }
}

BinaryReader::BinaryReader(std::istream& in, std::uint64_t size, std::string path)
    : in_(&in), size_(size), remaining_(size), path_(std::move(path)) {}

BinaryReader::BinaryReader(const char* data, std::uint64_t size, std::string path)
    : data_(data), size_(size), remaining_(size), path_(std::move(path)) {}

void BinaryReader::truncated(const char* what, std::uint64_t wanted) const {
  const std::uint64_t most = std::numeric_limits<std::uint64_t>::max();
  short_read_ = {what, wanted > most - position() ? most : position() + wanted};
  throw file_error(path_, std::string("truncated while reading ") + what);
}

void BinaryReader::require_room(std::uint64_t n, std::size_t element_bytes, std::uint64_t skipped,
                                const char* what) const {
  if (skipped > remaining_ || n > (remaining_ - skipped) / element_bytes) {
    const std::uint64_t most = std::numeric_limits<std::uint64_t>::max();
    const std::uint64_t wanted = n > (most - skipped) / element_bytes ? most : skipped + n * element_bytes;
    short_read_ = {what, wanted > most - position() ? most : position() + wanted};
    throw file_error(path_, std::string("truncated or inconsistent counts while reading ") + what);
  }
}

void BinaryReader::bytes(void* p, std::uint64_t n, const char* what) {
  if (n > remaining_) truncated(what, n);
  if (n == 0) return;  // an empty array may have a null data pointer
  if (in_) {
    in_->read(static_cast<char*>(p), static_cast<std::streamsize>(n));
    if (static_cast<std::uint64_t>(in_->gcount()) != n) truncated(what, n);
  } else {
    std::memcpy(p, data_ + position(), static_cast<std::size_t>(n));
  }
  checksum_.update(p, static_cast<std::size_t>(n));
  remaining_ -= n;
}

std::string BinaryReader::string(std::uint64_t n, const char* what) {
  if (n > remaining_) truncated(what, n);
  std::string s(static_cast<std::size_t>(n), '\0');
  bytes(s.data(), n, what);
  return s;
}

std::vector<std::string> BinaryReader::counted_strings(const char* what) {
  const auto count = scalar<std::uint64_t>(what);
  // Each string takes at least its 8-byte length.
  require_room(count, sizeof(std::uint64_t), 0, what);
  std::vector<std::string> rows(static_cast<std::size_t>(count));
  for (auto& row : rows) row = string(scalar<std::uint64_t>(what), what);
  return rows;
}

void write_keyed_payload(std::ostream& out, const char* magic, const std::string& key,
                         const std::function<void(BinaryWriter&)>& write) {
  BinaryWriter head(out);  // outside the payload checksum
  head.bytes(magic, 8);
  head.scalar<std::uint64_t>(key.size());
  head.bytes(key.data(), key.size());
  BinaryWriter payload(out);
  write(payload);
  BinaryWriter(out).scalar<std::uint64_t>(payload.checksum());
}

}  // namespace pd
