// ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV and TOTDEV against Stable32 (every table in
// tests/data/stable32), NIST SP1065's NBS14 values, the naive long-double reference
// (with and without gaps); properties, thread invariance and dumb inputs.
#include "kernels/allan/allan.hpp"
#include "kernels/allan/hadamard.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/simd.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/allan/total.hpp"
#include "reference/naive_allan.hpp"
#include "reference/stable32.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>

namespace allanlot {
namespace {

using kernels::PhaseData;
using kernels::Stat;
using kernels::StatResult;
using MList = std::vector<std::int64_t>;

// Stable32 prints 5 significant digits: a correct value is within half a unit of the 5th
// digit (5e-5 relative); 1e-4 leaves room for the printed rounding.
constexpr double kStable32Rel = 1e-4;
// NBS14 values carry 7 significant digits (SP1065 pp. 107-108).
constexpr double kNbs14Rel = 1e-6;
// Kernels against the long-double reference on the data below (N <= 4000, |x| <= ~1e3 after
// the trend removal, rms second differences >= ~1): each term differs by the one rounding of
// x to double (eps max|x| / |d| ~ 1e-13, zero-mean), by its own few flops (~4 eps), by MDEV's
// fixed-point rounding (2^-(59 - 11) max|x| / |d| ~ 1e-12, zero-mean), and the blocked sum
// adds (kBlock/16 + n/kBlock) eps ~ 1e-14. The zero-mean errors shrink as 1/sqrt(n) ~ 1/50 in
// the sum, so the deviations agree to a few 1e-14 (measured: <= 1.0e-14); 1e-12 leaves a
// factor 100 for unlucky data and still catches any formula or index error, which moves a
// deviation by at least ~1/n ~ 3e-4.
constexpr double kNaiveRel = 1e-12;

const char* const kNames[] = {"adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"};

StatResult run(Stat s, const PhaseData& p, const MList& ms, int nthreads = 1) {
  switch (s) {
  case Stat::Adev:
    return kernels::adev(p, ms, nthreads);
  case Stat::Oadev:
    return kernels::oadev(p, ms, nthreads);
  case Stat::Mdev:
    return kernels::mdev(p, ms, nthreads);
  case Stat::Tdev:
    return kernels::tdev(p, ms, nthreads);
  case Stat::Hdev:
    return kernels::hdev(p, ms, nthreads);
  case Stat::Ohdev:
    return kernels::ohdev(p, ms, nthreads);
  case Stat::Totdev:
    return kernels::totdev(p, ms, nthreads);
  default:  // the statistics of test_tie.cpp, test_theo.cpp, test_total_family.cpp, ...
    break;
  }
  return {};
}

test::NaiveRow naive(Stat s, const std::vector<double>& x, std::int64_t m, long double tau0) {
  switch (s) {
  case Stat::Adev:
    return test::naive_oadev_phase(x, m, tau0, m);
  case Stat::Oadev:
    return test::naive_oadev_phase(x, m, tau0, 1);
  case Stat::Mdev:
    return test::naive_mdev_phase(x, m, tau0);
  case Stat::Tdev:
    return test::naive_tdev_phase(x, m, tau0);
  case Stat::Hdev:
    return test::naive_hdev_phase(x, m, tau0, m);
  case Stat::Ohdev:
    return test::naive_hdev_phase(x, m, tau0, 1);
  case Stat::Totdev:
    return test::naive_totdev_phase(x, m, tau0);
  default:
    break;
  }
  return {};
}

// ---------------------------------------------------------------------------------------
// Stable32

struct Stable32Case {
  const char* file;
  Stat stat;
  const char* grid;        // tau grid of the run
  std::int64_t run_m_max;  // the run's own stop when below max_m (0 = none)
};

void expect_matches_stable32(const Stable32Case& c, const PhaseData& p) {
  SCOPED_TRACE(c.file);
  const auto rows = test::read_stable32(c.file);
  ASSERT_FALSE(rows.empty());
  std::int64_t m_max = kernels::max_m(c.stat, p.n_points());
  if (c.run_m_max > 0) m_max = std::min(m_max, c.run_m_max);
  const auto ms = kernels::make_m_list(kernels::parse_tau_grid(c.grid), m_max, p.n_points());
  const auto res = kernels::compute(c.stat, p, ms, 2);
  ASSERT_EQ(res.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(res.m[i], rows[i].m) << "row " << i;
    EXPECT_EQ(res.n[i], rows[i].n) << "m=" << rows[i].m;
    EXPECT_DOUBLE_EQ(res.tau_s[i], rows[i].tau) << "m=" << rows[i].m;
    EXPECT_NEAR(res.dev[i] / rows[i].sigma, 1.0, kStable32Rel) << "m=" << rows[i].m;
  }
}

PhaseData phase_dat() {
  const auto x = test::read_column("stable32/phasedat/PHASE.DAT");
  EXPECT_EQ(x.size(), 1001u);
  return kernels::phase_from_phase(x, 1.0, 1);
}

// tau0 = 42 s for these runs (tests/data/stable32/README.md); frequency data.
PhaseData pink() {
  const auto y = test::read_column("stable32/pink_frequency/pink_frequency.txt");
  EXPECT_EQ(y.size(), 10000u);
  return kernels::phase_from_rate(y, 1.0 / 42.0, 1);
}

TEST(AllanFamilyStable32, PhaseDatAllTau) {
  const auto p = phase_dat();
  for (const Stable32Case& c : {
           Stable32Case{"stable32/phasedat/phase_dat_adev.txt", Stat::Adev, "stable32", 0},
           {"stable32/phasedat/phase_dat_oadev.txt", Stat::Oadev, "stable32", 0},
           {"stable32/phasedat/phase_dat_mdev.txt", Stat::Mdev, "stable32", 0},
           {"stable32/phasedat/phase_dat_tdev.txt", Stat::Tdev, "stable32", 0},
           {"stable32/phasedat/phase_dat_hdev.txt", Stat::Hdev, "stable32", 0},
           {"stable32/phasedat/phase_dat_ohdev.txt", Stat::Ohdev, "stable32", 0},
           // Plain TOTDEV: the Alpha column is 0 or 1 throughout, where Stable32 applies
           // no TOTVAR bias correction (it corrects only flicker and random-walk FM).
           {"stable32/phasedat/phase_dat_totdev.txt", Stat::Totdev, "stable32", 0},
       })
    expect_matches_stable32(c, p);
}

TEST(AllanFamilyStable32, PhaseDatOctave) {
  const auto p = phase_dat();
  for (const Stable32Case& c : {
           Stable32Case{"stable32/phasedat/phase_dat_adev_octave.txt", Stat::Adev, "octave", 0},
           {"stable32/phasedat/phase_dat_oadev_octave.txt", Stat::Oadev, "octave", 0},
           {"stable32/phasedat/phase_dat_mdev_octave.txt", Stat::Mdev, "octave", 0},
           {"stable32/phasedat/phase_dat_tdev_octave.txt", Stat::Tdev, "octave", 0},
           {"stable32/phasedat/phase_dat_hdev_octave.txt", Stat::Hdev, "octave", 0},
           {"stable32/phasedat/phase_dat_ohdev_octave.txt", Stat::Ohdev, "octave", 0},
           {"stable32/phasedat/phase_dat_totdev_octave.txt", Stat::Totdev, "octave", 0},
       })
    expect_matches_stable32(c, p);
}

TEST(AllanFamilyStable32, PinkFrequencyAllTau) {
  const auto p = pink();
  // The overlapping and total runs used step constant 42 and stopped at tau <= 1e5 s
  // (m <= 2380): settings of those runs, see tests/kernels/test_tau_grid_stable32.cpp.
  const std::int64_t run_stop = 100000 / 42;
  for (const Stable32Case& c : {
           Stable32Case{"stable32/pink_frequency/adev.txt", Stat::Adev, "stable32", 0},
           {"stable32/pink_frequency/hdev.txt", Stat::Hdev, "stable32", 0},
           {"stable32/pink_frequency/oadev.txt", Stat::Oadev, "stable32:42", run_stop},
           {"stable32/pink_frequency/mdev.txt", Stat::Mdev, "stable32:42", run_stop},
           {"stable32/pink_frequency/tdev.txt", Stat::Tdev, "stable32:42", run_stop},
           {"stable32/pink_frequency/ohdev.txt", Stat::Ohdev, "stable32:42", run_stop},
           // "alpha0": bias correction forced off, i.e. the plain TOTDEV.
           {"stable32/pink_frequency/totdev_alpha0.txt", Stat::Totdev, "stable32:42", run_stop},
       })
    expect_matches_stable32(c, p);
}

TEST(AllanFamilyStable32, PinkFrequencyOctaveAtOneSecond) {
  const auto y = test::read_column("stable32/pink_frequency/pink_frequency.txt");
  expect_matches_stable32(
      {"stable32/pink_frequency/s32_oadev_octave.txt", Stat::Oadev, "octave", 0},
      kernels::phase_from_rate(y, 1.0, 1));
}

// ---------------------------------------------------------------------------------------
// NBS14, SP1065 pp. 107-108

struct Nbs14Row {
  Stat stat;
  double v[3];
};

TEST(AllanFamilyNbs14, TenPointPhaseAndFrequency) {
  const Nbs14Row table[] = {
      {Stat::Adev, {91.22945, 115.8082}}, {Stat::Oadev, {91.22945, 85.95287}},
      {Stat::Mdev, {91.22945, 74.78849}}, {Stat::Totdev, {91.22945, 93.90379}},
      {Stat::Hdev, {70.80608, 116.7980}}, {Stat::Ohdev, {70.80607, 85.61487}},
      {Stat::Tdev, {52.67135, 86.35831}},
  };
  const PhaseData inputs[] = {kernels::phase_from_phase(test::nbs14_10_phase(), 1.0),
                              kernels::phase_from_rate(test::nbs14_10_freq(), 1.0)};
  for (const auto& p : inputs)
    for (const auto& row : table) {
      const auto r = run(row.stat, p, MList{1, 2});
      ASSERT_EQ(r.size(), 2u) << kNames[static_cast<int>(row.stat)];
      for (int i = 0; i < 2; ++i)
        EXPECT_NEAR(r.dev[static_cast<std::size_t>(i)] / row.v[i], 1.0, kNbs14Rel)
            << kNames[static_cast<int>(row.stat)] << " m=" << i + 1;
    }
}

TEST(AllanFamilyNbs14, ThousandPoint) {
  const Nbs14Row table[] = {
      {Stat::Adev, {2.922319e-01, 9.965736e-02, 3.897804e-02}},
      {Stat::Oadev, {2.922319e-01, 9.159953e-02, 3.241343e-02}},
      {Stat::Mdev, {2.922319e-01, 6.172376e-02, 2.170921e-02}},
      {Stat::Totdev, {2.922319e-01, 9.134743e-02, 3.406530e-02}},
      {Stat::Hdev, {2.943883e-01, 1.052754e-01, 3.910860e-02}},
      {Stat::Ohdev, {2.943883e-01, 9.581083e-02, 3.237638e-02}},
      {Stat::Tdev, {1.687202e-01, 3.563623e-01, 1.253382e+00}},
  };
  const auto p = kernels::phase_from_rate(test::nbs14_1000_freq(), 1.0);
  for (const auto& row : table) {
    const auto r = run(row.stat, p, MList{1, 10, 100}, 2);
    ASSERT_EQ(r.size(), 3u);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(r.dev[static_cast<std::size_t>(i)] / row.v[i], 1.0, kNbs14Rel)
          << kNames[static_cast<int>(row.stat)] << " m=" << r.m[static_cast<std::size_t>(i)];
  }
}

// ---------------------------------------------------------------------------------------
// Naive long-double reference

// White phase plus white and random-walk rate: every power law a statistic must follow.
std::vector<double> random_phase(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double phase = 5.0, rate = 0.3, walk = 0.0;
  for (auto& v : x) {
    walk += 0.01 * g(rng);
    phase += rate + g(rng) + walk;
    v = phase + 0.5 * g(rng);
  }
  return x;
}

void expect_matches_naive(const std::vector<double>& x, const MList& ms, bool gapped) {
  const double rate_hz = 4.0;
  const auto p = kernels::phase_from_phase(x, rate_hz, 2);
  EXPECT_EQ(p.has_gaps(), gapped);
  for (int si = 0; si < 7; ++si) {
    const auto s = static_cast<Stat>(si);
    if (gapped && s == Stat::Totdev) continue;  // throws: see Gaps.TotdevRefuses
    const auto r = run(s, p, ms, 2);
    std::size_t row = 0;
    for (const std::int64_t m : ms) {
      if (s == Stat::Totdev && 2 * m > p.n_points() - 1) continue;  // beyond its range
      const auto ref = naive(s, x, m, 1.0L / rate_hz);
      if (ref.n == 0) continue;  // no row expected
      ASSERT_LT(row, r.size()) << kNames[si] << " m=" << m;
      EXPECT_EQ(r.m[row], m) << kNames[si];
      EXPECT_EQ(r.n[row], ref.n) << kNames[si] << " m=" << m;
      EXPECT_NEAR(r.dev[row] / static_cast<double>(ref.dev), 1.0, kNaiveRel)
          << kNames[si] << " m=" << m;
      ++row;
    }
    EXPECT_EQ(row, r.size()) << kNames[si];
  }
}

TEST(AllanFamilyNaive, RandomPhaseEveryStatistic) {
  const auto x = random_phase(4001, 17);
  expect_matches_naive(x, MList{1, 2, 3, 5, 8, 13, 50, 199, 333, 666, 1000, 1333, 1999, 2000},
                       false);
}

TEST(AllanFamilyNaive, LargeMeanRateKeepsDigits) {
  // A phase ramp of 1e6 per sample: phase_from_phase removes it exactly (SP1065 sec. 5.2),
  // the naive reference sees it and cancels it in long double.
  auto x = random_phase(3001, 23);
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] += 1e6 * static_cast<double>(i);
  expect_matches_naive(x, MList{1, 4, 30, 250, 750}, false);
}

// ---------------------------------------------------------------------------------------
// Gaps

std::vector<double> with_random_gaps(std::vector<double> x, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, x.size() - 1);
  for (int k = 0; k < count; ++k)
    x[pick(rng)] = std::nan("");
  // A run of missing points too.
  for (std::size_t i = 1500; i < 1520 && i < x.size(); ++i)
    x[i] = std::nan("");
  return x;
}

