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

}  // namespace allanlot::io
