// Lot statistics (docs/lots-and-slurm.md "The lot summary: spec, statistics, outliers"): the
// one quantile, median and MAD of the project, and THE outlier rule. The lot summary
// (src/lot/summary.hpp) and the report's lot page (src/report/) both judge units through
// compute_lot_statistics, so that they flag the same units with the same z.
#pragma once

#include "io/results.hpp"
#include "kernels/common/quantile.hpp"

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace allanlot::lot {

/// The terms of eq. (3) in the order of io::SummaryRow's arrays.
inline constexpr std::array<const char*, 5> kTermNames = {"R", "K", "B", "N", "Q"};

/// Outlier rule: the modified z-score of Iglewicz & Hoaglin (1993, "How to Detect and Handle
/// Outliers", ch. 3), M = (x - median) / (1.4826 MAD), |M| > 3.5 flags an outlier, with one
/// change: the scale is sqrt((1.4826 MAD)^2 + sigma_i^2), sigma_i the unit's own 1-sigma
/// uncertainty of the coefficient. Median and MAD have a 50 % breakdown point, so the planted
/// outlier cannot hide itself by inflating the scale as it would with mean and standard
/// deviation. 1.4826 = 1 / Phi^-1(3/4) makes 1.4826 MAD estimate sigma for normal data; 3.5 is
/// the cut-off Iglewicz & Hoaglin recommend (P(|Z| > 3.5) = 4.7e-4: about 1 false flag in 2000
/// units of a large normal lot). Why sigma_i: in a small lot the MAD can come out far below the
/// units' own measurement uncertainty by chance (seen on a simulated lot of 8: B of gyro_z with
/// MAD-based spread 0.07 deg/h while each unit's B had sigma 0.3 to 0.9 deg/h), and a unit whose
/// term is undetected (value 0, sigma 0.86) was then "10 spreads" low although it was within
/// one of its own sigmas of the median. A deviation smaller than the unit's own uncertainty is
/// no evidence of anything; with sigma_i << spread the rule is Iglewicz & Hoaglin's.
using kernels::kMadToSigma;  // 1.4826, owned by kernels/common/quantile.hpp
inline constexpr double kOutlierZ = 3.5;
/// Below 5 units the scale is too coarse to call anyone an outlier: with 3 or 4 values the
/// MAD is set by one or two deviations, often small by chance, and the rule would flag
/// ordinary units far more often than the 1 in 2000 it is calibrated for.
inline constexpr std::size_t kMinUnitsForOutliers = 5;
// A term is also judged only when at least half of its units detect it (see
// compute_lot_statistics).

/// The p-quantile (0 <= p <= 1) of ascending `sorted` (non-empty) by linear interpolation
/// between order statistics, x[floor(h)] + (h - floor(h)) (x[floor(h)+1] - x[floor(h)]) with
/// h = (n - 1) p: Hyndman & Fan (1996) definition 7, the default of R and NumPy, so the numbers
/// can be checked with either. Throws std::invalid_argument when `sorted` is empty or p is
/// outside [0, 1].
double quantile_sorted(std::span<const double> sorted, double p);

/// The median absolute deviation of `values` (any order, non-empty) from `median`.
double median_absolute_deviation(std::span<const double> values, double median);

/// The rule's modified z-score of one unit's `value` with 1-sigma `sigma` (NaN counts as 0)
/// against its group's `median` and `spread` (1.4826 MAD); NaN where both the spread and the
/// sigma are 0, since there is no scale to measure a deviation against.
double outlier_z(double value, double sigma, double median, double spread);

/// One unit flagged on one term.
struct TermOutlier {
  std::size_t row = 0;   // index of the unit's row in the rows given
  std::size_t term = 0;  // 0 .. 4: R, K, B, N, Q (kTermNames)
  double z = 0;          // the modified z-score, signed
  double median = 0;     // the lot median of the term over the row's group
};

struct LotStatistics {
  /// Per (channel path, term, datasheet unit), sorted by channel path then R, K, B, N, Q.
  std::vector<io::StatisticsRow> statistics;
  /// Every unit flagged by the rule above, in the order of `statistics`, then of the rows.
  std::vector<TermOutlier> outliers;
};

/// Lot statistics over the rows with status ok, a channel and a finite value, grouped by
/// channel path, term and datasheet unit (so that numbers of different units are never
/// pooled), and the outliers by the rule above: only in groups of >= 5 units of which at
/// least half detect the term, and never where both the MAD and the unit's sigma are 0.
LotStatistics compute_lot_statistics(const std::vector<io::SummaryRow>& rows);

/// A modified z-score as every outlier list prints it (the lot summary's outlier_terms, the
/// terminal overview, the report's outlier table), so that the three read alike: signed, two
/// significant digits, e.g. "+26", "-4.1".
std::string z_text(double z);

/// The text of one flagged term in the lot summary's outlier_terms column, e.g. "N z=+26".
std::string outlier_text(const TermOutlier& o);

/// compute_lot_statistics, with each row's outlier and outlier_terms set from its outliers
/// ("N z=+5.2; B z=-4.1"; cleared on rows without any); returns the statistics.
std::vector<io::StatisticsRow> lot_statistics(std::vector<io::SummaryRow>& rows);

}  // namespace allanlot::lot
