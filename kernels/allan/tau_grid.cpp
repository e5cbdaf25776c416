#include "kernels/allan/tau_grid.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace allanlot::kernels {
namespace {

std::int64_t parse_int(std::string_view s, std::string_view whole) {
  std::int64_t v = 0;
  const auto* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, v);
  if (ec != std::errc() || ptr != end)
    throw std::invalid_argument("tau grid '" + std::string(whole) + "': '" + std::string(s) +
                                "' is not an integer");
  return v;
}

}  // namespace

TauGridSpec parse_tau_grid(std::string_view text) {
  TauGridSpec spec;
  if (text == "octave") {
    spec.kind = TauGridKind::Octave;
  } else if (text == "decade") {
    spec.kind = TauGridKind::Decade;
  } else if (text == "all") {
    spec.kind = TauGridKind::All;
  } else if (text == "stable32") {
    spec.kind = TauGridKind::Stable32;
  } else if (text.starts_with("stable32:")) {
    spec.kind = TauGridKind::Stable32;
    spec.stable32_k = parse_int(text.substr(9), text);
    if (spec.stable32_k < 1 || spec.stable32_k > 1'000'000'000)
      throw std::invalid_argument("tau grid '" + std::string(text) +
                                  "': step constant must be in 1..1000000000");
  } else if (text.starts_with("log:")) {
    spec.kind = TauGridKind::Log;
    const std::int64_t k = parse_int(text.substr(4), text);
    if (k < 1 || k > 1000)
      throw std::invalid_argument("tau grid '" + std::string(text) +
                                  "': points per decade must be in 1..1000");
    spec.per_decade = static_cast<int>(k);
  } else if (text.starts_with("m:")) {
    spec.kind = TauGridKind::Explicit;
    std::string_view rest = text.substr(2);
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      const std::int64_t m = parse_int(rest.substr(0, comma), text);
      if (m < 1)
        throw std::invalid_argument("tau grid '" + std::string(text) + "': m must be >= 1");
      spec.m.push_back(m);
      if (comma == std::string_view::npos) break;
      rest = rest.substr(comma + 1);
    }
    if (spec.m.empty())
      throw std::invalid_argument("tau grid '" + std::string(text) + "': empty list");
  } else {
    throw std::invalid_argument(
        "unknown tau grid '" + std::string(text) +
        "' (expected octave, decade, all, stable32, stable32:K, log:K or m:LIST)");
  }
  return spec;
}

std::int64_t stable32_step_constant(std::int64_t n_points) {
  const std::int64_t freq_points = n_points - 1;
  if (freq_points < 10) return 1'000'000'000;  // below one decade: every m
  // Whole decades of the number of frequency points: see tau_grid.hpp for the evidence.
  const double decades = std::floor(std::log10(static_cast<double>(freq_points)));
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor(215.0 / decades)));
}

std::vector<std::int64_t> make_m_list(const TauGridSpec& spec, std::int64_t m_max) {
  if (spec.kind == TauGridKind::Stable32 && spec.stable32_k == 0)
    throw std::invalid_argument(
        "tau grid 'stable32': the step constant depends on the number of points; call "
        "make_m_list(spec, m_max, n_points) or give it as 'stable32:K'");
  return make_m_list(spec, m_max, 0);
}

std::vector<std::int64_t> make_m_list(const TauGridSpec& spec, std::int64_t m_max,
                                      std::int64_t n_points) {
  std::vector<std::int64_t> out;
  if (m_max < 1) return out;
  switch (spec.kind) {
  case TauGridKind::Octave:
    for (std::int64_t m = 1; m <= m_max; m *= 2)
      out.push_back(m);
    break;
  case TauGridKind::Decade:
    // Stable32's decade grid: 1, 2, 4 times each power of ten.
    for (std::int64_t p = 1; p <= m_max; p *= 10) {
      for (const std::int64_t f : {1, 2, 4})
        if (f * p <= m_max) out.push_back(f * p);
      if (p > m_max / 10) break;
    }
    break;
  case TauGridKind::All:
    for (std::int64_t m = 1; m <= m_max; ++m)
      out.push_back(m);
    break;
  case TauGridKind::Stable32: {
    const std::int64_t k = spec.stable32_k > 0 ? spec.stable32_k : stable32_step_constant(n_points);
    for (std::int64_t m = 1; m <= m_max; m += m / k + 1)
      out.push_back(m);
    break;
  }
  case TauGridKind::Log: {
    const double k = spec.per_decade;
    for (int j = 0;; ++j) {
      const double v = std::round(std::pow(10.0, j / k));
      if (v > static_cast<double>(m_max)) break;
      const auto m = static_cast<std::int64_t>(v);
      if (out.empty() || out.back() != m) out.push_back(m);
    }
    break;
  }
  case TauGridKind::Explicit:
    for (const std::int64_t m : spec.m)
      if (m >= 1 && m <= m_max) out.push_back(m);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    break;
  }
  return out;
}

std::string to_string(const TauGridSpec& spec) {
  switch (spec.kind) {
  case TauGridKind::Octave:
    return "octave";
  case TauGridKind::Decade:
    return "decade";
  case TauGridKind::All:
    return "all";
  case TauGridKind::Stable32:
    return spec.stable32_k > 0 ? "stable32:" + std::to_string(spec.stable32_k) : "stable32";
  case TauGridKind::Log:
    return "log:" + std::to_string(spec.per_decade);
  case TauGridKind::Explicit: {
    std::string s = "m:";
    for (std::size_t i = 0; i < spec.m.size(); ++i) {
      if (i) s += ',';
      s += std::to_string(spec.m[i]);
    }
    return s;
  }
  }
  return "?";
}

}  // namespace allanlot::kernels
