// Every string allanlot writes (results, lot summaries, CSV) is valid UTF-8, as the HDF5 string
// type it declares says and as CSV readers expect; names that come from elsewhere (a device_id
// attribute, a file name, a path) may hold any bytes.
#pragma once

#include <string>
#include <string_view>

namespace allanlot::io {

/// `s` with every byte that does not start or continue a well-formed UTF-8 sequence (RFC 3629:
/// no overlong forms, no surrogates, nothing above U+10FFFF) written as the four characters
/// `\xNN`; valid text is returned unchanged, so that "unit\xff7" still tells units apart.
std::string valid_utf8(std::string_view s);

/// valid_utf8 with the control characters (NUL, ESC, ... DEL) also as `\xNN`: bytes from a file
/// shown in a message, which a NUL would cut short and an escape sequence would act on.
std::string printable(std::string_view s);

/// Bytes of the well-formed UTF-8 sequence of a code point from U+0080 up at s[i] (0 for ASCII
/// and for a byte that starts none), and in `letter` whether it may stand in a file name made
/// from a name of another script (a device_id in Cyrillic or CJK): from U+00A1 up, save the
/// invisible and look-alike ones (spaces, joiners, direction marks and overrides, line
/// separators, the byte-order mark, variation selectors, private use, and the division,
/// fraction and fullwidth slashes and backslash).
std::size_t name_letter_length(std::string_view s, std::size_t i, bool& letter);

}  // namespace allanlot::io
