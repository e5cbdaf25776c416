// What every statistic of the Allan family returns, apart from the dispatcher (stats.hpp), so
// that the family headers (allan.hpp, hadamard.hpp, total.hpp) and the consumers of results
// need not see the statistics by name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace allanlot::kernels {

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

}  // namespace allanlot::kernels
