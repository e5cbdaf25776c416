#include "io/text_fields.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

namespace allanlot::io {

std::string ascii_lower(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
namespace {

bool blank(char c) {
  return c == ' ' || c == '\t';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (blank(s.front()) || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (blank(s.back()) || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool digits(std::string_view s, std::size_t at, std::size_t n, int& value) {
  if (at + n > s.size()) return false;
  value = 0;
  for (std::size_t i = at; i < at + n; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    value = value * 10 + (s[i] - '0');
  }
  return true;
}

bool leap(int y) {
  return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
}

// Days from 1970-01-01 to a Gregorian date: whole years, then whole months of the year.
long long days_since_epoch(int y, int m, int d) {
  static constexpr int kMonthDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  long long days = 0;
  for (int k = 1970; k < y; ++k)
    days += leap(k) ? 366 : 365;
  for (int k = y; k < 1970; ++k)
    days -= leap(k) ? 366 : 365;
  for (int k = 1; k < m; ++k)
    days += kMonthDays[k - 1] + (k == 2 && leap(y) ? 1 : 0);
  return days + d - 1;
}

}  // namespace

char detect_delimiter(std::string_view line) {
  bool seen[3] = {};
  bool quoted = false;
  for (const char c : line) {
    if (c == '"') quoted = !quoted;  // "" inside a quoted field toggles twice
    if (quoted) continue;
    seen[0] |= c == '\t';
    seen[1] |= c == ',';
    seen[2] |= c == ';';
  }
  return seen[0] ? '\t' : seen[1] ? ',' : seen[2] ? ';' : ' ';
}

namespace {

// The end of the field that starts at `b`: the next delimiter, or with RFC 4180 quoting (a
// field in double quotes, "" inside for one quote) the next delimiter after the closing quote.
std::size_t field_end(std::string_view line, char delim, std::size_t b) {
  std::size_t q = b;
  while (q < line.size() && blank(line[q]))
    ++q;
  if (q == line.size() || line[q] != '"') return line.find(delim, b);
  std::size_t close = q + 1;
  for (;;) {
    close = line.find('"', close);
    if (close == std::string_view::npos) return close;  // unclosed: the rest of the line
    if (close + 1 < line.size() && line[close + 1] == '"') {
      close += 2;
      continue;
    }
    return line.find(delim, close + 1);
  }
}

}  // namespace

void split_fields(std::string_view line, char delim, std::vector<std::string_view>& out) {
  out.clear();
  if (delim == ' ') {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (blank(line[i]) || line[i] == '\r'))
        ++i;
      if (i == line.size()) break;
      const std::size_t b = i;
      while (i < line.size() && !blank(line[i]) && line[i] != '\r')
        ++i;
      out.push_back(line.substr(b, i - b));
    }
    return;
  }
  std::size_t b = 0;
  for (;;) {
    const std::size_t e = field_end(line, delim, b);
    std::string_view f = trim(line.substr(b, e == std::string_view::npos ? e : e - b));
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    out.push_back(f);
    if (e == std::string_view::npos) break;
    b = e + 1;
  }
}

bool parse_number(std::string_view field, double& value) {
  if (field.empty()) {
    value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  // from_chars takes no '+'; a second sign after it stays an error.
  if (field.front() == '+') {
    field.remove_prefix(1);
    if (field.empty() || field.front() == '-' || field.front() == '+') return false;
  }
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  if (ptr != end) return false;
  // A value beyond double's range is an error, not a silent infinity or zero.
  return ec == std::errc();
}

bool looks_numeric(std::string_view f) {
  if (!f.empty() && (f.front() == '+' || f.front() == '-')) f.remove_prefix(1);
  const auto digit = [&](std::size_t i) { return i < f.size() && f[i] >= '0' && f[i] <= '9'; };
  return digit(0) || (!f.empty() && f.front() == '.' && digit(1));
}

StampParse parse_numeric_stamp(std::string_view f, NumericStamp& out) {
  out = {};
  const bool negative = !f.empty() && f.front() == '-';
  std::string_view digits_part = f;
  if (!f.empty() && (f.front() == '-' || f.front() == '+')) digits_part.remove_prefix(1);
  const std::size_t dot = digits_part.find('.');
  const std::string_view whole = digits_part.substr(0, dot);
  const std::string_view frac =
      dot == std::string_view::npos ? std::string_view{} : digits_part.substr(dot + 1);
  const auto all_digits = [](std::string_view s) {
    return std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if ((whole.empty() && frac.empty()) || !all_digits(whole) || !all_digits(frac)) {
    // Exponent notation (1.7e12) or anything else: through double, when it is a number.
    double v = 0;
    if (f.empty() || !parse_number(f, v) || !std::isfinite(v)) return StampParse::not_a_number;
    if (!(std::fabs(v) < 9.2e18)) return StampParse::beyond_int64;
    out.whole = static_cast<std::int64_t>(v);
    out.fraction = v - static_cast<double>(out.whole);
    return StampParse::ok;
  }
  if (!whole.empty()) {
    std::uint64_t w = 0;
    const auto [ptr, ec] = std::from_chars(whole.data(), whole.data() + whole.size(), w);
    constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
    if (ec != std::errc() || ptr != whole.data() + whole.size() || w > kMax)
      return StampParse::beyond_int64;
    out.whole = negative ? -static_cast<std::int64_t>(w) : static_cast<std::int64_t>(w);
  }
  // The fraction as digits / 10^n, both exact in double for n <= 18 (5^18 < 2^53): one
  // rounding. Decimals beyond 18 are below double's resolution of a fraction.
  std::uint64_t digits = 0;
  double denominator = 1;
  for (std::size_t i = 0; i < std::min<std::size_t>(frac.size(), 18); ++i) {
    digits = digits * 10 + static_cast<std::uint64_t>(frac[i] - '0');
    denominator *= 10;
  }
  out.fraction = static_cast<double>(digits) / denominator;
  if (negative) out.fraction = -out.fraction;
  return StampParse::ok;
}

bool is_comment(std::string_view line) {
  line = trim(line);
  return line.empty() || line.front() == '#' || line.front() == '%' || line.front() == ';';
}

HeaderCell parse_header_cell(std::string_view quoted_cell) {
  // A quoted cell's "" is one quote (RFC 4180); split_fields keeps it doubled.
  std::string text(trim(quoted_cell));
  for (std::size_t at = text.find("\"\""); at != std::string::npos; at = text.find("\"\"", at + 1))
    text.erase(at, 1);
  const std::string_view cell = text;
  HeaderCell h;
  for (const auto& [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const auto o = cell.rfind(open);
    if (cell.empty() || cell.back() != close || o == std::string_view::npos || o == 0) continue;
    h.name = std::string(trim(cell.substr(0, o)));
    h.unit = std::string(trim(cell.substr(o + 1, cell.size() - o - 2)));
    return h;
  }
  h.name = text;
  return h;
}

std::optional<double> time_unit_seconds(std::string_view unit) {
  const std::string u = lower(trim(unit));
  if (u == "s" || u == "sec" || u == "seconds") return 1.0;
  if (u == "ms") return 1e-3;
  if (u == "us" || u == "\xc2\xb5s" || u == "\xce\xbcs") return 1e-6;  // micro sign, Greek mu
  if (u == "ns") return 1e-9;
  return std::nullopt;
}

bool is_time_name(std::string_view name) {
  std::string n = lower(trim(name));
  // A time unit after the name, as loggers write it: time_ms, timestamp_ns, t_us.
  if (const auto u = n.rfind('_');
      u != std::string::npos && u > 0 && time_unit_seconds(std::string_view(n).substr(u + 1)))
    n.resize(u);
  return n == "time" || n == "timestamp" || n == "timestamps" || n == "t" || n == "stamp" ||
         n == "sec" || n == "seconds" || n.ends_with("_time");
}

std::optional<IsoTime> parse_iso8601(std::string_view f) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, s = 0;
  if (f.size() < 19 || !digits(f, 0, 4, y) || f[4] != '-' || !digits(f, 5, 2, mo) || f[7] != '-' ||
      !digits(f, 8, 2, d) || (f[10] != 'T' && f[10] != ' ') || !digits(f, 11, 2, h) ||
      f[13] != ':' || !digits(f, 14, 2, mi) || f[16] != ':' || !digits(f, 17, 2, s))
    return std::nullopt;
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || s > 60) return std::nullopt;
  IsoTime t;
  std::size_t i = 19;
  if (i < f.size() && (f[i] == '.' || f[i] == ',')) {
    const std::size_t b = i + 1;
    double scale = 0.1;
    for (i = b; i < f.size() && f[i] >= '0' && f[i] <= '9'; ++i, scale /= 10)
      t.fraction += (f[i] - '0') * scale;
    if (i == b) return std::nullopt;
  }
  long long zone = 0;
  if (i < f.size() && f[i] == 'Z') {
    ++i;
  } else if (i < f.size() && (f[i] == '+' || f[i] == '-')) {
    int zh = 0, zm = 0;
    const std::size_t colon = f.size() > i + 3 && f[i + 3] == ':' ? 1 : 0;
    if (!digits(f, i + 1, 2, zh) || !digits(f, i + 3 + colon, 2, zm)) return std::nullopt;
    zone = (f[i] == '+' ? 1 : -1) * (zh * 3600LL + zm * 60LL);
    i += 5 + colon;
  }
  if (i != f.size()) return std::nullopt;
  t.seconds = days_since_epoch(y, mo, d) * 86400 + h * 3600LL + mi * 60LL + s - zone;
  return t;
}

}  // namespace allanlot::io
