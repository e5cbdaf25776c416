// PDEV against the naive long-double reference (random data, with a large offset and drift),
// properties (m = 1 is OADEV, a linear phase gives zero), thread invariance, gaps and dumb
// inputs. Stable32 has no PDEV, so there is no table to compare with.
#include "kernels/allan/parabolic.hpp"
#include "reference/naive_extended.hpp"
#include "test_extended_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace allanlot {
namespace {

using kernels::Stat;
using test::MList;

// Kernel against the long-double reference: d_j = x_j - x_{j+m} is one double subtraction of
// the phase after phase_from_phase (eps |x| relative to |d| ~ sqrt(m): <= ~1e-14 with
// |x| <= ~1e3 after the trend removal); A and B run in long double over at most 2^16 terms per
// chunk, each step adding ~eps_ld (m |d|) to A ~ m^1.5 |d|, so A drifts by <= 2^16 * 5e-20 *
// m^-0.5 < 1e-14 relative. The deviations therefore agree to ~1e-14 (measured on these data:
// <= 2.3e-16; <= 2.7e-13 with the 1e6 ramp, where the reference's own long-double cancellation
// of the ramp's m (m/2) 1e6-sized terms limits it); 1e-11 keeps a factor
// 1000 and still catches an index error (a moved term changes PDEV by ~1/M >= 1e-3).
constexpr double kNaiveRel = 1e-11;

void expect_matches_naive(const std::vector<double>& x, const MList& ms) {
  const double rate_hz = 8.0;
  const auto p = kernels::phase_from_phase(x, rate_hz, 2);
  const auto r = kernels::compute(Stat::Pdev, p, ms, 2);
  std::size_t row = 0;
  for (const std::int64_t m : ms) {
    if (m > kernels::max_m(Stat::Pdev, p.n_points())) continue;
    const auto ref = test::naive_pdev_phase(x, m, 1.0L / rate_hz);
    if (ref.n == 0) continue;
    ASSERT_LT(row, r.size()) << "m=" << m;
    EXPECT_EQ(r.m[row], m);
    EXPECT_EQ(r.n[row], ref.n) << "m=" << m;
    EXPECT_NEAR(r.dev[row] / static_cast<double>(ref.dev), 1.0, kNaiveRel) << "m=" << m;
    ++row;
  }
  EXPECT_EQ(row, r.size());
}

TEST(PdevNaive, RandomPhase) {
  expect_matches_naive(test::random_phase(2001, 51), MList{1, 2, 3, 4, 7, 50, 333, 500});
}

TEST(PdevNaive, LargeOffsetAndDriftKeepDigits) {
  expect_matches_naive(test::random_phase(1601, 52, 1e9, 1e6), MList{1, 2, 9, 100, 400});
}

TEST(PdevNaive, ChunkBoundariesOnALongRecord) {
  // 2^16-term chunks (parabolic.hpp): with 150001 points every m below has three chunks, so
  // the restart of A and B at a chunk boundary is compared as well.
  const auto x = test::random_phase(150001, 53);
  const auto p = kernels::phase_from_phase(x, 1.0, 2);
  const auto r = kernels::pdev(p, MList{2, 17}, 2);
  ASSERT_EQ(r.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto ref = test::naive_pdev_phase(x, r.m[i], 1.0L);
    EXPECT_EQ(r.n[i], ref.n);
    EXPECT_NEAR(r.dev[i] / static_cast<double>(ref.dev), 1.0, kNaiveRel) << "m=" << r.m[i];
  }
}

TEST(PdevProperties, OadevAtOneAndZeroForLinearPhase) {
  const auto p = kernels::phase_from_phase(test::random_phase(3001, 54), 1.0, 1);
  EXPECT_EQ(kernels::pdev(p, MList{1}).dev, kernels::compute(Stat::Oadev, p, MList{1}).dev);
  // The weights (m-1)/2 - k sum to zero, so a linear phase gives exactly nothing at m >= 2.
  kernels::PhaseData lin;
  for (int k = 0; k < 1000; ++k)
    lin.x.push_back(0.5 + 0.25 * k);
  for (const double d : kernels::pdev(lin, MList{2, 3, 10, 200}).dev)
    EXPECT_EQ(d, 0.0);
}

TEST(PdevProperties, BitIdenticalForAnyThreadCount) {
  const auto p = kernels::phase_from_phase(test::random_phase(400001, 55), 10.0, 1);
  test::expect_thread_invariant(Stat::Pdev, p, MList{1, 2, 3, 64, 1000, 70000, 100000});
}

TEST(PdevGaps, Refused) {
  auto x = test::random_phase(300, 56);
  x[10] = std::nan("");
  EXPECT_FALSE(kernels::supports_gaps(Stat::Pdev));
  EXPECT_THROW(kernels::compute(Stat::Pdev, kernels::phase_from_phase(x, 1.0), MList{2}),
               std::invalid_argument);
}

TEST(PdevDumbInputs, TinyRecordsAndBadM) {
  for (const std::size_t n : {3u, 4u, 5u}) {
    const auto p = kernels::phase_from_phase(test::random_phase(n, 57), 1.0);
    const auto r = kernels::pdev(p, MList{1, 2, 3, 1000});
    for (std::size_t i = 0; i < r.size(); ++i) {
      EXPECT_TRUE(std::isfinite(r.dev[i]));
      EXPECT_GE(r.n[i], 1);
    }
    EXPECT_THROW(kernels::pdev(p, MList{0}), std::invalid_argument);
  }
}

}  // namespace
}  // namespace allanlot