TEST(AllanFamilyGaps, ExcludeTouchingTermsLikeNaive) {
  for (const unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    const auto x = with_random_gaps(random_phase(3000, 100 + seed), 12, seed);
    expect_matches_naive(x, MList{1, 2, 3, 7, 20, 64, 150, 400, 700, 990}, true);
  }
}

TEST(AllanFamilyGaps, RowsDisappearWhenEveryTermTouchesAGap) {
  // Every 5th point missing: no span of 5 or more points is clean.
  auto x = random_phase(500, 5);
  for (std::size_t i = 0; i < x.size(); i += 5)
    x[i] = std::nan("");
  const auto p = kernels::phase_from_phase(x, 1.0);
  for (const Stat s : {Stat::Adev, Stat::Oadev, Stat::Mdev, Stat::Tdev, Stat::Hdev, Stat::Ohdev}) {
    const auto r = run(s, p, MList{1, 2, 3, 4, 10});
    for (std::size_t i = 0; i < r.size(); ++i) {
      EXPECT_GT(r.n[i], 0);
      EXPECT_TRUE(std::isfinite(r.dev[i]));
      EXPECT_LE(r.m[i], 2) << kNames[static_cast<int>(s)];  // m = 2 spans 5 points (mdev: 6)
    }
  }
}

