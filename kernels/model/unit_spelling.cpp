// The vocabulary of unit spellings (units.hpp): how people write a unit in a CSV header, an
// HDF5 attribute, a spec or a datasheet, reduced to the one spelling allanlot computes with.
#include "kernels/model/units.hpp"

#include <array>
#include <utility>

namespace allanlot::kernels::units {
namespace {

// Characters outside ASCII that unit strings use, as UTF-8: the degree sign, the micro sign
// and the Greek mu (both written for micro), the square root, the superscript two and the
// middle dot (product).
constexpr std::array<std::pair<std::string_view, std::string_view>, 6> kSymbols{{
    {"\xC2\xB0", "deg"},
    {"\xC2\xB5", "u"},
    {"\xCE\xBC", "u"},
    {"\xE2\x88\x9A", "sqrt"},
    {"\xC2\xB2", "^2"},
    {"\xC2\xB7", "*"},
}};

// One '/'-separated piece of a unit, spelled as allanlot does.
std::string_view normal_token(std::string_view t) {
  static constexpr std::pair<std::string_view, std::string_view> kTokens[] = {
      {"degree", "deg"},
      {"degrees", "deg"},
      {"deg.", "deg"},
      {"sec", "s"},
      {"second", "s"},
      {"seconds", "s"},
      {"hr", "h"},
      {"hour", "h"},
      {"hours", "h"},
      {"hz", "Hz"},
      {"HZ", "Hz"},
      {"sqrtHz", "sqrt(Hz)"},
      {"sqrt(hz)", "sqrt(Hz)"},
      {"sqrthz", "sqrt(Hz)"},
      {"rtHz", "sqrt(Hz)"},
      {"rthz", "sqrt(Hz)"},
      {"rt(Hz)", "sqrt(Hz)"},
      {"Hz^0.5", "sqrt(Hz)"},
      {"sqrt(Hz)", "sqrt(Hz)"},
      {"sqrth", "sqrt(h)"},
      {"sqrt(hr)", "sqrt(h)"},
      {"sqrthr", "sqrt(h)"},
      {"rt(h)", "sqrt(h)"},
      {"rth", "sqrt(h)"},
      {"rthr", "sqrt(h)"},
      {"h^0.5", "sqrt(h)"},
      {"hr^0.5", "sqrt(h)"},
      {"sqrts", "sqrt(s)"},
      {"s^0.5", "sqrt(s)"},
      {"sqrt(sec)", "sqrt(s)"},
      {"s2", "s^2"},
      {"sec^2", "s^2"},
      {"sec2", "s^2"},
      {"h2", "h^2"},
      {"hr^2", "h^2"},
      {"arcsecond", "arcsec"},
  };
  for (const auto& [from, to] : kTokens)
    if (t == from) return to;
  return t;
}

// Whole channel-unit spellings after the pieces are normalised, and the factor from the unit
// as spelled to the canonical one.
struct Alias {
  std::string_view spelled, canonical;
  double scale;
  bool per_nominal = false;
};
constexpr Alias kChannelAliases[] = {
    {"deg/s", "deg/s", 1}, {"dps", "deg/s", 1},   {"deg/h", "deg/h", 1}, {"dph", "deg/h", 1},
    {"rad/s", "rad/s", 1}, {"m/s^2", "m/s^2", 1}, {"m/s/s", "m/s^2", 1}, {"m*s^-2", "m/s^2", 1},
    {"ms^-2", "m/s^2", 1}, {"mps2", "m/s^2", 1},  {"g", "g", 1},         {"mg", "mg", 1},
    {"milli-g", "mg", 1},  {"ug", "ug", 1},       {"s", "s", 1},         {"ms", "s", 1e-3},
    {"us", "s", 1e-6},     {"ns", "s", 1e-9},     {"ps", "s", 1e-12},    {"1", "1", 1},
    {"ppm", "1", 1e-6},    {"ppb", "1", 1e-9},    {"ppt", "1", 1e-12},   {"Hz/Hz", "1", 1},
    {"Hz", "1", 1, true},
};

}  // namespace

std::string normalize_spelling(std::string_view spelled) {
  std::string s;
  for (std::size_t i = 0; i < spelled.size();) {
    bool replaced = false;
    for (const auto& [from, to] : kSymbols)
      if (spelled.substr(i, from.size()) == from) {
        s.append(to);
        i += from.size();
        replaced = true;
        break;
      }
    if (replaced) continue;
    if (spelled[i] != ' ' && spelled[i] != '\t') s.push_back(spelled[i]);
    ++i;
  }
  // A power written with a slash ("Hz^(1/2)") is one piece, not two.
  for (std::size_t at; (at = s.find("^(1/2)")) != std::string::npos;)
    s.replace(at, 6, "^0.5");
  // "sqrtHz", from the square-root sign, and the other pieces spelled as allanlot does.
  std::string out;
  std::size_t start = 0;
  while (true) {
    const std::size_t slash = s.find('/', start);
    const std::string_view piece = std::string_view(s).substr(
        start, slash == std::string::npos ? std::string::npos : slash - start);
    out.append(normal_token(piece));
    if (slash == std::string::npos) break;
    out.push_back('/');
    start = slash + 1;
  }
  return out;
}

std::optional<ChannelUnits> parse_channel_units(std::string_view spelled) {
  const std::string s = normalize_spelling(spelled);
  for (const Alias& a : kChannelAliases)
    if (s == a.spelled) return ChannelUnits{std::string(a.canonical), a.scale, a.per_nominal};
  return std::nullopt;
}

}  // namespace allanlot::kernels::units
