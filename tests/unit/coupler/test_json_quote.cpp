// JSON string literals of summary.json (coflow/output.hpp json_quote): the
// escapes of RFC 8259 §7, and UTF-8 text only (§8.1): well-formed sequences
// pass unchanged, every byte that starts no well-formed sequence becomes
// U+FFFD (a Latin-1 path in a failure reason wrote invalid JSON before).
#include <catch2/catch.hpp>
#include <string>

#include "coflow/output.hpp"

using coflow::output::json_quote;

TEST_CASE("json_quote escapes quotes, backslashes and control characters", "[json]") {
  CHECK(json_quote("a\"b\\c") == "\"a\\\"b\\\\c\"");
  CHECK(json_quote("x\ny\tz") == "\"x\\ny\\tz\"");
  CHECK(json_quote(std::string("\x01\x1f", 2)) == "\"\\u0001\\u001f\"");
  CHECK(json_quote(std::string("a\0b", 3)) == "\"a\\u0000b\"");
  CHECK(json_quote("") == "\"\"");
}

TEST_CASE("json_quote keeps well-formed UTF-8", "[json]") {
  // Each sequence's smallest and largest lead bytes and second bytes (RFC 3629
  // table 3.7): U+0080, U+0800, U+D7FF, U+E000, U+10000, U+10FFFF, U+FFFD.
  for (const char* s :
       {"caf\xc3\xa9", "\xc2\x80", "\xe0\xa0\x80", "\xe2\x82\xac 5", "\xed\x9f\xbf", "\xee\x80\x80",
        "\xf0\x90\x80\x80", "\xf0\x9f\x98\x80", "\xf4\x8f\xbf\xbf", "\xef\xbf\xbd"}) {
    std::string quoted = "\"";
    quoted += s;
    quoted += '"';
    CHECK(json_quote(s) == quoted);
  }
}

TEST_CASE("json_quote replaces bytes that start no well-formed UTF-8 sequence", "[json]") {
  // A Latin-1 e-acute, a lone continuation byte, a truncated sequence at the
  // end, overlong forms, a surrogate, a code point past U+10FFFF, 0xff.
  CHECK(json_quote("caf\xe9/run") == "\"caf\\ufffd/run\"");
  CHECK(json_quote("\x80") == "\"\\ufffd\"");
  CHECK(json_quote("ab\xe2\x82") == "\"ab\\ufffd\\ufffd\"");
  CHECK(json_quote("\xc0\xaf") == "\"\\ufffd\\ufffd\"");
  CHECK(json_quote("\xc1\xbf") == "\"\\ufffd\\ufffd\"");
  CHECK(json_quote("\xf5\x80\x80\x80") == "\"\\ufffd\\ufffd\\ufffd\\ufffd\"");
  CHECK(json_quote("\xe0\x80\xaf") == "\"\\ufffd\\ufffd\\ufffd\"");
  CHECK(json_quote("\xed\xa0\x80") == "\"\\ufffd\\ufffd\\ufffd\"");
  CHECK(json_quote("\xf4\x90\x80\x80") == "\"\\ufffd\\ufffd\\ufffd\\ufffd\"");
  CHECK(json_quote("\xff\"") == "\"\\ufffd\\\"\"");
}
