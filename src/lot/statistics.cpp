#include "src/lot/statistics.hpp"

#include "kernels/common/quantile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <tuple>

namespace allanlot::lot {

double quantile_sorted(std::span<const double> sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("quantile_sorted: no values");
  if (!(p >= 0.0 && p <= 1.0)) throw std::invalid_argument("quantile_sorted: p outside [0, 1]");
  return kernels::quantile_sorted(sorted, p);
}

double median_absolute_deviation(std::span<const double> values, double median) {
  std::vector<double> dev;
  dev.reserve(values.size());
  for (const double x : values)
    dev.push_back(std::abs(x - median));
  std::sort(dev.begin(), dev.end());
  return quantile_sorted(dev, 0.5);
}

double outlier_z(double value, double sigma, double median, double spread) {
  const double scale = std::hypot(spread, std::isfinite(sigma) ? sigma : 0.0);
  if (!(scale > 0.0)) return std::nan("");
  return (value - median) / scale;
}

namespace {

// (channel, term index, unit) -> indices of the rows with a value. The unit is part of the
// key so that a lot mixing channel units never pools numbers of different units.
using Groups =
    std::map<std::tuple<std::string, std::size_t, std::string>, std::vector<std::size_t>>;

Groups group_rows(const std::vector<io::SummaryRow>& rows) {
  Groups groups;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const io::SummaryRow& row = rows[r];
    if (!row.status.is_ok() || row.channel.empty()) continue;
    for (std::size_t i = 0; i < 5; ++i)
      if (std::isfinite(row.value[i])) groups[{row.channel, i, row.unit[i]}].push_back(r);
  }
  return groups;
}

}  // namespace

LotStatistics compute_lot_statistics(const std::vector<io::SummaryRow>& rows) {
  LotStatistics out;
  for (const auto& [key, members] : group_rows(rows)) {
    const auto& [channel, i, unit] = key;
    std::vector<double> v;
    io::StatisticsRow s;
    s.channel = channel;
    s.term = kTermNames[i];
    s.unit = unit;
    for (const std::size_t r : members) {
      v.push_back(rows[r].value[i]);
      s.n_detected += rows[r].detected[i] ? 1 : 0;
    }
    std::sort(v.begin(), v.end());
    s.n = static_cast<std::int64_t>(v.size());
    s.median = quantile_sorted(v, 0.5);
    s.spread = kMadToSigma * median_absolute_deviation(v, s.median);
    s.p5 = quantile_sorted(v, 0.05);
    s.p25 = quantile_sorted(v, 0.25);
    s.p75 = quantile_sorted(v, 0.75);
    s.p95 = quantile_sorted(v, 0.95);
    s.min = v.front();
    s.max = v.back();
    // Outliers only where most units detect the term: otherwise median and MAD describe the
    // fit's noise around the zero clamp, and a unit that merely detects the term (K at 3.6
    // sigma where its neighbours fit 0, seen on a simulated lot) would be called an outlier.
    if (v.size() >= kMinUnitsForOutliers && 2 * s.n_detected >= s.n)
      for (const std::size_t r : members) {
        const double z = outlier_z(rows[r].value[i], rows[r].sigma[i], s.median, s.spread);
        if (!(std::abs(z) > kOutlierZ)) continue;  // NaN: no scale to measure against
        ++s.n_outliers;
        out.outliers.push_back({r, i, z, s.median});
      }
    out.statistics.push_back(std::move(s));
  }
  // std::map orders the terms by index already (R, K, B, N, Q), channels by path.
  return out;
}

std::string z_text(double z) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.2g", z);
  return buf;
}

std::string outlier_text(const TermOutlier& o) {
  return std::string(kTermNames[o.term]) + " z=" + z_text(o.z);
}

std::vector<io::StatisticsRow> lot_statistics(std::vector<io::SummaryRow>& rows) {
  LotStatistics lot = compute_lot_statistics(rows);
  for (io::SummaryRow& row : rows) {
    row.outlier = 0;  // this function alone decides them
    row.outlier_terms.clear();
  }
  for (const TermOutlier& o : lot.outliers) {
    io::SummaryRow& row = rows[o.row];
    row.outlier = 1;
    row.outlier_terms += (row.outlier_terms.empty() ? "" : "; ") + outlier_text(o);
  }
  return std::move(lot.statistics);
}

}  // namespace allanlot::lot