TEST(AllanFamilyGaps, TotdevRefuses) {
  auto x = random_phase(100, 9);
  x[40] = std::nan("");
  const auto p = kernels::phase_from_phase(x, 1.0);
  EXPECT_THROW(kernels::totdev(p, MList{1}), std::invalid_argument);
  EXPECT_THROW(kernels::compute(Stat::Totdev, p, MList{1, 2}), std::invalid_argument);
  // Rate input: a NaN rate sample is a gap as well.
  std::vector<double> y(100, 1.0);
  y[10] = std::nan("");
  EXPECT_THROW(kernels::totdev(kernels::phase_from_rate(y, 1.0), MList{1}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// Properties

TEST(AllanFamilyProperties, LinearPhaseHasZeroDeviation) {
  // Built directly, without the mean-rate removal of phase_from_*, so the kernels themselves
  // must cancel the ramp; 0.5 + 0.25 i is exact in double, so the cancellation is exact.
  PhaseData p;
  p.tau0_s = 0.1;
  for (int i = 0; i < 2000; ++i)
    p.x.push_back(0.5 + 0.25 * i);
  for (int si = 0; si < 7; ++si) {
    const auto r = run(static_cast<Stat>(si), p, MList{1, 2, 7, 100, 499});
    ASSERT_EQ(r.size(), 5u) << kNames[si];
    for (const double d : r.dev)
      EXPECT_EQ(d, 0.0) << kNames[si];
  }
}

TEST(AllanFamilyProperties, WhiteRateSlopeIsMinusHalf) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(200000);
  for (auto& v : y)
    v = g(rng);
  const auto p = kernels::phase_from_rate(y, 1.0);
  // White FM: sigma ~ tau^-1/2 for every statistic here (SP1065 Table 5 and sec. 5.2.5/5.2.7).
  // At m = 100 the non-overlapping estimates have ~2000 terms (~1.6 % standard error), so
  // the fitted slope between m = 10 and 100 is within ~0.01 of -1/2; 0.05 is ~5 sigma.
  for (const Stat s :
       {Stat::Adev, Stat::Oadev, Stat::Mdev, Stat::Hdev, Stat::Ohdev, Stat::Totdev}) {
    const auto r = run(s, p, MList{10, 100}, 2);
    ASSERT_EQ(r.size(), 2u);
    const double slope = std::log(r.dev[1] / r.dev[0]) / std::log(10.0);
    EXPECT_NEAR(slope, -0.5, 0.05) << kNames[static_cast<int>(s)];
  }
  // Unit-variance white rate: ADEV(tau0) = 1 (SP1065 Table 5).
  EXPECT_NEAR(run(Stat::Adev, p, MList{1}).dev[0], 1.0, 0.01);
  // TDEV = tau/sqrt(3) MDEV exactly, by definition (eq. 16).
  const auto md = run(Stat::Mdev, p, MList{1, 10, 1000});
  const auto td = run(Stat::Tdev, p, MList{1, 10, 1000});
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_NEAR(td.dev[i] / (md.dev[i] * md.tau_s[i] / std::sqrt(3.0)), 1.0, 1e-14);
}

TEST(AllanFamilyProperties, BitIdenticalForAnyThreadCount) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(200001);
  double walk = 0.0;
  for (auto& v : y) {
    walk += 1e-3 * g(rng);
    v = 1.0 + g(rng) + walk;
  }
  const auto ms = kernels::make_m_list(kernels::parse_tau_grid("log:20"), 100000);
  const auto p1 = kernels::phase_from_rate(y, 100.0, 1);
  for (int si = 0; si < 7; ++si) {
    const auto s = static_cast<Stat>(si);
    const auto r1 = kernels::compute(s, p1, ms, 1);
    ASSERT_GT(r1.size(), 50u) << kNames[si];
    for (const int nt : {2, 7}) {
      const auto pn = kernels::phase_from_rate(y, 100.0, nt);
      const auto rn = kernels::compute(s, pn, ms, nt);
      EXPECT_EQ(r1.m, rn.m) << kNames[si] << " " << nt << " threads";
      EXPECT_EQ(r1.n, rn.n) << kNames[si] << " " << nt << " threads";
      EXPECT_EQ(r1.dev, rn.dev) << kNames[si] << " " << nt << " threads";
    }
  }
}

// White rate samples offset + sigma g_k, g standard normal from seed.
std::vector<double> white_rate(std::size_t n, unsigned seed, double offset, double sigma) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  for (auto& v : y)
    v = offset + sigma * g(rng);
  return y;
}

