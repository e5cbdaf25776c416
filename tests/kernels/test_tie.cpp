// MTIE and TIE rms against Stable32 (PHASE.DAT), the naive long-double reference (random data
// with a frequency offset, a large drift and gaps), theory (linear phase, white FM), thread
// invariance and dumb inputs.
#include "kernels/allan/tie.hpp"
#include "reference/naive_extended.hpp"
#include "test_extended_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace allanlot {
namespace {

using kernels::Stat;
using test::MList;

// Kernels against the long-double reference: the kernel reads the phase after
// phase_from_phase (the increments integrated again in long double and rounded once to
// double, |error| <= eps |x|) plus the offset k tau0 mean_rate (one more rounding of a number
// of the size of the recorded phase), so each value is within a few eps max|x_raw| of the
// reference's. MTIE is a difference of two such values and TIE rms an rms of such
// differences, of the size m |rate| + the noise, so the relative error is a few eps
// max|x_raw| / (m |rate|) <= ~1e-12 for the data below (max|x_raw| <= 3e9 with the 1e6 ramp,
// m |rate| >= 1e6); measured on these data: <= 5.1e-15. 1e-10 still catches any index error, which
// moves a value by at least one noise sample (~1e-6 relative at the largest ramp).
constexpr double kNaiveRel = 1e-10;

TEST(TimeErrorStable32, PhaseDatMtieAndTierms) {
  const auto p = test::phase_dat();
  // MTIE's "Fast" run at m = 2^k - 1, every row; TIE rms at every m of its all-tau run.
  const auto mtie =
      test::compare_with_table(Stat::Mtie, p, "stable32/phasedat/phase_dat_mtie.txt", false);
  EXPECT_EQ(mtie.rows, 9);
  EXPECT_EQ(mtie.rows_within, mtie.rows);
  const auto tie =
      test::compare_with_table(Stat::Tierms, p, "stable32/phasedat/phase_dat_tierms.txt", false);
  EXPECT_EQ(tie.rows, 139);
  EXPECT_EQ(tie.rows_within, tie.rows);
  RecordProperty("stable32_rows", mtie.rows + tie.rows);
}

void expect_matches_naive(const std::vector<double>& x, const MList& ms, bool gapped) {
  const auto p = kernels::phase_from_phase(x, 4.0, 2);
  EXPECT_EQ(p.has_gaps(), gapped);
  for (const Stat s : {Stat::Mtie, Stat::Tierms}) {
    const auto r = kernels::compute(s, p, ms, 2);
    std::size_t row = 0;
    for (const std::int64_t m : ms) {
      const auto ref =
          s == Stat::Mtie ? test::naive_mtie_phase(x, m) : test::naive_tierms_phase(x, m);
      if (ref.n == 0 || m > kernels::max_m(s, p.n_points())) continue;
      ASSERT_LT(row, r.size()) << kernels::stat_name(s) << " m=" << m;
      EXPECT_EQ(r.m[row], m);
      EXPECT_EQ(r.n[row], ref.n) << kernels::stat_name(s) << " m=" << m;
      // tau in s: tau0 = 1/4 s; the deviations in phase units.
      EXPECT_DOUBLE_EQ(r.tau_s[row], 0.25 * static_cast<double>(m));
      EXPECT_NEAR(r.dev[row] / static_cast<double>(ref.dev), 1.0, kNaiveRel)
          << kernels::stat_name(s) << " m=" << m;
      ++row;
    }
    EXPECT_EQ(row, r.size()) << kernels::stat_name(s);
  }
}

TEST(TimeErrorNaive, RandomPhaseWithFrequencyOffset) {
  expect_matches_naive(test::random_phase(3001, 7), MList{1, 2, 3, 7, 30, 255, 700, 2999}, false);
}

TEST(TimeErrorNaive, LargeOffsetAndDriftKeepDigits) {
  // 1e9 phase offset and a 1e6-per-sample frequency offset: phase_from_phase removes both, the
  // kernels add the frequency offset back (tie.hpp), the reference never removes them.
  expect_matches_naive(test::random_phase(3001, 8, 1e9, 1e6), MList{1, 4, 60, 750}, false);
}

TEST(TimeErrorGaps, WindowsTouchingAGapAreLeftOut) {
  auto x = test::random_phase(2000, 9);
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<std::size_t> pick(0, x.size() - 1);
  for (int k = 0; k < 8; ++k)
    x[pick(rng)] = std::nan("");
  for (std::size_t i = 1200; i < 1230; ++i)
    x[i] = std::nan("");
  expect_matches_naive(x, MList{1, 2, 5, 17, 100, 400}, true);
  EXPECT_TRUE(kernels::supports_gaps(Stat::Mtie));
  EXPECT_TRUE(kernels::supports_gaps(Stat::Tierms));
}

TEST(TimeErrorProperties, LinearPhaseAndWhiteFm) {
  // A linear phase of slope 0.25 per sample: MTIE = TIE rms = 0.25 m exactly (the kernels add
  // the removed frequency offset back).
  std::vector<double> ramp(500);
  for (std::size_t i = 0; i < ramp.size(); ++i)
    ramp[i] = 3.0 + 0.25 * static_cast<double>(i);
  const auto lin = kernels::phase_from_phase(ramp, 1.0, 1);
  for (const Stat s : {Stat::Mtie, Stat::Tierms}) {
    const auto r = kernels::compute(s, lin, MList{1, 8, 100});
    ASSERT_EQ(r.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i)
      EXPECT_NEAR(r.dev[i], 0.25 * static_cast<double>(r.m[i]), 1e-12);
  }
  // White FM of unit variance at tau0 = 1 s: x_{i+m} - x_i is a sum of m independent unit
  // normals, so TIE rms = sqrt(m) (SP1065 sec. 5.2.16 with sigma_y = 1). With 2e5 pairs the
  // mean square has a relative standard error of sqrt(2/2e5) ~ 0.3 % at m = 1 and ~ 3 % at
  // m = 1000 (correlated pairs: sqrt(2 m / n)); 0.1 relative on the deviation is > 3 sigma.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(200000);
  for (auto& v : y)
    v = g(rng);
  const auto p = kernels::phase_from_rate(y, 1.0, 1);
  const auto r = kernels::compute(Stat::Tierms, p, MList{1, 10, 1000});
  ASSERT_EQ(r.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_NEAR(r.dev[i] / std::sqrt(static_cast<double>(r.m[i])), 1.0, 0.1);
}

TEST(TimeErrorProperties, BitIdenticalForAnyThreadCount) {
  const auto p = kernels::phase_from_phase(test::random_phase(300001, 4), 100.0, 1);
  const auto ms = MList{1, 3, 7, 63, 1000, 65535, 70000, 150000};
  for (const Stat s : {Stat::Mtie, Stat::Tierms})
    test::expect_thread_invariant(s, p, ms);
}

TEST(TimeErrorDumbInputs, TinyRecordsAndBadM) {
  const auto p = kernels::phase_from_phase(std::vector<double>{1.0, 2.0, 4.0}, 1.0);
  for (const Stat s : {Stat::Mtie, Stat::Tierms}) {
    const auto r = kernels::compute(s, p, MList{1, 2, 1000});
    for (std::size_t i = 0; i < r.size(); ++i)
      EXPECT_TRUE(std::isfinite(r.dev[i]));
    EXPECT_THROW(kernels::compute(s, p, MList{0}), std::invalid_argument);
    EXPECT_EQ(kernels::compute(s, p, MList{}).size(), 0u);
  }
  // m beyond the record: no row from the functions themselves either.
  EXPECT_EQ(kernels::mtie(p, MList{3, 1 << 30}).size(), 0u);
  EXPECT_EQ(kernels::tierms(p, MList{3, 1 << 30}).size(), 0u);
  EXPECT_THROW(kernels::mtie(p, MList{-1}), std::invalid_argument);
  // No interval: edf, dev_lo and dev_hi are NaN, the level is recorded.
  auto r = kernels::compute(Stat::Mtie, test::phase_dat(), MList{1, 3, 7});
  kernels::add_confidence(Stat::Mtie, test::phase_dat(), r);
  ASSERT_EQ(r.edf.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(std::isnan(r.edf[i]));
    EXPECT_TRUE(std::isnan(r.dev_lo[i]));
    EXPECT_TRUE(std::isnan(r.dev_hi[i]));
  }
}

}  // namespace
}  // namespace allanlot
