// The dynamic Allan deviation of dynamic.hpp.
#include "kernels/allan/dynamic.hpp"

#include "kernels/allan/allan.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/common/parallel.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

// A positive number with an optional suffix s; `seconds` receives whether it had one.
double parse_length(std::string_view part, bool& seconds, std::string_view whole) {
  seconds = !part.empty() && part.back() == 's';
  if (seconds) part.remove_suffix(1);
  const std::string s(part);
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size() || !(v > 0) || !std::isfinite(v))
    throw std::invalid_argument("dynamic '" + std::string(whole) +
                                "': expected WINDOW[:STEP], each a positive number of samples "
                                "or of seconds with the suffix s (e.g. 4096 or 3600s:600s)");
  return v;
}

}  // namespace

DynamicSpec parse_dynamic_spec(std::string_view text) {
  DynamicSpec spec;
  const std::size_t colon = text.find(':');
  bool w_seconds = false, s_seconds = false;
  spec.window = parse_length(text.substr(0, colon), w_seconds, text);
  if (colon != std::string_view::npos) {
    spec.step = parse_length(text.substr(colon + 1), s_seconds, text);
    if (s_seconds != w_seconds)
      throw std::invalid_argument("dynamic '" + std::string(text) +
                                  "': window and step in the same unit (both samples or both s)");
  }
  spec.in_seconds = w_seconds;
  return spec;
}

DynamicAdev dynamic_oadev(std::span<const double> samples, DataType type, double rate_hz,
                          std::int64_t window, std::int64_t step, int nthreads) {
  const auto n = static_cast<std::int64_t>(samples.size());
  if (!(rate_hz > 0) || !std::isfinite(rate_hz))
    throw std::invalid_argument("dynamic: rate_hz must be finite and > 0");
  if (window < 3 || window > n)
    throw std::invalid_argument("dynamic: window of " + std::to_string(window) +
                                " samples, expected 3 to the record's " + std::to_string(n));
  if (step < 1) throw std::invalid_argument("dynamic: step must be >= 1 sample");
  const std::int64_t windows = (n - window) / step + 1;
  if (windows > kMaxDynamicWindows)
    throw std::invalid_argument("dynamic: " + std::to_string(windows) + " windows, at most " +
                                std::to_string(kMaxDynamicWindows) + " (a larger step)");
  DynamicAdev d;
  d.window = window;
  d.step = step;
  // The window's phase points: window + 1 for rate samples, window for phase samples.
  const std::int64_t points = type == DataType::Rate ? window + 1 : window;
  d.m = make_m_list(TauGridSpec{TauGridKind::Octave, 0, {}, 0}, max_m(Stat::Oadev, points), points);
  const auto nm = d.m.size();
  for (const std::int64_t m : d.m)
    d.tau_s.push_back(static_cast<double>(m) / rate_hz);
  d.oadev.assign(static_cast<std::size_t>(windows) * nm, std::numeric_limits<double>::quiet_NaN());
  d.t_center_s.resize(static_cast<std::size_t>(windows));
  const int threads = resolve_threads(nthreads);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::int64_t w = 0; w < windows; ++w) {
    const std::int64_t first = w * step;
    const auto wi = static_cast<std::size_t>(w);
    d.t_center_s[wi] = (static_cast<double>(first) + static_cast<double>(window - 1) / 2) / rate_hz;
    try {
      const PhaseData p = make_phase(
          samples.subspan(static_cast<std::size_t>(first), static_cast<std::size_t>(window)), type,
          rate_hz, 1);
      const StatResult r = oadev(p, d.m, 1);
      for (std::size_t j = 0; j < r.size(); ++j)
        for (std::size_t k = 0; k < nm; ++k)
          if (d.m[k] == r.m[j]) d.oadev[wi * nm + k] = r.dev[j];
    } catch (const std::exception&) {
      // A window with no valid sample has no deviation: its row stays NaN.
    }
  }
  return d;
}

}  // namespace allanlot::kernels