// The AVX2 and AVX-512 sums (kernels/allan/sweep_simd.cpp) must round exactly like the baseline
// SSE2 loops: same sixteen lanes, same tree, no fused multiply-add. Every level this CPU has
// is compared bit for bit on every statistic (200001 samples: blocks with tails of every
// length occur across the m).
TEST(AllanFamilyProperties, BitIdenticalOnEverySimdLevel) {
  const auto y = white_rate(200001, 11, 9.80665, 1e-3);
  const auto ms = kernels::make_m_list(kernels::parse_tau_grid("log:20"), 100000);
  const auto p = kernels::phase_from_rate(y, 100.0, 2);
  const kernels::SimdLevel best = kernels::best_simd_level();
  RecordProperty("best_simd_level", std::string(kernels::simd_level_name(best)));
  const kernels::SimdLevel before = kernels::simd_level();
  std::vector<StatResult> baseline;
  ASSERT_EQ(kernels::set_simd_level(kernels::SimdLevel::Baseline), kernels::SimdLevel::Baseline);
  for (int si = 0; si < 7; ++si)
    baseline.push_back(kernels::compute(static_cast<Stat>(si), p, ms, 2));
  for (const auto level : {kernels::SimdLevel::Avx2, kernels::SimdLevel::Avx512}) {
    if (level > best) continue;
    ASSERT_EQ(kernels::set_simd_level(level), level);
    for (int si = 0; si < 7; ++si) {
      const auto r = kernels::compute(static_cast<Stat>(si), p, ms, 2);
      EXPECT_EQ(baseline[static_cast<std::size_t>(si)].dev, r.dev)
          << kNames[si] << " on " << kernels::simd_level_name(level);
    }
  }
  kernels::set_simd_level(before);
}

