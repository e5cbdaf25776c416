// Confidence intervals and noise identification against Stable32 1.60 (every table of
// tests/data/stable32 that prints Alpha or Min/Max Sigma), thread invariance, gaps and
// dumb inputs.
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "kernels/uncertainty/noise_id.hpp"
#include "reference/stable32.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <string>

namespace allanlot {
namespace {

using kernels::Stat;

// Stable32 prints 5 significant digits; its bounds agree with the exact chi-square bounds of
// our edf within 4e-4 (3e-4 where edf > 100, where Stable32's intervals are consistently a
// little narrower). The required tolerance is 1 %.
constexpr double kBoundRel = 0.01;
// What the implementation actually achieves on these tables (worst 6.8e-4, TOTDEV m = 256),
// checked as well so that a regression well inside 1 % is still noticed.
constexpr double kBoundRelAchieved = 1e-3;

// The only rows whose alpha differs from Stable32's. PHASE.DAT TOTDEV octave run, m = 128 and
// 256: Stable32 prints 0, the B1 ratio gives 1 at m = 128 (s^2/AVAR = 0.695, boundary 0.817)
// and m = 256 keeps it. The all-tau TOTDEV run is matched at all 185 rows with the same rule
// (B1 computed up to m = 250, e.g. 0 at m = 149 between 1 at 146 and 152), so the octave
// run's 0 at m = 128 is not explained by the B1 ratio, by keeping the previous alpha (which
// would contradict m = 149) or by the lag-1 method (1 at m = 128 as well); no rule found fits
// both runs. The check below requires exactly these mismatches, so that any change shows.
struct KnownMismatch {
  const char* file;
  std::int64_t m;
};
constexpr KnownMismatch kKnownAlphaMismatch[] = {
    {"phasedat/phase_dat_totdev_octave.txt", 128},
    {"phasedat/phase_dat_totdev_octave.txt", 256},
};

bool known_mismatch(const char* file, std::int64_t m) {
  for (const auto& k : kKnownAlphaMismatch)
    if (std::string(k.file) == file && k.m == m) return true;
  return false;
}

struct Table {
  const char* file;
  Stat stat;
  bool phase_input;  // PHASE.DAT (phase) or pink_frequency (fractional frequency)
  double tau0_s;
  bool check_alpha;  // false where Stable32's alpha was fixed by the user (see below)
  const char* phase_file = nullptr;  // phase data other than PHASE.DAT, under stable32/
};

kernels::PhaseData load(const Table& t) {
  if (t.phase_file)
    return kernels::phase_from_phase(test::read_column(std::string("stable32/") + t.phase_file),
                                     1.0 / t.tau0_s, 1);
  if (t.phase_input)
    return kernels::phase_from_phase(test::read_column("stable32/phasedat/PHASE.DAT"),
                                     1.0 / t.tau0_s, 1);
  return kernels::phase_from_rate(test::read_column("stable32/pink_frequency/pink_frequency.txt"),
                                  1.0 / t.tau0_s, 1);
}

// Our rows for the table's m values: kernels::compute, whose m, n and dev must agree with the
// table (n decides the edf and the B1 test, dev scales the bounds).
kernels::StatResult our_rows(const Table& t, const kernels::PhaseData& p,
                             const std::vector<test::Stable32Row>& rows) {
  std::vector<std::int64_t> ms;
  for (const auto& row : rows)
    ms.push_back(row.m);
  auto r = kernels::compute(t.stat, p, ms, 1);
  EXPECT_EQ(r.size(), rows.size()) << t.file;
  return r;
}

struct Summary {
  int rows = 0, bounds = 0, alpha_checked = 0, alpha_mismatch = 0;
  double worst = 0.0;
};

Summary check_table(const Table& t) {
  Summary sum;
  const auto rows = test::read_stable32(std::string("stable32/") + t.file);
  EXPECT_FALSE(rows.empty()) << t.file;
  const auto p = load(t);
  auto r = our_rows(t, p, rows);
  if (r.size() != rows.size()) return sum;
  kernels::add_confidence(t.stat, p, r, 0.683, 2);
  EXPECT_EQ(r.confidence, 0.683);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    ++sum.rows;
    EXPECT_EQ(r.m[i], row.m) << t.file;
    EXPECT_EQ(r.n[i], row.n) << t.file << " m=" << row.m;
    EXPECT_NEAR(r.dev[i] / row.sigma, 1.0, 1e-4) << t.file << " m=" << row.m;
    EXPECT_LT(r.dev_lo[i], r.dev[i]);
    EXPECT_GT(r.dev_hi[i], r.dev[i]);
    if (t.check_alpha) {
      ++sum.alpha_checked;
      if (r.alpha[i] != row.alpha) ++sum.alpha_mismatch;
      if (known_mismatch(t.file, row.m))
        EXPECT_NE(r.alpha[i], row.alpha) << t.file << " m=" << row.m << " now matches";
      else
        EXPECT_EQ(r.alpha[i], row.alpha) << t.file << " m=" << row.m;
    }
    if (row.min_sigma == 0.0 && row.max_sigma == 0.0) continue;  // all-tau runs print 0
    ++sum.bounds;
    // Compare the bounds relative to Stable32's own Sigma so that the small difference
    // between its printed Sigma and ours does not count twice.
    // Where the identified alpha differs from Stable32's (kKnownAlphaMismatch), the bounds are
    // those of Stable32's alpha: an interval of another noise type cannot match.
    kernels::Interval ours{r.dev_lo[i], r.dev_hi[i]};
    if (known_mismatch(t.file, row.m))
      ours = kernels::chi2_interval(
          r.dev[i], kernels::stat_edf(t.stat, row.alpha, row.m, p.n_points(), r.n[i]), 0.683);
    const double lo = ours.lo / r.dev[i] * row.sigma;
    const double hi = ours.hi / r.dev[i] * row.sigma;
    const double e_lo = std::fabs(lo / row.min_sigma - 1.0);
    const double e_hi = std::fabs(hi / row.max_sigma - 1.0);
    sum.worst = std::max({sum.worst, e_lo, e_hi});
    EXPECT_LT(e_lo, kBoundRel) << t.file << " m=" << row.m << " lo " << lo << " vs "
                               << row.min_sigma;
    EXPECT_LT(e_hi, kBoundRel) << t.file << " m=" << row.m << " hi " << hi << " vs "
                               << row.max_sigma;
    EXPECT_LT(e_lo, kBoundRelAchieved) << t.file << " m=" << row.m;
    EXPECT_LT(e_hi, kBoundRelAchieved) << t.file << " m=" << row.m;
  }
  std::printf("%-40s rows %3d  bounds %2d  worst bound rel. err %.1e  alpha %3d/%3d equal\n",
              t.file, sum.rows, sum.bounds, sum.worst, sum.alpha_checked - sum.alpha_mismatch,
              sum.alpha_checked);
  return sum;
}

// Every Stable32 table of an implemented statistic that prints Alpha or Min/Max Sigma.
// pink_frequency/totdev_alpha0.txt prints alpha 0 at every m, including m = 1 and 2 where the
// same data give -1 and -2 in each of the other six tables (which agree with each other and
// with the lag-1 method); as its name says, that run had alpha fixed to 0 by the user, a
// Stable32 option add_confidence does not have, so only its deviations and n are checked.
const Table kTables[] = {
    {"phasedat/phase_dat_adev_octave.txt", Stat::Adev, true, 1.0, true},
    {"phasedat/phase_dat_oadev_octave.txt", Stat::Oadev, true, 1.0, true},
    {"phasedat/phase_dat_mdev_octave.txt", Stat::Mdev, true, 1.0, true},
    {"phasedat/phase_dat_tdev_octave.txt", Stat::Tdev, true, 1.0, true},
    {"phasedat/phase_dat_hdev_octave.txt", Stat::Hdev, true, 1.0, true},
    {"phasedat/phase_dat_ohdev_octave.txt", Stat::Ohdev, true, 1.0, true},
    {"phasedat/phase_dat_totdev_octave.txt", Stat::Totdev, true, 1.0, true},
    {"phasedat/phase_dat_adev.txt", Stat::Adev, true, 1.0, true},
    {"phasedat/phase_dat_oadev.txt", Stat::Oadev, true, 1.0, true},
    {"phasedat/phase_dat_mdev.txt", Stat::Mdev, true, 1.0, true},
    {"phasedat/phase_dat_tdev.txt", Stat::Tdev, true, 1.0, true},
    {"phasedat/phase_dat_hdev.txt", Stat::Hdev, true, 1.0, true},
    {"phasedat/phase_dat_ohdev.txt", Stat::Ohdev, true, 1.0, true},
    {"phasedat/phase_dat_totdev.txt", Stat::Totdev, true, 1.0, true},
    {"pink_frequency/s32_oadev_octave.txt", Stat::Oadev, false, 1.0, true},
    {"pink_frequency/adev.txt", Stat::Adev, false, 42.0, true},
    {"pink_frequency/oadev.txt", Stat::Oadev, false, 42.0, true},
    {"pink_frequency/mdev.txt", Stat::Mdev, false, 42.0, true},
    {"pink_frequency/tdev.txt", Stat::Tdev, false, 42.0, true},
    {"pink_frequency/hdev.txt", Stat::Hdev, false, 42.0, true},
    {"pink_frequency/ohdev.txt", Stat::Ohdev, false, 42.0, true},
    {"pink_frequency/totdev_alpha0.txt", Stat::Totdev, false, 42.0, false},
    // A time-interval counter's noise floor: white PM to m = 1024, then flicker PM, where
    // TOTDEV's edf is SP1065's simple formula (kernels/uncertainty/edf.hpp edf_totvar), not
    // Howe's white FM fit (bounds 12 % and 34 % off before).
    {"tic/tic_totdev.txt", Stat::Totdev, true, 1.0, true, "tic/tic_phase.txt"},
};

class Stable32Tables : public ::testing::TestWithParam<Table> {};

TEST_P(Stable32Tables, BoundsAndAlphaMatch) {
  const Summary s = check_table(GetParam());
  EXPECT_GT(s.rows, 0);
}

INSTANTIATE_TEST_SUITE_P(All, Stable32Tables, ::testing::ValuesIn(kTables),
                         [](const ::testing::TestParamInfo<Table>& param) {
                           std::string name = param.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// The pink_frequency octave run (tau0 = 1 s) prints alpha -1 at m = 1, -2 at m = 2..32 and 0
// from m = 64: the simulated "pink" data are flicker FM only up to m ~ 50 (OADEV is flat there
// and falls as tau^-1/2 beyond), and at m >= 2 its m-sample averages decorrelate more slowly
// than flicker FM (lag-1 delta of the differenced averages above -0.25). The lag-1 estimates
// themselves show it.
TEST(NoiseId, PinkFrequencyLag1Path) {
  const auto p = load(Table{"pink_frequency/s32_oadev_octave.txt", Stat::Oadev, false, 1.0, true});
  const kernels::Lag1Estimate e1 = kernels::noise_id_lag1(p, 1, 2);
  EXPECT_EQ(e1.alpha, -1);
  EXPECT_EQ(e1.d, 2);  // phase and its first difference are both non-stationary
  for (const std::int64_t m : {2, 4, 8, 16, 32}) {
    const auto e = kernels::noise_id_lag1(p, m, 2);
    EXPECT_EQ(e.alpha, -2) << m;
    EXPECT_GT(e.delta, -0.25) << m;
  }
  for (const std::int64_t m : {64, 128, 256}) {
    const auto e = kernels::noise_id_lag1(p, m, 2);
    EXPECT_EQ(e.alpha, 0) << m;
    EXPECT_EQ(e.d, 1) << m;
  }
}

TEST(NoiseId, Lag1AutocorrelationOfSimpleSeries) {
  // Alternating +-1 over n points: mean 0 (n even), sum of products -(n-1), sum of squares n:
  // r1 = (n-1)/n * (-(n-1)/n).
  const std::vector<double> alt = {1, -1, 1, -1, 1, -1};
  EXPECT_NEAR(kernels::lag1_autocorrelation(alt), -(5.0 / 6.0) * (5.0 / 6.0), 1e-15);
  const std::vector<double> constant = {2, 2, 2};
  EXPECT_EQ(kernels::lag1_autocorrelation(constant), 0.0);
  // A NaN drops its two pairs and itself: {1, NaN, 1, -1} leaves values {1, 1, -1}, mean 1/3,
  // one pair (1, -1).
  const std::vector<double> gap = {1, std::nan(""), 1, -1};
  const double mean = 1.0 / 3.0;
  const double num = (1 - mean) * (-1 - mean);
  const double den = 2 * (1 - mean) * (1 - mean) + (-1 - mean) * (-1 - mean);
  EXPECT_NEAR(kernels::lag1_autocorrelation(gap), (2.0 / 3.0) * num / den, 1e-15);
}

TEST(NoiseId, B1AndRnBoundaries) {
  // White FM: B1 = 1 for any N; random walk FM: N/2 (Barnes); flicker: N ln N/(2(N-1) ln 2).
  EXPECT_NEAR(kernels::b1_expected(20, -1), 1.0, 1e-15);
  EXPECT_NEAR(kernels::b1_expected(20, 1), 10.0, 1e-12);
  EXPECT_NEAR(kernels::b1_expected(20, 0), 20 * std::log(20.0) / (38 * std::log(2.0)), 1e-12);
  EXPECT_NEAR(kernels::b1_expected(20, -2), (400.0 - 1) / (1.5 * 20 * 19), 1e-12);
  for (const int alpha : {-2, -1, 0}) {
    const int mu = -alpha - 1;
    EXPECT_EQ(kernels::alpha_from_b1(kernels::b1_expected(25, mu), 25), alpha);
  }
  EXPECT_EQ(kernels::alpha_from_b1(kernels::b1_expected(25, -2), 25), 1);
  EXPECT_EQ(kernels::alpha_from_rn(kernels::rn_expected(50, 1), 50), 1);
  EXPECT_EQ(kernels::alpha_from_rn(kernels::rn_expected(50, 2), 50), 2);
}

TEST(Confidence, IntervalOrientationAndKnownValue) {
  // edf = 2, where the chi-square p-quantile is -2 ln(1 - p): the lower bound uses the larger
  // quantile (p = (1 + c)/2), the upper bound the smaller one.
  const double c = 0.9;
  const auto ci = kernels::chi2_interval(3.0, 2.0, c);
  EXPECT_NEAR(ci.lo, 3.0 * std::sqrt(2.0 / (-2.0 * std::log(1.0 - 0.95))), 1e-12);
  EXPECT_NEAR(ci.hi, 3.0 * std::sqrt(2.0 / (-2.0 * std::log(1.0 - 0.05))), 1e-12);
  for (const double edf : {0.3, 1.0, 4.5, 100.0, 1e6}) {
    const auto b = kernels::chi2_interval(1.0, edf, 0.683);
    EXPECT_LT(b.lo, 1.0) << edf;
    EXPECT_GT(b.hi, 1.0) << edf;
  }
  // Wider confidence, wider interval.
  const auto narrow = kernels::chi2_interval(1.0, 10.0, 0.5);
  const auto wide = kernels::chi2_interval(1.0, 10.0, 0.95);
  EXPECT_LT(wide.lo, narrow.lo);
  EXPECT_GT(wide.hi, narrow.hi);
}

std::vector<double> white(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  for (auto& v : y)
    v = g(rng);
  return y;
}

TEST(Confidence, BitIdenticalForAnyThreadCount) {
  auto y = white(50001, 9);
  double walk = 0.0;
  for (auto& v : y) {
    walk += 0.01 * v;
    v += walk;
  }
  const auto p = kernels::phase_from_rate(y, 10.0, 1);
  std::vector<std::int64_t> ms;
  for (std::int64_t m = 1; m <= 12000; m = m * 3 / 2 + 1)
    ms.push_back(m);
  for (const Stat s : {Stat::Oadev, Stat::Adev}) {
    auto r1 = kernels::compute(s, p, ms, 1);
    kernels::add_confidence(s, p, r1, 0.9, 1);
    for (const int nt : {2, 7}) {
      auto rn = kernels::compute(s, p, ms, nt);
      kernels::add_confidence(s, p, rn, 0.9, nt);
      EXPECT_EQ(r1.alpha, rn.alpha) << nt;
      EXPECT_EQ(r1.edf, rn.edf) << nt;
      EXPECT_EQ(r1.dev_lo, rn.dev_lo) << nt;
      EXPECT_EQ(r1.dev_hi, rn.dev_hi) << nt;
    }
  }
}

// One Lag1Cache shared by every statistic of a record (as analyze does) changes no alpha, edf or
// bound, at any thread count; and an estimate read back from it is noise_id_lag1's.
TEST(Confidence, SharedNoiseIdCacheChangesNothing) {
  auto y = white(40001, 13);
  double walk = 0.0;
  for (auto& v : y) {
    walk += 0.02 * v;
    v += walk;
  }
  const auto p = kernels::phase_from_rate(y, 10.0, 1);
  const std::vector<std::int64_t> ms{1, 2, 3, 5, 8, 13, 21, 34, 55, 89, 144, 233, 377, 610, 987};
  for (const int nt : {1, 2}) {
    kernels::Lag1Cache cache;
    for (const Stat s :
         {Stat::Oadev, Stat::Mdev, Stat::Tdev, Stat::Hdev, Stat::Ohdev, Stat::Totdev}) {
      SCOPED_TRACE(std::string(kernels::stat_name(s)) + ", threads " + std::to_string(nt));
      auto plain = kernels::compute(s, p, ms, nt);
      auto shared = plain;
      kernels::add_confidence(s, p, plain, 0.683, nt);
      kernels::add_confidence(s, p, shared, 0.683, nt, &cache);
      EXPECT_EQ(plain.alpha, shared.alpha);
      EXPECT_EQ(plain.edf, shared.edf);
      EXPECT_EQ(plain.dev_lo, shared.dev_lo);
      EXPECT_EQ(plain.dev_hi, shared.dev_hi);
    }
    const auto e = cache.get(p, 21, 2);
    const auto direct = kernels::noise_id_lag1(p, 21, 2);
    EXPECT_EQ(e.alpha, direct.alpha);
    EXPECT_EQ(e.d, direct.d);
    EXPECT_EQ(e.delta, direct.delta);
  }
}

// Gap-free records evaluate the differencing levels on the fly from the phase; records with
// a gap index store each level (the path noise_id_lag1 always took). The same phase with an
// all-zero gap index takes the stored path: both must give the same bits, for every level a
// random walk, flicker-like and white mixture reaches, with dmax 2 and 3, directly and through
// a cache that answers dmax 2 from a dmax 3 run and the reverse.
TEST(NoiseId, OnTheFlyLevelsEqualStoredLevels) {
  std::mt19937_64 rng(31);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(30001);
  double walk = 0.0, walk2 = 0.0;
  for (auto& v : y) {
    walk += 0.02 * g(rng);
    walk2 += 0.001 * walk;
    v = g(rng) + walk + walk2;
  }
  const auto fly = kernels::phase_from_rate(y, 10.0, 1);
  kernels::PhaseData stored = fly;
  stored.gaps.assign(fly.x.size(), 0);
  ASSERT_FALSE(fly.has_gaps());
  ASSERT_TRUE(stored.has_gaps());
  std::set<int> levels;
  kernels::Lag1Cache cache3_first, cache2_first;
  for (const std::int64_t m : {1, 2, 3, 7, 50, 333, 1000}) {
    for (const int dmax : {2, 3}) {
      const auto a = kernels::noise_id_lag1(fly, m, dmax);
      const auto b = kernels::noise_id_lag1(stored, m, dmax);
      EXPECT_EQ(a.delta, b.delta) << "m " << m << " dmax " << dmax;
      EXPECT_EQ(a.d, b.d) << "m " << m << " dmax " << dmax;
      EXPECT_EQ(a.alpha, b.alpha) << "m " << m << " dmax " << dmax;
      levels.insert(a.d);
    }
    for (const int dmax : {3, 2}) {
      const auto e = cache3_first.get(fly, m, dmax);
      EXPECT_EQ(e.delta, kernels::noise_id_lag1(fly, m, dmax).delta) << m << " " << dmax;
      EXPECT_EQ(e.d, kernels::noise_id_lag1(fly, m, dmax).d) << m << " " << dmax;
    }
    for (const int dmax : {2, 3}) {
      const auto e = cache2_first.get(fly, m, dmax);
      EXPECT_EQ(e.delta, kernels::noise_id_lag1(fly, m, dmax).delta) << m << " " << dmax;
      EXPECT_EQ(e.d, kernels::noise_id_lag1(fly, m, dmax).d) << m << " " << dmax;
    }
  }
  // The multi-m sweep (Lag1Cache::prefetch) for all m at once gives the same bits as each m
  // alone, for dmax 3 and then dmax 2 read from it, and for dmax 2 swept first then dmax 3.
  const std::vector<std::int64_t> all_m = {1, 2, 3, 7, 50, 333, 1000};
  for (const int first : {3, 2}) {
    kernels::Lag1Cache swept;
    swept.prefetch(fly, all_m, first, first == 3 ? 1 : 3);  // thread counts 1 and 3
    swept.prefetch(fly, all_m, 5 - first, 2);
    for (const std::int64_t m : all_m)
      for (const int dmax : {2, 3}) {
        const auto e = swept.get(fly, m, dmax);
        const auto direct = kernels::noise_id_lag1(fly, m, dmax);
        EXPECT_EQ(e.delta, direct.delta) << "swept, m " << m << " dmax " << dmax;
        EXPECT_EQ(e.d, direct.d) << "swept, m " << m << " dmax " << dmax;
      }
  }
  // The data reach the deeper levels, so the test covers them.
  EXPECT_GE(levels.size(), 2u);
  EXPECT_TRUE(levels.count(2) || levels.count(3));
}

TEST(Confidence, GapsReduceEdfAndKeepIntervalsValid) {
  auto y = white(20000, 21);
  const auto clean = kernels::phase_from_rate(y, 1.0, 1);
  for (std::size_t k = 5000; k < 9000; ++k)  // one long gap: 20 % of the record
    y[k] = std::nan("");
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<std::size_t> pick(0, y.size() - 1);
  for (int k = 0; k < 40; ++k)
    y[pick(rng)] = std::nan("");
  const auto gapped = kernels::phase_from_rate(y, 1.0, 1);
  ASSERT_TRUE(gapped.has_gaps());
  const std::vector<std::int64_t> ms = {1, 2, 4, 16, 64, 256};
  for (const Stat s : {Stat::Oadev, Stat::Mdev, Stat::Hdev}) {
    auto rc = kernels::compute(s, clean, ms, 1);
    auto rg = kernels::compute(s, gapped, ms, 1);
    ASSERT_EQ(rc.size(), rg.size());
    kernels::add_confidence(s, clean, rc);
    kernels::add_confidence(s, gapped, rg);
    for (std::size_t i = 0; i < rg.size(); ++i) {
      EXPECT_LT(rg.n[i], rc.n[i]);
      EXPECT_TRUE(std::isfinite(rg.edf[i]) && rg.edf[i] > 0.0);
      if (rg.alpha[i] == rc.alpha[i]) {
        EXPECT_LT(rg.edf[i], rc.edf[i]) << kernels::stat_name(s) << rg.m[i];
      }
      EXPECT_LT(rg.dev_lo[i], rg.dev[i]);
      EXPECT_GT(rg.dev_hi[i], rg.dev[i]);
      // White FM: the identification must not be thrown off by the gaps at short tau.
      if (rg.m[i] <= 64) {
        EXPECT_EQ(rg.alpha[i], 0) << rg.m[i];
      }
    }
  }
}

TEST(Confidence, DumbInputs) {
  const auto p = kernels::phase_from_rate(white(1000, 1), 1.0, 1);
  auto r = kernels::compute(Stat::Oadev, p, std::vector<std::int64_t>{1, 2, 4});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double c : {0.0, 1.0, -0.5, 1.5, nan})
    EXPECT_THROW(kernels::add_confidence(Stat::Oadev, p, r, c), std::invalid_argument) << c;
  EXPECT_TRUE(r.edf.empty());  // a rejected call leaves the result untouched
  auto bad = r;
  bad.n.pop_back();
  EXPECT_THROW(kernels::add_confidence(Stat::Oadev, p, bad), std::invalid_argument);
  auto unordered = r;
  std::swap(unordered.m[0], unordered.m[1]);
  EXPECT_THROW(kernels::add_confidence(Stat::Oadev, p, unordered), std::invalid_argument);
  EXPECT_THROW(kernels::chi2_interval(1.0, 0.0, 0.683), std::invalid_argument);
  EXPECT_THROW(kernels::chi2_interval(1.0, nan, 0.683), std::invalid_argument);
  // No row: nothing to do, but the confidence is recorded.
  kernels::StatResult empty;
  kernels::add_confidence(Stat::Oadev, p, empty, 0.9);
  EXPECT_EQ(empty.confidence, 0.9);
  EXPECT_TRUE(empty.alpha.empty());
  // A zero deviation (linear phase) keeps zero bounds instead of NaN.
  const std::vector<double> flat(1000, 3.0);
  const auto pf = kernels::phase_from_rate(flat, 1.0, 1);
  auto rf = kernels::compute(Stat::Oadev, pf, std::vector<std::int64_t>{1, 8});
  kernels::add_confidence(Stat::Oadev, pf, rf);
  for (std::size_t i = 0; i < rf.size(); ++i) {
    EXPECT_EQ(rf.dev_lo[i], 0.0);
    EXPECT_EQ(rf.dev_hi[i], 0.0);
    EXPECT_GT(rf.edf[i], 0.0);
  }
}

}  // namespace
}  // namespace allanlot
