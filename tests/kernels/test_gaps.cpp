// The gap policy (kernels/allan/gaps.hpp) and the interval rule for filled samples
// (kernels/uncertainty/confidence.hpp stat_edf): the fill itself on known answers, a simulated
// record with a dozen short drops against the same record without them, the naive long-double
// reference on the filled samples, and thread-count independence.
#include "kernels/allan/gaps.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "reference/naive_allan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

using kernels::DataType;
using kernels::GapPolicy;
using kernels::Stat;

const double kNaN = std::nan("");

// White FM plus random-walk FM, the two noises that dominate an IMU's short and long taus.
std::vector<double> white_plus_walk(std::size_t n, double walk, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double w = 0.0;
  for (double& v : y) {
    w += walk * g(rng);
    v = 3.0 + g(rng) + w;
  }
  return y;
}

// A dozen drops of 1 to 3 samples at random places, as a logger drops rows.
std::vector<double> with_drops(std::vector<double> y, int drops, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> at(10, y.size() - 20);
  std::uniform_int_distribution<std::size_t> len(1, 3);
  for (int d = 0; d < drops; ++d) {
    const std::size_t a = at(rng), l = len(rng);
    for (std::size_t k = a; k < a + l; ++k)
      y[k] = kNaN;
  }
  return y;
}

kernels::StatResult with_interval(Stat s, const kernels::PhaseData& p,
                                  const std::vector<std::int64_t>& ms, int threads = 1) {
  kernels::StatResult r = kernels::compute(s, p, ms, threads);
  kernels::add_confidence(s, p, r, kernels::kDefaultConfidence, threads);
  return r;
}

TEST(GapPolicy, ParsesItsThreeFormsAndWritesThemBack) {
  EXPECT_EQ(kernels::parse_gap_policy("skip").mode, GapPolicy::Mode::Skip);
  EXPECT_EQ(kernels::parse_gap_policy("fill").max_run, 0);
  EXPECT_EQ(kernels::parse_gap_policy("fill:25").max_run, 25);
  for (const char* t : {"skip", "fill", "fill:1", "fill:10", "fill:100000"})
    EXPECT_EQ(kernels::to_string(kernels::parse_gap_policy(t)), t);
  EXPECT_EQ(kernels::to_string(GapPolicy{}), "fill:" + std::to_string(kernels::kDefaultMaxFill));
  for (const char* bad : {"", "fil", "fill:", "fill:0", "fill:-3", "fill:3x", "fill: 3", "Skip",
                          "skip:3", "fill:99999999999999999999"})
    EXPECT_THROW(kernels::parse_gap_policy(bad), std::invalid_argument) << "'" << bad << "'";
  try {
    kernels::parse_gap_policy("fill:0");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fill:0"), std::string::npos) << e.what();
  }
}

TEST(GapPolicy, InteriorRunsAreInterpolatedBetweenTheirNeighbours) {
  std::vector<double> y = {1.0, kNaN, kNaN, 4.0, 5.0, kNaN, 9.0};
  const auto f = kernels::fill_gaps(y, DataType::Rate, GapPolicy{});
  EXPECT_EQ(y, (std::vector<double>{1.0, 2.0, 3.0, 4.0, 5.0, 7.0, 9.0}));
  EXPECT_EQ(f.missing, 3);
  EXPECT_EQ(f.runs, 2);
  EXPECT_EQ(f.filled, 3);
  EXPECT_EQ(f.filled_runs, 2);
  EXPECT_EQ(f.runs_left, 0);
  EXPECT_EQ(f.missing_left, 0);
}

