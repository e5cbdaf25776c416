#include "kernels/allan/gaps.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace allanlot::kernels {
namespace {

[[noreturn]] void bad_policy(std::string_view text) {
  throw std::invalid_argument("gap policy '" + std::string(text) +
                              "' is not one of skip, fill, fill:N (N >= 1 samples)");
}

// The line through the first and last valid points, per sample: the slope phase data are
// continued along at the record's ends. 0 when fewer than two points are valid.
double mean_slope(std::span<const double> x) {
  std::size_t first = 0, last = x.size();
  while (first < x.size() && std::isnan(x[first]))
    ++first;
  while (last > first && std::isnan(x[last - 1]))
    --last;
  if (last - first < 2) return 0.0;
  return (x[last - 1] - x[first]) / static_cast<double>(last - 1 - first);
}

// Fills samples a .. b-1 (all NaN) from their valid neighbours, at a - 1 and b when inside.
void fill_run(std::span<double> v, std::size_t a, std::size_t b, DataType type, double slope) {
  const bool left = a > 0, right = b < v.size();
  if (left && right) {
    // Linear interpolation between v[a-1] and v[b]: the estimate of every missing sample from
    // its two neighbours, for rate and phase alike.
    const double y0 = v[a - 1], y1 = v[b];
    const double span = static_cast<double>(b - a + 1);
    for (std::size_t k = a; k < b; ++k)
      v[k] = y0 + (y1 - y0) * (static_cast<double>(k - a + 1) / span);
    return;
  }
  const double step = type == DataType::Phase ? slope : 0.0;
  if (left) {
    for (std::size_t k = a; k < b; ++k)
      v[k] = v[a - 1] + step * static_cast<double>(k - a + 1);
  } else {
    for (std::size_t k = a; k < b; ++k)
      v[k] = v[b] - step * static_cast<double>(b - k);
  }
}

}  // namespace

GapPolicy parse_gap_policy(std::string_view text) {
  GapPolicy p;
  if (text == "skip") {
    p.mode = GapPolicy::Mode::Skip;
    p.max_run = 0;
    return p;
  }
  if (text == "fill") {
    p.max_run = 0;
    return p;
  }
  constexpr std::string_view prefix = "fill:";
  if (text.substr(0, prefix.size()) != prefix) bad_policy(text);
  const std::string_view num = text.substr(prefix.size());
  std::int64_t n = 0;
  const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), n);
  if (num.empty() || ec != std::errc() || end != num.data() + num.size() || n < 1) bad_policy(text);
  p.max_run = n;
  return p;
}

std::string to_string(const GapPolicy& policy) {
  if (policy.mode == GapPolicy::Mode::Skip) return "skip";
  return policy.max_run == 0 ? "fill" : "fill:" + std::to_string(policy.max_run);
}

namespace {

using Runs = std::vector<std::pair<std::size_t, std::size_t>>;

// fill_gaps, noting each filled run [a, b) in `filled` when given.
GapFill fill_runs(std::span<double> samples, DataType type, const GapPolicy& policy, Runs* filled) {
  GapFill out;
  const bool fill = policy.mode == GapPolicy::Mode::Fill;
  double slope = 0.0;
  bool slope_known = false;
  const std::size_t n = samples.size();
  for (std::size_t a = 0; a < n;) {
    if (!std::isnan(samples[a])) {
      ++a;
      continue;
    }
    std::size_t b = a;
    while (b < n && std::isnan(samples[b]))
      ++b;
    const auto len = static_cast<std::int64_t>(b - a);
    ++out.runs;
    out.missing += len;
    const bool whole = a == 0 && b == n;
    if (fill && !whole && (policy.max_run == 0 || len <= policy.max_run)) {
      if (!slope_known && type == DataType::Phase && (a == 0 || b == n)) {
        slope = mean_slope(samples);
        slope_known = true;
      }
      fill_run(samples, a, b, type, slope);
      if (filled) filled->emplace_back(a, b);
      ++out.filled_runs;
      out.filled += len;
    } else {
      ++out.runs_left;
      out.missing_left += len;
    }
    a = b;
  }
  return out;
}

// The gaps of the phase (phase.hpp: missing increments before each phase point) with the
// filled samples counted as missing again: a rate sample is one increment, a phase point
// makes both increments beside it missing.
std::vector<std::int64_t> skip_gaps(std::span<const double> samples, DataType type,
                                    const Runs& filled) {
  std::vector<std::uint8_t> missing(samples.size(), 0);
  for (std::size_t k = 0; k < samples.size(); ++k)
    missing[k] = std::isnan(samples[k]) ? 1 : 0;
  for (const auto& [a, b] : filled)
    std::fill(missing.begin() + static_cast<std::ptrdiff_t>(a),
              missing.begin() + static_cast<std::ptrdiff_t>(b), std::uint8_t{1});
  const std::size_t increments = type == DataType::Rate ? samples.size() : samples.size() - 1;
  std::vector<std::int64_t> g(increments + 1, 0);
  for (std::size_t j = 0; j < increments; ++j) {
    const bool gone = type == DataType::Rate ? missing[j] : (missing[j] || missing[j + 1]);
    g[j + 1] = g[j] + (gone ? 1 : 0);
  }
  return g;
}

}  // namespace