// OADEV, TOTDEV and OHDEV from the one shared sweep (prime_second_third, as `analyze` runs them
// when both are asked for) have the bits of their own sweeps, on every SIMD level and thread
// count, at m whose third differences end inside, at and before a block's end (N - 3m against
// the 1024-term blocks), including m with second but no third differences.
TEST(AllanFamilyProperties, SharedSecondThirdSweepHasTheSameBits) {
  const auto p = kernels::phase_from_rate(white_rate(20011, 5, 1.0, 1.0), 1.0, 1);
  const std::vector<std::int64_t> ms = {1, 2, 5, 17, 100, 1000, 3000, 6669, 6670, 6671, 9000};
  const kernels::SimdLevel before = kernels::simd_level();
  for (const auto level :
       {kernels::SimdLevel::Baseline, kernels::SimdLevel::Avx2, kernels::SimdLevel::Avx512}) {
    if (level > kernels::best_simd_level()) continue;
    ASSERT_EQ(kernels::set_simd_level(level), level);
    for (const int threads : {1, 2, 3}) {
      kernels::SumCache cache;
      kernels::prime_second_third(p, ms, threads, cache);
      for (const Stat s : {Stat::Oadev, Stat::Totdev, Stat::Ohdev}) {
        const StatResult own = kernels::compute(s, p, ms, 1);
        const StatResult shared = kernels::compute(s, p, ms, threads, &cache);
        EXPECT_EQ(own.m, shared.m) << kernels::stat_name(s);
        EXPECT_EQ(own.n, shared.n) << kernels::stat_name(s);
        EXPECT_EQ(own.dev, shared.dev)
            << kernels::stat_name(s) << " on " << kernels::simd_level_name(level) << ", " << threads
            << " threads";
      }
      EXPECT_TRUE(cache.third(6669).has_value());   // 20012 - 3 * 6669 = 5 terms
      EXPECT_FALSE(cache.third(6671).has_value());  // none: 20012 < 3 * 6671
      EXPECT_TRUE(cache.second(9000).has_value());
    }
  }
  kernels::set_simd_level(before);
}