TEST(GapPolicy, EndRunsTakeTheNeighbourForRateAndTheMeanSlopeForPhase) {
  std::vector<double> y = {kNaN, kNaN, 2.0, 5.0, kNaN};
  kernels::fill_gaps(y, DataType::Rate, GapPolicy{});
  EXPECT_EQ(y, (std::vector<double>{2.0, 2.0, 2.0, 5.0, 5.0}));
  // Phase 1, 2, ..., with its first and last points missing: the line through the first and
  // last valid points (slope 1) continues it.
  std::vector<double> x = {kNaN, 1.0, 2.5, 3.0, kNaN, kNaN};
  kernels::fill_gaps(x, DataType::Phase, GapPolicy{});
  EXPECT_EQ(x, (std::vector<double>{0.0, 1.0, 2.5, 3.0, 4.0, 5.0}));
}

TEST(GapPolicy, RunsLongerThanTheLimitAndSkipStayGaps) {
  const std::vector<double> in = {1.0, kNaN, 3.0, kNaN, kNaN, kNaN, 7.0, kNaN, kNaN, 10.0};
  auto y = in;
  const auto f = kernels::fill_gaps(y, DataType::Rate, kernels::parse_gap_policy("fill:2"));
  EXPECT_EQ(f.runs, 3);
  EXPECT_EQ(f.filled, 3);
  EXPECT_EQ(f.filled_runs, 2);
  EXPECT_EQ(f.runs_left, 1);
  EXPECT_EQ(f.missing_left, 3);
  EXPECT_EQ(y[1], 2.0);
  EXPECT_TRUE(std::isnan(y[3]) && std::isnan(y[4]) && std::isnan(y[5]));
  EXPECT_EQ(y[8], 9.0);
  auto z = in;
  const auto s = kernels::fill_gaps(z, DataType::Rate, kernels::parse_gap_policy("skip"));
  EXPECT_EQ(s.filled, 0);
  EXPECT_EQ(s.runs_left, 3);
  EXPECT_EQ(s.missing_left, 6);
  for (std::size_t i = 0; i < in.size(); ++i)
    EXPECT_EQ(std::isnan(z[i]), std::isnan(in[i])) << i;
  // A record with no valid sample is not filled (make_phase names it).
  std::vector<double> all = {kNaN, kNaN};
  EXPECT_EQ(kernels::fill_gaps(all, DataType::Rate, kernels::parse_gap_policy("fill")).filled, 0);
}

// The user's case on a simulated record: a dozen short drops in 2e5 samples. Under the default
// policy every row keeps at least 99 % of the gap-free terms, taken as skip takes them where
// that keeps them (short taus) and from the filled record elsewhere, with every term at the
// longest tau (skip leaves out most there); the gap-free deviation lies inside the run's
// interval, and TOTDEV runs (on the filled record, with every term).
TEST(GapPolicy, ADozenDropsCostNoTauAndStayInsideTheIntervals) {
  const auto clean = white_plus_walk(200000, 0.002, 7);
  const auto dropped = with_drops(clean, 12, 8);
  auto filled = dropped;
  const auto p0 = kernels::make_phase(clean, DataType::Rate, 100.0, 1);
  kernels::GapFill fill;
  const auto pf =
      kernels::make_phase(std::span<double>(filled), DataType::Rate, 100.0, GapPolicy{}, &fill, 1);
  ASSERT_GT(fill.filled, 11);
  EXPECT_EQ(pf.n_filled, fill.filled);
  EXPECT_FALSE(pf.has_gaps());
  const auto ps = kernels::make_phase(dropped, DataType::Rate, 100.0, 1);  // skip
  for (const Stat s : {Stat::Oadev, Stat::Mdev, Stat::Ohdev, Stat::Totdev}) {
    const auto ms = kernels::make_m_list(kernels::parse_tau_grid("octave"),
                                         kernels::max_m(s, p0.n_points()), p0.n_points());
    const auto r0 = with_interval(s, p0, ms);
    const auto rf = with_interval(s, pf, ms);
    ASSERT_EQ(rf.m, r0.m) << kernels::stat_name(s);
    EXPECT_EQ(rf.n.back(), r0.n.back()) << kernels::stat_name(s);
    const auto rs = kernels::supports_gaps(s) ? kernels::compute(s, ps, ms, 1) : r0;
    std::map<std::int64_t, std::int64_t> skip_n;
    for (std::size_t i = 0; i < rs.size(); ++i)
      skip_n[rs.m[i]] = rs.n[i];
    for (std::size_t i = 0; i < r0.size(); ++i) {
      if (rf.n[i] != r0.n[i]) {  // a row as skip computes it, keeping >= 99 % of the terms
        EXPECT_EQ(rf.n[i], skip_n[r0.m[i]]) << kernels::stat_name(s) << " m=" << r0.m[i];
        EXPECT_GE(rf.n[i], kernels::kSkipKeepShare * r0.n[i]) << kernels::stat_name(s);
      }
      EXPECT_GE(r0.dev[i], rf.dev_lo[i]) << kernels::stat_name(s) << " m=" << r0.m[i];
      EXPECT_LE(r0.dev[i], rf.dev_hi[i]) << kernels::stat_name(s) << " m=" << r0.m[i];
      // The filled samples carry no information: never a narrower interval than without gaps.
      EXPECT_LE(rf.edf[i], r0.edf[i]) << kernels::stat_name(s) << " m=" << r0.m[i];
    }
    if (kernels::supports_gaps(s)) {
      EXPECT_LT(skip_n[r0.m.back()], r0.n.back() / 2) << kernels::stat_name(s);
    }
  }
}

