// The pieces of a text recording's line (docs/formats.md "Text recordings"): fields split by
// the file's delimiter, numbers, header cells `name [unit]`, the names that mark a time
// column, and ISO-8601 time stamps.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::io {

/// `s` with ASCII letters in lower case (file extensions, column names; other bytes as they are).
std::string ascii_lower(std::string s);

/// The first of '\t' ',' ';' found outside double quotes, or ' ' for runs of blanks (spaces
/// and tabs).
char detect_delimiter(std::string_view line);

/// Splits `line` at `delim` into `out` (cleared first), each field trimmed of blanks and of
/// one pair of double quotes. A field in double quotes may hold the delimiter (RFC 4180; a
/// doubled quote inside stays doubled here, parse_header_cell makes it one). With ' ', runs of
/// blanks are one separator and leading and trailing blanks separate nothing.
void split_fields(std::string_view line, char delim, std::vector<std::string_view>& out);

/// Parses a whole field as a number: decimal or exponent notation, an optional sign, nan
/// and inf in any case. An empty field is NaN (a missing value). False when the field is
/// anything else.
bool parse_number(std::string_view field, double& value);

/// A numeric time stamp as written, its integer part and its fraction apart (same sign): a
/// double holds 15-16 digits, so an epoch in ns (1.7e18) read as one is rounded to 256 ns and a
/// 100 Hz logger reads as 99.99872 Hz; the parts keep every digit of an integer stamp up to
/// int64 and the fraction of a decimal one to double's precision.
struct NumericStamp {
  std::int64_t whole = 0;
  double fraction = 0;  // in (-1, 1), the sign of the stamp
};
enum class StampParse { ok, not_a_number, beyond_int64 };
/// A field written as a number, whether or not it is one: an optional sign, then a digit or a
/// '.' and a digit (`1e999`, `0x1p3`, `12abc`). Refused by parse_number, it is a malformed
/// number, never a text column or a header cell.
bool looks_numeric(std::string_view field);

/// Parses a whole field as a time stamp: digits with an optional sign and decimals exactly;
/// exponent notation through double. beyond_int64 when its integer part does not fit.
StampParse parse_numeric_stamp(std::string_view field, NumericStamp& out);

/// A comment line: empty after trimming, or starting with '#', '%' or ';'.
bool is_comment(std::string_view line);

/// A header cell split into the channel's name and its unit: `gx [deg/s]`, `gx (deg/s)`; a
/// doubled quote is one.
struct HeaderCell {
  std::string name;
  std::string unit;  // "" when the cell names none
};
HeaderCell parse_header_cell(std::string_view cell);

/// Names that say "time stamps", never a channel, in any case: time, timestamp(s), t, stamp,
/// sec, seconds, any name ending in _time, each also with a time unit after '_' (time_ms,
/// timestamp_ns, t_us, ...).
bool is_time_name(std::string_view name);

/// Seconds of one time unit ("s", "sec", "ms", "us", "µs", "ns"); nullopt for anything else.
std::optional<double> time_unit_seconds(std::string_view unit);

/// An ISO-8601 date and time, `YYYY-MM-DD[T ]hh:mm:ss[.fff][Z|±hh:mm]`, as seconds since
/// 1970-01-01T00:00:00Z split in whole seconds and a fraction (a double alone would keep only
/// microseconds of a date in this century). nullopt when the field is not one.
struct IsoTime {
  long long seconds = 0;
  double fraction = 0;
};
std::optional<IsoTime> parse_iso8601(std::string_view field);

}  // namespace allanlot::io
