// io::valid_utf8: well-formed UTF-8 unchanged, every other byte as \xNN (RFC 3629).
#include "io/utf8.hpp"

#include <gtest/gtest.h>

namespace allanlot::io {
namespace {

TEST(Utf8, WellFormedTextIsUnchanged) {
  for (const char* s : {"", "unit_7", "gyro \xC2\xB0/s", "\xE2\x88\x9AHz", "\xF0\x9F\x93\x88",
                        "\xEF\xBF\xBD", "\xF4\x8F\xBF\xBF"})
    EXPECT_EQ(valid_utf8(s), s);
}

TEST(Utf8, EveryOtherByteIsEscaped) {
  // Latin-1, a lone continuation byte, a truncated sequence, an overlong '/', a surrogate,
  // a code point above U+10FFFF, and the bytes that never occur.
  EXPECT_EQ(valid_utf8("unit\xE9"
                       "7"),
            "unit\\xE97");
  EXPECT_EQ(valid_utf8("\x80"), "\\x80");
  EXPECT_EQ(valid_utf8("a\xE2\x88"), "a\\xE2\\x88");
  EXPECT_EQ(valid_utf8("\xC0\xAF"), "\\xC0\\xAF");
  EXPECT_EQ(valid_utf8("\xED\xA0\x80"), "\\xED\\xA0\\x80");
  EXPECT_EQ(valid_utf8("\xF4\x90\x80\x80"), "\\xF4\\x90\\x80\\x80");
  EXPECT_EQ(valid_utf8("\xFE\xFF"), "\\xFE\\xFF");
  // The escape of an escape stays readable: the backslash is ASCII.
  EXPECT_EQ(valid_utf8(valid_utf8("\xFF")), "\\xFF");
}

}  // namespace
}  // namespace allanlot::io