// Each row is the naive long-double definition: on the samples with their drops where the row
// leaves out the terms touching them (short taus), on the filled samples elsewhere.
TEST(GapPolicy, FilledRecordMatchesTheNaiveReference) {
  const auto dropped = with_drops(white_plus_walk(20000, 0.01, 3), 40, 4);
  auto y = dropped;
  const auto p = kernels::make_phase(std::span<double>(y), DataType::Rate, 1.0, GapPolicy{});
  for (const double v : y)
    ASSERT_FALSE(std::isnan(v));
  const std::vector<std::int64_t> ms = {1, 3, 17, 200, 4000};
  const auto r = kernels::compute(Stat::Oadev, p, ms, 1);
  int skipped = 0;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const std::int64_t full = static_cast<std::int64_t>(y.size()) + 1 - 2 * ms[i];
    skipped += r.n[i] < full ? 1 : 0;
    const auto ref = test::naive_oadev_rate(r.n[i] < full ? dropped : y, ms[i]);
    EXPECT_EQ(r.n[i], ref.n);
    EXPECT_NEAR(r.dev[i] / static_cast<double>(ref.dev), 1.0, 1e-12) << "m=" << ms[i];
  }
  EXPECT_EQ(skipped, 1);  // m = 1 keeps >= 99 % of its terms without the filled ones
  EXPECT_EQ(r.n.back(), static_cast<std::int64_t>(y.size()) + 1 - 2 * ms.back());
}

// Phase data: the phase is interpolated across a drop, and skip's view leaves out both
// increments of each missing phase point, as the naive definition on the phase with NaN does.
TEST(GapPolicy, PhaseRecordMatchesTheNaiveReference) {
  std::vector<double> x(20000);
  std::mt19937_64 rng(12);
  std::normal_distribution<double> g(0.0, 1.0);
  double s = 0.0;
  for (double& v : x)
    v = (s += 1.0 + g(rng));  // white FM as phase, with a rate offset
  const auto dropped = with_drops(x, 20, 13);
  auto filled = dropped;
  const auto p = kernels::make_phase(std::span<double>(filled), DataType::Phase, 1.0, GapPolicy{});
  EXPECT_FALSE(p.has_gaps());
  const std::vector<std::int64_t> ms = {1, 2, 50, 1000};
  const auto r = kernels::compute(Stat::Oadev, p, ms, 1);
  ASSERT_EQ(r.size(), ms.size());
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const std::int64_t full = static_cast<std::int64_t>(x.size()) - 2 * ms[i];
    const auto ref = test::naive_oadev_phase(r.n[i] < full ? dropped : filled, ms[i], 1.0L);
    EXPECT_EQ(r.n[i], ref.n) << "m=" << ms[i];
    EXPECT_NEAR(r.dev[i] / static_cast<double>(ref.dev), 1.0, 1e-9) << "m=" << ms[i];
  }
  EXPECT_LT(r.n.front(), static_cast<std::int64_t>(x.size()) - 2);  // m = 1 as skip takes it
  EXPECT_EQ(r.n.back(), static_cast<std::int64_t>(x.size()) - 2000);
}

