// The Allan-family statistics by name: one entry point that the command line and the batch
// driver call, and the per-statistic rules (valid m range) in one place.
#pragma once

#include "kernels/allan/phase.hpp"

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

namespace allanlot::kernels {

/// Statistics, named as in allantools and Stable32.
enum class Stat {
  Adev,   // Allan deviation (non-overlapping), SP1065 eq. (7)
  Oadev,  // overlapping Allan deviation, SP1065 eq. (11)
  Mdev,   // modified Allan deviation, SP1065 eq. (14)
  Tdev,   // time deviation, SP1065 eq. (16)
  Hdev,   // Hadamard deviation, SP1065 eq. (17)
  Ohdev,  // overlapping Hadamard deviation, SP1065 eq. (18)
  Totdev  // total deviation (doubly reflected TOTVAR), SP1065 eq. (25)
};

/// One row per averaging factor, like allantools' (taus, devs, errs, ns).
/// Rows whose estimator has no term (every term touches a gap) are left out.
struct StatResult {
  std::vector<std::int64_t> m;  // averaging factor
  std::vector<double> tau_s;    // tau = m * tau0
  std::vector<double> dev;      // the deviation, in the channel's rate units
  std::vector<std::int64_t> n;  // number of terms in the estimator's sum
  // Confidence intervals and noise identification (kernels/uncertainty/confidence.hpp); empty until
  // computed, then one entry per row.
  std::vector<double> edf;     // equivalent degrees of freedom
  std::vector<double> dev_lo;  // lower bound of the confidence interval
  std::vector<double> dev_hi;  // upper bound
  std::vector<int> alpha;      // identified power-law exponent of the rate PSD (S_y ~ f^alpha)
  double confidence = 0.0;     // the intervals' confidence level (0 = not computed)
  std::size_t size() const { return m.size(); }
};

/// "oadev" etc.
std::string_view stat_name(Stat s);
/// Inverse of stat_name; nullopt for an unknown name.
std::optional<Stat> parse_stat(std::string_view name);
/// False for the statistics that refuse gapped data (totdev: its reflections have no meaning
/// across a gap; see kernels/allan/total.hpp); the others leave out the terms that touch a gap.
bool supports_gaps(Stat s);
/// Every statistic this build computes, in the order results are written.
std::span<const Stat> all_stats();

/// Largest averaging factor Stable32 1.60 evaluates for `n_points` phase points N (its
/// tables in tests/data/stable32): (N-2)/5 for ADEV and HDEV, (N-1)/4 for OADEV, MDEV, TDEV and
/// OHDEV, (N-1)/2 for TOTDEV (Riley's stop ratios 5, 4, 2), so that every estimate keeps a
/// reasonable number of terms. 0 when N < 2.
std::int64_t max_m(Stat s, std::int64_t n_points);

/// Sums shared between the statistics of one phase record. OADEV's sums of squared second
/// differences at m are exactly TOTDEV's inner sums at m (SP1065 eq. (25): the centres away
/// from the reflected ends are OADEV's terms), formed in the same order, so the statistic
/// computed second reuses them instead of sweeping the record again (a third of TOTDEV's cost
/// on the default grid). Thread-safe; valid for one PhaseData only (one cache per record).
class SumCache {
public:
  /// The (sum, count) of the second-difference terms at m, when stored.
  std::optional<std::pair<double, std::int64_t>> second(std::int64_t m) const;
  void store_second(std::int64_t m, double sum, std::int64_t n);

private:
  mutable std::mutex mutex_;
  std::map<std::int64_t, std::pair<double, std::int64_t>> second_;
};

/// Computes statistic `s` at every m of `m_list` with m <= max_m(s, N); larger m give no row.
/// Throws std::invalid_argument for any m < 1, for gapped data with TOTDEV, and for the
/// preconditions of the statistic's own function (allan.hpp, hadamard.hpp, total.hpp).
/// Parallel over m with `nthreads` (0 = OpenMP default); results are bit-identical for any
/// thread count because each tau's sum is formed by one thread in a fixed order. With a
/// cache, OADEV and TOTDEV share their second-difference sums (same bits as without).
StatResult compute(Stat s, const PhaseData& p, std::span<const std::int64_t> m_list,
                   int nthreads = 0, SumCache* cache = nullptr);

}  // namespace allanlot::kernels
