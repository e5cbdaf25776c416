// The sums one statistic hands to another over the same phase record (kernels::compute's
// `cache`); apart from the dispatcher (stats.hpp) so that the family headers need not see it.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

namespace allanlot::kernels {

/// Sums shared between the statistics of one phase record. OADEV's sums of squared second
/// differences at m are exactly TOTDEV's inner sums at m (SP1065 eq. (25): the centres away
/// from the reflected ends are OADEV's terms), formed in the same order, so the statistic
/// computed second reuses them instead of sweeping the record again (a third of TOTDEV's cost
/// on the default grid). OHDEV's third differences at m read the same four points as OADEV's
/// second differences and the next one, so both are formed in one sweep when the caller asks
/// for both (kernels::prime_second_third) and each statistic takes its sums from here.
/// Thread-safe; valid for one PhaseData only (one cache per record).
class SumCache {
public:
  /// The (sum, count) of the second-difference terms at m, when stored.
  std::optional<std::pair<double, std::int64_t>> second(std::int64_t m) const;
  void store_second(std::int64_t m, double sum, std::int64_t n);
  /// The same for the third-difference terms at m (OHDEV's; prime_second_third stores both).
  std::optional<std::pair<double, std::int64_t>> third(std::int64_t m) const;
  void store_third(std::int64_t m, double sum, std::int64_t n);

private:
  mutable std::mutex mutex_;
  std::map<std::int64_t, std::pair<double, std::int64_t>> second_, third_;
};

}  // namespace allanlot::kernels
