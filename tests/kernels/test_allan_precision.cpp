// Prefix-sum precision of every statistic on a long record with a large mean: an
// accelerometer's 1 g (9.80665 m/s^2) on 5.4 M samples of 1e-3 m/s^2 white noise at 1 kHz,
// against long-double references, to 1e-9 relative.
//
// Why this is hard: a double cumulative sum of the raw data reaches 5.3e4 m/s and keeps only
// ~1e-11 absolute resolution against m = 1 second differences of ~1.4e-6 m/s; and MDEV/TDEV
// need sums of windows of x, a second-level prefix sum that grows to ~1e4 times x. The
// kernels remove the mean rate before integrating (long double, phase.cpp) and form MDEV's
// window sums in exact fixed point (allan.hpp, detail::WindowSums).
#include "kernels/allan/allan.hpp"
#include "kernels/allan/hadamard.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/total.hpp"
#include "reference/naive_allan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace allanlot {
namespace {

using kernels::Stat;
using MList = std::vector<std::int64_t>;

constexpr double kRel = 1e-9;  // the requirement; the measured agreement is far better

TEST(AllanPrecision, OneGOffsetOnFivePointFourMillionSamples) {
  const std::size_t n = 5'400'000;
  const double rate_hz = 1000.0, offset = 9.80665;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 1e-3);
  std::vector<double> y(n);
  for (auto& v : y)
    v = offset + g(rng);
  const auto p = kernels::phase_from_rate(y, rate_hz);

  // Reference phase in long double. The known offset is subtracted first (a constant rate is
  // a linear phase, which no statistic sees, SP1065 sec. 5.2), so the long-double sum stays
  // near its data (|X| < 1e-2) instead of growing to 5e4.
  std::vector<long double> X(n + 1, 0.0L);
  for (std::size_t k = 0; k < n; ++k)
    X[k + 1] = X[k] + (static_cast<long double>(y[k]) - offset) / rate_hz;
  const long double tau0 = 1.0L / rate_hz;

  const MList ms = {1, 10, 1000, 100000, 1000000};
  for (int si = 0; si < 7; ++si) {
    const auto s = static_cast<Stat>(si);
    const auto r = kernels::compute(s, p, ms, 2);
    ASSERT_GE(r.size(), 4u) << kernels::stat_name(s);
    for (std::size_t i = 0; i < r.size(); ++i) {
      const std::int64_t m = r.m[i];
      test::NaiveRow ref;
      switch (s) {
      case Stat::Adev:
        ref = test::naive_oadev_phase(X, m, tau0, m);
        break;
      case Stat::Oadev:
        ref = test::naive_oadev_phase(X, m, tau0, 1);
        break;
      case Stat::Mdev:
      case Stat::Tdev:
        ref = m <= 10 ? test::naive_mdev_phase(X, m, tau0)
                      : test::naive_mdev_phase_running(X, m, tau0);
        if (s == Stat::Tdev) ref.dev *= m * tau0 / std::sqrt(3.0L);
        break;
      case Stat::Hdev:
        ref = test::naive_hdev_phase(X, m, tau0, m);
        break;
      case Stat::Ohdev:
        ref = test::naive_hdev_phase(X, m, tau0, 1);
        break;
      case Stat::Totdev:
        ref = test::naive_totdev_phase(X, m, tau0);
        break;
      default:  // the first seven only; the others: test_tie.cpp, test_theo.cpp, ...
        break;
      }
      EXPECT_EQ(r.n[i], ref.n) << kernels::stat_name(s) << " m=" << m;
      EXPECT_NEAR(r.dev[i] / static_cast<double>(ref.dev), 1.0, kRel)
          << kernels::stat_name(s) << " m=" << m;
    }
  }
}

}  // namespace
}  // namespace allanlot