// The documented order of the sums (kernels/allan/detail/sweep.hpp): blocks of 1024 terms, sixteen
// interleaved lanes per block, the lanes reduced by the fixed tree, blocks added in order.
// Rebuilt here in plain scalar code for OADEV at a few m; the kernel's sum must be the same
// double, on whichever SIMD level and thread count it runs.
TEST(AllanFamilyProperties, SumOrderIsTheDocumentedOne) {
  const auto p = kernels::phase_from_rate(white_rate(50003, 12, 1.0, 1.0), 1.0, 1);
  const double* x = p.x.data();
  for (const std::int64_t m : {1, 7, 1000, 10000}) {
    const std::int64_t n = p.n_points() - 2 * m;
    double total = 0.0;
    for (std::int64_t b = 0; b < n; b += 1024) {
      double lane[16] = {};
      for (std::int64_t k = b; k < std::min(n, b + 1024); ++k) {
        const double d = x[k + 2 * m] - 2.0 * x[k + m] + x[k];
        lane[(k - b) % 16] += d * d;
      }
      double t[8], u[4];
      for (int l = 0; l < 8; ++l)
        t[l] = lane[l] + lane[l + 8];
      for (int l = 0; l < 4; ++l)
        u[l] = t[l] + t[l + 4];
      total += (u[0] + u[2]) + (u[1] + u[3]);
    }
    const double tau = static_cast<double>(m);
    const double expected = std::sqrt(total / (2.0 * tau * tau * static_cast<double>(n)));
    for (const int nt : {1, 2})
      EXPECT_EQ(kernels::compute(Stat::Oadev, p, MList{m}, nt).dev[0], expected) << "m " << m;
  }
}

