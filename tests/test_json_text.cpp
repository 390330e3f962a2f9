// JSON strings and numbers of the tools' summaries and provenance (common/json_text):
// UTF-8 JSON text whatever bytes a path holds (RFC 8259, RFC 3629).
#include <catch2/catch.hpp>

#include <cstdlib>
#include <limits>

#include "json_text.hpp"

TEST_CASE("a JSON string escapes quotes, backslashes and control characters", "[json]") {
  CHECK(pd::json_string("") == "\"\"");
  CHECK(pd::json_string("run/out 1") == "\"run/out 1\"");
  CHECK(pd::json_string("a\"b\\c") == "\"a\\\"b\\\\c\"");
  CHECK(pd::json_string("a\nb\tc") == "\"a\\nb\\tc\"");
  CHECK(pd::json_string(std::string("a\0b\x01\x1f\x7f", 6)) == "\"a\\u0000b\\u0001\\u001f\\u007f\"");
}

TEST_CASE("a JSON string keeps UTF-8 and writes a byte of another encoding as U+FFFD", "[json]") {
  // Two-, three- and four-byte characters (é, €, U+1F600) as they are.
  CHECK(pd::json_string("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80") == "\"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\"");
  // é in Latin-1 (0xE9) before 'c' and at the end, a sequence cut short.
  CHECK(pd::json_string("out\tA\xe9" "c") == "\"out\\tA\\ufffdc\"");
  CHECK(pd::json_string("A\xe9") == "\"A\\ufffd\"");
  CHECK(pd::json_string("\xe2\x82") == "\"\\ufffd\\ufffd\"");
  // Not UTF-8 though of its shape: an overlong '/', a surrogate, above U+10FFFF, a lone continuation byte.
  CHECK(pd::json_string("\xc0\xaf") == "\"\\ufffd\\ufffd\"");
  CHECK(pd::json_string("\xed\xa0\x80") == "\"\\ufffd\\ufffd\\ufffd\"");
  CHECK(pd::json_string("\xf4\x90\x80\x80") == "\"\\ufffd\\ufffd\\ufffd\\ufffd\"");
  CHECK(pd::json_string("\x80") == "\"\\ufffd\"");
}

// One number writer for the three tools' JSON (pd-solve's summary.json had 12
// digits, pd-post's 9 and pd-mesh's provenance 17 before 7 December 2026):
// the shortest text that reads back to the double.
TEST_CASE("a JSON number is the shortest text that reads back to the double, null if not finite", "[json]") {
  CHECK(pd::json_number(0.1) == "0.1");
  CHECK(pd::json_number(0.1 + 0.2) == "0.30000000000000004");
  CHECK(pd::json_number(0.12345670000001) == "0.12345670000001");
  CHECK(pd::json_number(1234.5678901) == "1234.5678901");  // 9 digits would cut it to 1234.56789
  CHECK(pd::json_number(5e-4) == "0.0005");                // 17 digits wrote 0.00050000000000000001
  CHECK(pd::json_number(3) == "3");
  CHECK(pd::json_number(3.24e9) == "3240000000");  // whole numbers in full, as 12 digits wrote them
  CHECK(pd::json_number(-4e15) == "-4000000000000000");
  CHECK(pd::json_number(1e16) == "1e+16");
  CHECK(pd::json_number(-2.5e-9) == "-2.5e-09");
  CHECK(pd::json_number(-0.0) == "0");
  CHECK(pd::json_number(std::numeric_limits<double>::quiet_NaN()) == "null");
  CHECK(pd::json_number(-std::numeric_limits<double>::infinity()) == "null");
  for (double v : {1.0 / 3, 2.0 / 3, 1e-300, 6.02214076e23, 0.019999999999999348})
    CHECK(std::strtod(pd::json_number(v).c_str(), nullptr) == v);
}