GapFill fill_gaps(std::span<double> samples, DataType type, const GapPolicy& policy) {
  return fill_runs(samples, type, policy, nullptr);
}

PhaseData make_phase(std::span<double> samples, DataType type, double rate_hz,
                     const GapPolicy& policy, GapFill* fill, int nthreads) {
  Runs filled;
  const GapFill f = fill_runs(samples, type, policy, &filled);
  PhaseData p = make_phase(std::span<const double>(samples), type, rate_hz, nthreads);
  p.n_filled = f.filled;
  if (f.filled > 0) p.skip_gaps = skip_gaps(samples, type, filled);
  if (fill) *fill = f;
  return p;
}

PhaseData skip_view(const PhaseData& p) {
  if (p.skip_gaps.empty()) throw std::invalid_argument("skip_view: no sample was filled");
  PhaseData v;
  v.x = p.x;
  v.gaps = p.skip_gaps;
  v.tau0_s = p.tau0_s;
  v.n_gaps = p.n_gaps + p.n_filled;
  v.mean_rate = p.mean_rate;
  return v;
}

namespace {

// The one rule: a row with the filled samples' terms left out is kept when it keeps at least
// kSkipKeepShare of the filled record's terms at the same m.
bool keeps_enough(std::int64_t n_skipped, std::int64_t n_filled) {
  return static_cast<double>(n_skipped) >= kSkipKeepShare * static_cast<double>(n_filled);
}

void append_row(StatResult& out, const StatResult& r, std::size_t i) {
  out.m.push_back(r.m[i]);
  out.tau_s.push_back(r.tau_s[i]);
  out.dev.push_back(r.dev[i]);
  out.n.push_back(r.n[i]);
}

// Whether the row of `skipped` at m (its last) is taken over the row of `filled` at m.
bool taken(const StatResult& filled, const StatResult& skipped) {
  if (skipped.size() == 0) return false;
  const std::int64_t m = skipped.m.back();
  const auto it = std::lower_bound(filled.m.begin(), filled.m.end(), m);
  if (it == filled.m.end() || *it != m) return true;
  return keeps_enough(skipped.n.back(), filled.n[static_cast<std::size_t>(it - filled.m.begin())]);
}

}  // namespace

StatResult skipped_rows(
    const PhaseData& view, const std::vector<std::int64_t>& ms, const StatResult& filled,
    const std::function<StatResult(const PhaseData&, const std::vector<std::int64_t>&)>& run) {
  StatResult out;
  std::size_t done = 0, batch = 8;
  while (done < ms.size()) {
    const std::size_t end = std::min(ms.size(), done + batch);
    const std::vector<std::int64_t> part(ms.begin() + static_cast<std::ptrdiff_t>(done),
                                         ms.begin() + static_cast<std::ptrdiff_t>(end));
    const StatResult r = run(view, part);
    for (std::size_t i = 0; i < r.size(); ++i)
      append_row(out, r, i);
    // The last m of the batch without a row has no term without a filled sample: not taken.
    if (r.size() == 0 || r.m.back() != part.back() || !taken(filled, r)) break;
    done = end;
    batch *= 2;
  }
  return out;
}

StatResult merge_filled_skipped(const StatResult& filled, const StatResult& skipped) {
  StatResult out;
  std::size_t i = 0, j = 0;
  while (i < filled.size() || j < skipped.size()) {
    if (j == skipped.size() || (i < filled.size() && filled.m[i] < skipped.m[j])) {
      append_row(out, filled, i++);
    } else if (i == filled.size() || skipped.m[j] < filled.m[i]) {
      append_row(out, skipped, j++);
    } else {
      const bool keep = keeps_enough(skipped.n[j], filled.n[i]);
      append_row(out, keep ? skipped : filled, keep ? j : i);
      ++i;
      ++j;
    }
  }
  return out;
}

}  // namespace allanlot::kernels