// OADEV's second-difference sums are TOTDEV's inner sums (kernels::SumCache): whichever of
// the two runs first, sharing them must not change a bit of either.
TEST(AllanFamilyProperties, SharedSumsChangeNothing) {
  const auto p = kernels::phase_from_rate(white_rate(100003, 13, 1.0, 1.0), 1.0, 1);
  const auto ms = kernels::make_m_list(kernels::parse_tau_grid("log:16"), 60000);
  const auto oadev = kernels::compute(Stat::Oadev, p, ms, 2);
  const auto totdev = kernels::compute(Stat::Totdev, p, ms, 2);
  {
    kernels::SumCache cache;
    EXPECT_EQ(kernels::compute(Stat::Oadev, p, ms, 2, &cache).dev, oadev.dev);
    EXPECT_EQ(kernels::compute(Stat::Totdev, p, ms, 1, &cache).dev, totdev.dev);
  }
  {
    kernels::SumCache cache;
    EXPECT_EQ(kernels::compute(Stat::Totdev, p, ms, 1, &cache).dev, totdev.dev);
    ASSERT_TRUE(cache.second(ms.front()).has_value());
    EXPECT_EQ(kernels::compute(Stat::Oadev, p, ms, 2, &cache).dev, oadev.dev);
  }
}

