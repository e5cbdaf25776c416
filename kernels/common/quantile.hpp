// The one sample quantile of the project: linear interpolation between order statistics
// (Hyndman & Fan, Am. Stat. 50(4), 1996, definition 7; R's and NumPy's default). Used by the
// diagnosis's Monte Carlo bands and, through src/lot/statistics, by the lot statistics and the
// outlier rule, so that every median and percentile allanlot prints is computed alike.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

namespace allanlot::kernels {

/// The p-quantile (0 <= p <= 1) of the ascending values `sorted`; NaN when there are none.
inline double quantile_sorted(std::span<const double> sorted, double p) {
  if (sorted.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double h = p * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

}  // namespace allanlot::kernels
