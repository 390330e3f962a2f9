// JSON strings of the tools' summaries and provenance (common/json_text):
// UTF-8 JSON text whatever bytes a path holds (RFC 8259, RFC 3629).
#include <catch2/catch.hpp>

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