TEST(GapPolicy, ResultsDoNotDependOnTheThreadCount) {
  const auto base = with_drops(white_plus_walk(300000, 0.001, 5), 30, 6);
  const auto ms = kernels::make_m_list(kernels::parse_tau_grid("octave"), 75000, 300001);
  auto y1 = base;
  const auto p1 = kernels::make_phase(std::span<double>(y1), DataType::Rate, 100.0,
                                      kernels::parse_gap_policy("fill:2"), nullptr, 1);
  const auto r1 = with_interval(Stat::Oadev, p1, ms, 1);
  for (const int nt : {2, 5}) {
    auto yn = base;
    const auto pn = kernels::make_phase(std::span<double>(yn), DataType::Rate, 100.0,
                                        kernels::parse_gap_policy("fill:2"), nullptr, nt);
    ASSERT_EQ(p1.x, pn.x) << nt;
    ASSERT_EQ(p1.gaps, pn.gaps) << nt;
    const auto rn = with_interval(Stat::Oadev, pn, ms, nt);
    EXPECT_EQ(r1.dev, rn.dev) << nt;
    EXPECT_EQ(r1.edf, rn.edf) << nt;
    EXPECT_EQ(r1.n, rn.n) << nt;
  }
}

// The interval rule: F filled points of N give a finite-difference variance the edf of a
// contiguous record of N - F points, and the length-proportional fits (b T/tau - c) (N - F)/N.
TEST(GapPolicy, FilledSamplesCountAsAShorterRecord) {
  const std::int64_t n = 100001, f = 2500;
  for (const Stat s : {Stat::Adev, Stat::Oadev, Stat::Mdev, Stat::Hdev, Stat::Ohdev})
    for (const std::int64_t m : {1, 10, 1000, 20000}) {
      const auto kind = kernels::difference_kind(s);
      const double want =
          kernels::stat_edf(s, 0, m, n - f, kernels::greenhall_terms(kind, m, n - f));
      const double got = kernels::stat_edf(s, 0, m, n, kernels::greenhall_terms(kind, m, n), f);
      EXPECT_NEAR(got / want, 1.0, 1e-9) << kernels::stat_name(s) << " m=" << m;
      EXPECT_LT(got, kernels::stat_edf(s, 0, m, n, kernels::greenhall_terms(kind, m, n)));
    }
  EXPECT_DOUBLE_EQ(kernels::stat_edf(Stat::Totdev, -1, 100, n, n - 1, f),
                   kernels::edf_totvar(-1, 100, n) * static_cast<double>(n - f) / n);
  EXPECT_DOUBLE_EQ(kernels::stat_edf(Stat::Theo1, 0, 500, n, 0, f),
                   kernels::edf_theo1(0, 500, n) * static_cast<double>(n - f) / n);
  // None filled: the rule is not there.
  EXPECT_EQ(kernels::stat_edf(Stat::Oadev, -1, 64, n, n - 128, 0),
            kernels::stat_edf(Stat::Oadev, -1, 64, n, n - 128));
  EXPECT_THROW(kernels::stat_edf(Stat::Oadev, 0, 1, n, n - 2, n), std::invalid_argument);
  EXPECT_THROW(kernels::stat_edf(Stat::Oadev, 0, 1, n, n - 2, -1), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
