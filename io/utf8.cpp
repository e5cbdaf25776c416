#include "io/utf8.hpp"

#include <cstdio>

namespace allanlot::io {
namespace {

// Length of the well-formed UTF-8 sequence starting at s[i], 0 when there is none (RFC 3629,
// section 4: the ranges of the second byte exclude overlong forms and surrogates).
std::size_t sequence_length(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + n > s.size() || b(1) < lo || b(1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (b(k) < 0x80 || b(k) > 0xBF) return 0;
  return n;
}

// s with the bytes that start no well-formed sequence, and the control characters when
// `controls`, as \xNN.
std::string escaped(std::string_view s, bool controls) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = controls && (c < 0x20 || c == 0x7F) ? 0 : sequence_length(s, i);
    if (n > 0) {
      out.append(s.substr(i, n));
      i += n;
      continue;
    }
    char hex[5];
    std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(s[i]));
    out.append(hex, 4);
    ++i;
  }
  return out;
}

// The code point of the well-formed sequence of `n` bytes at s[i].
char32_t decode(std::string_view s, std::size_t i, std::size_t n) {
  static constexpr unsigned char kLead[5] = {0, 0x7F, 0x1F, 0x0F, 0x07};
  char32_t cp = static_cast<unsigned char>(s[i]) & kLead[n];
  for (std::size_t k = 1; k < n; ++k)
    cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
  return cp;
}

// Code points that show as nothing, as a space, or as a slash, or reorder what follows.
bool invisible_or_lookalike(char32_t c) {
  return c == 0xAD || c == 0x34F || c == 0x61C || c == 0x115F || c == 0x1160 || c == 0x1680 ||
         c == 0x180E || (c >= 0x2000 && c <= 0x206F) || c == 0x2215 || c == 0x29F5 || c == 0x3000 ||
         c == 0x3164 || (c >= 0xE000 && c <= 0xF8FF) || (c >= 0xFE00 && c <= 0xFE0F) ||
         c == 0xFEFF || c == 0xFF0F || c == 0xFF3C || c == 0xFFA0 || c >= 0xFFF0;
}

}  // namespace

std::size_t name_letter_length(std::string_view s, std::size_t i, bool& letter) {
  letter = false;
  const std::size_t n = sequence_length(s, i);
  if (n < 2) return 0;
  const char32_t c = decode(s, i, n);
  letter = c > 0xA0 && !invisible_or_lookalike(c);
  return n;
}

std::string valid_utf8(std::string_view s) {
  return escaped(s, false);
}

std::string printable(std::string_view s) {
  return escaped(s, true);
}

}  // namespace allanlot::io
