// The binary codec of the tools' own files (common/binary_codec.hpp).
// Reference: docs/formats.md — fixed-width little-endian values, counts as
// uint64, strings as counted chars, the keyed layout (magic, key length, key,
// payload, checksum) and the checksum of docs/formats.md, "Checksum".
#include <catch2/catch.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "binary_codec.hpp"
#include "checksum.hpp"
#include "error.hpp"

using Catch::Matchers::Contains;

namespace {
std::string encode(const std::function<void(pd::BinaryWriter&)>& write) {
  std::ostringstream out(std::ios::binary);
  pd::BinaryWriter w(out);
  write(w);
  return out.str();
}
}  // namespace

TEST_CASE("values are written little-endian, counts as uint64, strings as counted chars", "[binary-codec]") {
  const std::string bytes = encode([](pd::BinaryWriter& w) {
    w.scalar<std::uint32_t>(0x01020304u);
    w.counted(std::vector<std::uint16_t>{0x0a0b});
    w.counted_strings({"ab"});
  });
  const std::string expected("\x04\x03\x02\x01"                  // uint32
                             "\x01\0\0\0\0\0\0\0" "\x0b\x0a"      // count 1, uint16
                             "\x01\0\0\0\0\0\0\0"                 // one string
                             "\x02\0\0\0\0\0\0\0" "ab",           // of 2 chars
                             4 + 8 + 2 + 8 + 8 + 2);
  CHECK(bytes == expected);
}

TEST_CASE("what is written is read back, from a stream and from memory", "[binary-codec]") {
  const std::vector<double> doubles{1.5, -0.0, std::numeric_limits<double>::denorm_min(), 1e300};
  const std::vector<std::string> rows{"", "time_s,step", std::string("a\0b", 3)};
  std::uint64_t written_checksum = 0;
  const std::string bytes = encode([&](pd::BinaryWriter& w) {
    w.scalar<std::int64_t>(-7);
    w.values(doubles);
    w.counted(std::vector<std::uint8_t>{1, 0, 1});
    w.counted_strings(rows);
    CHECK(w.count() == 8 + 4 * 8 + 8 + 3 + 8 + (8 + 0) + (8 + 11) + (8 + 3));
    written_checksum = w.checksum();
  });
  CHECK(written_checksum == pd::checksum_of(bytes.data(), bytes.size()));
  const auto check = [&](pd::BinaryReader& r) {
    CHECK(r.scalar<std::int64_t>("step") == -7);
    std::vector<double> d;
    r.values(d, doubles.size(), "doubles");
    CHECK(d == doubles);
    CHECK(r.counted<std::uint8_t>("flags") == std::vector<std::uint8_t>{1, 0, 1});
    CHECK(r.counted_strings("rows") == rows);
    CHECK(r.remaining() == 0);
    CHECK(r.position() == bytes.size());
    CHECK(r.checksum() == written_checksum);
  };
  std::istringstream in(bytes, std::ios::binary);
  pd::BinaryReader from_stream(in, bytes.size(), "stream.bin");
  check(from_stream);
  pd::BinaryReader from_memory(bytes.data(), bytes.size(), "memory.bin");
  check(from_memory);
}

TEST_CASE("a short or inconsistent input throws, naming the file and what was being read", "[binary-codec]") {
  const std::string bytes = encode([](pd::BinaryWriter& w) {
    w.counted(std::vector<double>{1, 2, 3});
    w.counted_strings({"row"});
  });
  SECTION("cut inside an array") {
    pd::BinaryReader r(bytes.data(), 8 + 2 * 8, "cut.bin");
    CHECK_THROWS_MATCHES(r.counted<double>("ux"), pd::Error,
                         Catch::Matchers::Message("cut.bin: truncated or inconsistent counts while reading ux"));
  }
  SECTION("cut inside a scalar") {
    pd::BinaryReader r(bytes.data(), 5, "cut.bin");
    CHECK_THROWS_WITH(r.scalar<std::uint64_t>("step"), Contains("cut.bin") && Contains("truncated while reading step"));
  }
  SECTION("the stream has fewer bytes than announced") {
    std::istringstream in(bytes.substr(0, 20), std::ios::binary);
    pd::BinaryReader r(in, bytes.size(), "short.bin");
    CHECK_THROWS_WITH(r.counted<double>("damage"), Contains("short.bin: truncated while reading damage"));
  }
  SECTION("a count larger than the input is refused before anything is allocated") {
    const std::string huge = encode([](pd::BinaryWriter& w) { w.scalar<std::uint64_t>(std::uint64_t(1) << 60); });
    pd::BinaryReader r(huge.data(), huge.size(), "huge.bin");
    CHECK_THROWS_WITH(r.counted<double>("velocities"), Contains("huge.bin") && Contains("velocities"));
    pd::BinaryReader s(huge.data(), huge.size(), "huge.bin");
    CHECK_THROWS_WITH(s.counted_strings("energy rows"), Contains("huge.bin") && Contains("energy rows"));
  }
  SECTION("the whole input reads") {
    pd::BinaryReader r(bytes.data(), bytes.size(), "whole.bin");
    CHECK(r.counted<double>("x").size() == 3);
    CHECK(r.counted_strings("rows") == std::vector<std::string>{"row"});
  }
}

TEST_CASE("the keyed layout: magic, key, payload, payload checksum", "[binary-codec]") {
  std::ostringstream out(std::ios::binary);
  pd::write_keyed_payload(out, "PDTEST01", "key", [](pd::BinaryWriter& w) { w.scalar<std::uint32_t>(5); });
  const std::string bytes = out.str();
  REQUIRE(bytes.size() == 8 + 8 + 3 + 4 + 8);
  CHECK(bytes.substr(0, 8) == "PDTEST01");
  CHECK(bytes.substr(8, 8) == std::string("\x03\0\0\0\0\0\0\0", 8));
  CHECK(bytes.substr(16, 3) == "key");
  CHECK(bytes.substr(19, 4) == std::string("\x05\0\0\0", 4));
  const std::uint32_t payload = 5;
  pd::BinaryReader r(bytes.data() + 23, 8, "keyed.bin");
  CHECK(r.scalar<std::uint64_t>("checksum") == pd::checksum_of(&payload, 4));
}