TEST(AllanFamilyProperties, ComputeAppliesStable32Limits) {
  const auto p = phase_dat();
  EXPECT_EQ(kernels::max_m(Stat::Adev, 1001), 199);
  EXPECT_EQ(kernels::max_m(Stat::Hdev, 1001), 199);
  for (const Stat s : {Stat::Oadev, Stat::Mdev, Stat::Tdev, Stat::Ohdev})
    EXPECT_EQ(kernels::max_m(s, 1001), 250);
  EXPECT_EQ(kernels::max_m(Stat::Totdev, 1001), 500);
  // The further statistics (stats.hpp max_m): N-1, (N-1)/4 and (N-1)/3.
  for (const Stat s : {Stat::Mtie, Stat::Theo1, Stat::Theoh})
    EXPECT_EQ(kernels::max_m(s, 1001), 1000);
  for (const Stat s : {Stat::Tierms, Stat::Pdev})
    EXPECT_EQ(kernels::max_m(s, 1001), 250);
  for (const Stat s : {Stat::Mtotdev, Stat::Ttotdev, Stat::Htotdev})
    EXPECT_EQ(kernels::max_m(s, 1001), 333);
  for (const Stat s : kernels::all_stats()) {
    const std::int64_t mm = kernels::max_m(s, p.n_points());
    const auto r = kernels::compute(s, p, MList{mm, mm + 1});
    EXPECT_EQ(r.m, MList{mm}) << kernels::stat_name(s);
  }
}

TEST(AllanFamilyProperties, NamesRoundTrip) {
  ASSERT_EQ(kernels::all_stats().size(), 15u);
  for (const Stat s : kernels::all_stats())
    EXPECT_EQ(kernels::parse_stat(kernels::stat_name(s)), s);
  EXPECT_FALSE(kernels::parse_stat("adevs").has_value());
}

// ---------------------------------------------------------------------------------------
// Dumb inputs

TEST(AllanFamilyDumbInputs, TinyAndOutOfRange) {
  const std::vector<double> two = {1.0, 3.0};  // 3 phase points
  const auto p = kernels::phase_from_rate(two, 1.0);
  for (int si = 0; si < 7; ++si) {
    const auto s = static_cast<Stat>(si);
    // compute: beyond max_m, no row at all (max_m is 0 or 1 for N = 3).
    const auto r = kernels::compute(s, p, MList{1, 2, 1000});
    EXPECT_LE(r.size(), 1u) << kNames[si];
    // The direct functions: rows only where a term exists, never NaN.
    const auto d = run(s, p, MList{1, 2, 1000, std::int64_t{1} << 40});
    for (std::size_t i = 0; i < d.size(); ++i) {
      EXPECT_TRUE(std::isfinite(d.dev[i])) << kNames[si];
      EXPECT_GE(d.n[i], 1);
      EXPECT_EQ(d.m[i], 1) << kNames[si];
    }
    EXPECT_THROW(run(s, p, MList{1, 0}), std::invalid_argument) << kNames[si];
    EXPECT_THROW(run(s, p, MList{-3}), std::invalid_argument) << kNames[si];
    EXPECT_THROW(kernels::compute(s, p, MList{0}), std::invalid_argument) << kNames[si];
    EXPECT_EQ(run(s, p, MList{}).size(), 0u);
  }
  // Exactly one term: ADEV needs 3 phase points for m = 1.
  EXPECT_EQ(kernels::adev(p, MList{1}).n, MList{1});
  EXPECT_EQ(kernels::hdev(p, MList{1}).size(), 0u);  // needs 4 points
  EXPECT_EQ(kernels::totdev(p, MList{1}).n, MList{1});
}

}  // namespace
}  // namespace allanlot
