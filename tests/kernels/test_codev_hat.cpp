// The two-recording statistics: the Groslambert codeviation (kernels/allan/codev.hpp) and the
// three-cornered hat with their intervals (kernels/uncertainty/hat.hpp), against the naive
// long-double references of tests/reference/naive_codev.hpp, with gaps, for any thread count,
// and on simulated clocks of known levels.
#include "kernels/allan/codev.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/uncertainty/edf.hpp"
#include "kernels/uncertainty/hat.hpp"
#include "reference/naive_codev.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

using kernels::Stat;

// The kernels and the long-double references differ by the rounding of the double second
// differences and of the sums: ~sqrt(N) 1e-16 of the scale sqrt(s_x s_y) of a covariance (the
// sum of products cancels, so the covariance itself is no scale), far below 1e-12 for N <= 1e5.
constexpr double kNaiveRel = 1e-12;

std::vector<double> white(std::size_t n, double sigma, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> d(0.0, sigma);
  std::vector<double> v(n);
  for (double& s : v)
    s = d(gen);
  return v;
}

// Two phase records that share one clock with opposite signs, as AB and CA share A: their
// covariance is negative.
struct TwoRecords {
  std::vector<double> x, y;
};
TwoRecords shared_clock_records(std::size_t n, std::uint64_t seed) {
  const auto a = white(n, 1.0, seed), b = white(n, 2.0, seed + 1), c = white(n, 0.5, seed + 2);
  TwoRecords r{std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    r.x[i] = a[i] - b[i] + 0.001 * static_cast<double>(i);  // a frequency offset too
    r.y[i] = c[i] - a[i];
  }
  return r;
}

std::vector<std::int64_t> octave(std::int64_t n_points) {
  kernels::TauGridSpec spec;
  spec.kind = kernels::TauGridKind::Octave;
  return kernels::make_m_list(spec, kernels::max_m(Stat::Oadev, n_points));
}

void expect_matches_naive(const std::vector<double>& x, const std::vector<double>& y) {
  const auto px = kernels::phase_from_phase(x, 1.0, 1), py = kernels::phase_from_phase(y, 1.0, 1);
  const auto ms = octave(px.n_points());
  const auto g = kernels::gcodev(px, py, ms, 1);
  ASSERT_EQ(g.size(), ms.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const auto ref = test::naive_gcov_phase(x, y, ms[i], 1.0L);
    const long double scale =
        test::naive_oadev_phase(x, ms[i], 1.0L).dev * test::naive_oadev_phase(y, ms[i], 1.0L).dev;
    EXPECT_EQ(g.m[i], ms[i]);
    EXPECT_EQ(g.n[i], ref.n) << "m=" << ms[i];
    const double v = std::copysign(g.dev[i] * g.dev[i], g.dev[i]);
    EXPECT_LE(std::fabs(v - static_cast<double>(ref.var)), kNaiveRel * static_cast<double>(scale))
        << "m=" << ms[i];
    EXPECT_LT(g.dev[i], 0.0) << "m=" << ms[i] << ": the shared clock enters with opposite signs";
  }
}

TEST(Gcodev, MatchesNaiveLongDouble) {
  const auto r = shared_clock_records(5000, 11);
  expect_matches_naive(r.x, r.y);
}

TEST(Gcodev, GapsLeaveOutTheTermsThatTouchThem) {
  auto r = shared_clock_records(3000, 21);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::size_t k : {7u, 500u, 501u, 1700u})
    r.x[k] = nan;
  for (const std::size_t k : {100u, 2999u})
    r.y[k] = nan;
  expect_matches_naive(r.x, r.y);
}

TEST(Gcodev, WithItselfIsOadev) {
  const auto r = shared_clock_records(4000, 31);
  const auto p = kernels::phase_from_phase(r.x, 1.0, 1);
  const auto ms = octave(p.n_points());
  const auto g = kernels::gcodev(p, p, ms, 1);
  const auto o = kernels::compute(Stat::Oadev, p, ms, 1);
  ASSERT_EQ(g.size(), o.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(g.n[i], o.n[i]);
    EXPECT_NEAR(g.dev[i] / o.dev[i], 1.0, kNaiveRel) << "m=" << g.m[i];
  }
  // And its interval is OADEV's: codev_edf gives the records' edf back when x = y.
  const auto c = kernels::gcodev_with_confidence(p, p, ms, 0.683, 1);
  for (std::size_t i = 0; i < c.codev.size(); ++i)
    EXPECT_NEAR(c.codev.edf[i] / c.oadev[0].edf[i], 1.0, 1e-12) << "m=" << c.codev.m[i];
}

TEST(Gcodev, BitIdenticalForAnyThreadCount) {
  // 300 000 points: several 2^16-term chunks per m, shared out differently per thread count.
  const auto r = shared_clock_records(300000, 41);
  const auto px = kernels::phase_from_phase(r.x, 1.0, 1),
             py = kernels::phase_from_phase(r.y, 1.0, 1);
  const auto ms = octave(px.n_points());
  const auto one = kernels::gcodev_with_confidence(px, py, ms, 0.9, 1);
  for (const int t : {2, 7}) {
    const auto other = kernels::gcodev_with_confidence(px, py, ms, 0.9, t);
    EXPECT_EQ(one.codev.dev, other.codev.dev) << t << " threads";
    EXPECT_EQ(one.codev.n, other.codev.n) << t << " threads";
    EXPECT_EQ(one.codev.dev_lo, other.codev.dev_lo) << t << " threads";
    EXPECT_EQ(one.codev.dev_hi, other.codev.dev_hi) << t << " threads";
  }
}

TEST(Gcodev, RefusesRecordsThatDoNotPair) {
  const auto a = kernels::phase_from_phase(white(100, 1.0, 1), 1.0, 1);
  const auto b = kernels::phase_from_phase(white(101, 1.0, 2), 1.0, 1);
  const auto c = kernels::phase_from_phase(white(100, 1.0, 3), 2.0, 1);
  const std::int64_t ms[] = {1, 2};
  const std::int64_t bad[] = {0};
  EXPECT_THROW(kernels::gcodev(a, b, ms), std::invalid_argument);
  EXPECT_THROW(kernels::gcodev(a, c, ms), std::invalid_argument);
  EXPECT_THROW(kernels::gcodev(a, a, bad), std::invalid_argument);
  EXPECT_THROW(kernels::gcodev_with_confidence(a, a, ms, 1.5), std::invalid_argument);
}

TEST(Gcodev, EdfOfTheCovarianceFromIsserlis) {
  // x = y: the records' own edf; uncorrelated records (g -> 0): no degrees of freedom left.
  EXPECT_DOUBLE_EQ(kernels::codev_edf(3.0, 3.0, 3.0, 50.0, 50.0), 50.0);
  EXPECT_DOUBLE_EQ(kernels::codev_edf(3.0, 5.0, 0.0, 50.0, 50.0), 0.0);
  // (s_x s_y + g^2) / nu with s_x = s_y = 2, g = 1: var = 5 / 40, edf = 2 / (5 / 40) = 16.
  EXPECT_DOUBLE_EQ(kernels::codev_edf(2.0, 2.0, -1.0, 40.0, 40.0), 16.0);
}

// Three pair records of clocks a, b, c with an independent measurement noise per pair (so that
// AB + BC + CA is not zero, as with three separate instruments).
struct Pairs {
  std::vector<double> ab, bc, ca;
};
Pairs pair_records(std::size_t n, double sa, double sb, double sc, std::uint64_t seed) {
  const auto a = white(n, sa, seed), b = white(n, sb, seed + 1), c = white(n, sc, seed + 2);
  const auto e1 = white(n, 0.1, seed + 3), e2 = white(n, 0.1, seed + 4),
             e3 = white(n, 0.1, seed + 5);
  Pairs p{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    p.ab[i] = a[i] - b[i] + e1[i];
    p.bc[i] = b[i] - c[i] + e2[i];
    p.ca[i] = c[i] - a[i] + e3[i];
  }
  return p;
}

TEST(Hat, MatchesNaiveLongDouble) {
  auto p = pair_records(4000, 1.0, 2.0, 3.0, 51);
  p.bc[1234] = std::numeric_limits<double>::quiet_NaN();  // a gap in one pair
  const auto ab = kernels::phase_from_phase(p.ab, 1.0, 1);
  const auto bc = kernels::phase_from_phase(p.bc, 1.0, 1);
  const auto ca = kernels::phase_from_phase(p.ca, 1.0, 1);
  const auto ms = octave(ab.n_points());
  const auto h = kernels::three_cornered_hat(ab, bc, ca, ms, 0.683, 1);
  for (int k = 0; k < 3; ++k)
    ASSERT_EQ(h.clock[k].size(), ms.size());
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const auto ref = test::naive_hat_phase(p.ab, p.bc, p.ca, ms[i], 1.0L);
    const double scale = h.pair[0].dev[i] * h.pair[0].dev[i] + h.pair[1].dev[i] * h.pair[1].dev[i] +
                         h.pair[2].dev[i] * h.pair[2].dev[i];
    for (int k = 0; k < 3; ++k) {
      const double dev = h.clock[k].dev[i];
      const double v = std::copysign(dev * dev, dev);
      EXPECT_LE(std::fabs(v - static_cast<double>(ref[k])), kNaiveRel * scale)
          << "clock " << k << " m=" << ms[i];
    }
  }
}

TEST(Hat, EstimateVarianceIsTheChiSquareOneWhenTheOtherClocksAreSilent) {
  // Equal edf nu: var = (2 A^2 + A B + A C + B C) / nu (the header's derivation); with B = C = 0
  // it is the chi-square 2 A^2 / nu, so the clock keeps the pairs' edf.
  const double A = 2.0, B = 3.0, C = 5.0, nu = 40.0;
  EXPECT_NEAR(kernels::hat_estimate_variance(A + B, B + C, C + A, nu, nu, nu),
              (2 * A * A + A * B + A * C + B * C) / nu, 1e-12);
  EXPECT_NEAR(kernels::hat_estimate_variance(A, 0.0, A, nu, nu, nu), 2 * A * A / nu, 1e-12);
}

TEST(Hat, NegativeVarianceIsSignedWithoutInterval) {
  // BC far noisier than AB and CA together: no three clocks give these pairs, and clock A's
  // estimate (AB + CA - BC) / 2 is negative at every tau.
  Pairs p{white(4000, 1.0, 61), white(4000, 10.0, 62), white(4000, 1.0, 63)};
  const auto ab = kernels::phase_from_phase(p.ab, 1.0, 1);
  const auto bc = kernels::phase_from_phase(p.bc, 1.0, 1);
  const auto ca = kernels::phase_from_phase(p.ca, 1.0, 1);
  const auto h = kernels::three_cornered_hat(ab, bc, ca, octave(ab.n_points()), 0.683, 1);
  ASSERT_GT(h.clock[0].size(), 5u);
  for (std::size_t i = 0; i < h.clock[0].size(); ++i) {
    EXPECT_LT(h.clock[0].dev[i], 0.0);
    EXPECT_TRUE(std::isnan(h.clock[0].edf[i]));
    EXPECT_TRUE(std::isnan(h.clock[0].dev_lo[i]));
    EXPECT_TRUE(std::isnan(h.clock[0].dev_hi[i]));
    EXPECT_GT(h.clock[1].dev[i], 0.0);
    EXPECT_LT(h.clock[1].dev_lo[i], h.clock[1].dev[i]);
    EXPECT_GT(h.clock[1].dev_hi[i], h.clock[1].dev[i]);
  }
  EXPECT_NE(h.notes[0].find("clock A"), std::string::npos) << h.notes[0];
  EXPECT_TRUE(h.notes[1].empty()) << h.notes[1];
}

TEST(Hat, IsMinusTheCodeviationWhenTheRecordsClose) {
  // AB + BC + CA = 0 (one instrument): (AB^2 + CA^2 - BC^2) / 2 = -AB CA term by term, so clock
  // A's hat variance is -Gcod(AB, CA) (docs/statistics.md), to the rounding of the sums.
  const auto a = white(5000, 1.0, 81), b = white(5000, 2.0, 82), c = white(5000, 3.0, 83);
  std::vector<double> ab(5000), bc(5000), ca(5000);
  for (std::size_t i = 0; i < ab.size(); ++i) {
    ab[i] = a[i] - b[i];
    bc[i] = b[i] - c[i];
    ca[i] = -(ab[i] + bc[i]);
  }
  const auto pab = kernels::phase_from_phase(ab, 1.0, 1);
  const auto pbc = kernels::phase_from_phase(bc, 1.0, 1);
  const auto pca = kernels::phase_from_phase(ca, 1.0, 1);
  const auto ms = octave(pab.n_points());
  const auto h = kernels::three_cornered_hat(pab, pbc, pca, ms, 0.683, 1);
  const auto g = kernels::gcodev(pab, pca, ms, 1);
  ASSERT_EQ(h.clock[0].size(), g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double scale = h.pair[0].dev[i] * h.pair[2].dev[i];
    EXPECT_NEAR(h.clock[0].dev[i] * std::fabs(h.clock[0].dev[i]), -g.dev[i] * std::fabs(g.dev[i]),
                kNaiveRel * scale)
        << "m=" << g.m[i];
  }
}

TEST(Hat, BitIdenticalForAnyThreadCount) {
  const auto p = pair_records(200000, 1.0, 2.0, 3.0, 71);
  const auto ab = kernels::phase_from_phase(p.ab, 1.0, 1);
  const auto bc = kernels::phase_from_phase(p.bc, 1.0, 1);
  const auto ca = kernels::phase_from_phase(p.ca, 1.0, 1);
  const auto ms = octave(ab.n_points());
  const auto one = kernels::three_cornered_hat(ab, bc, ca, ms, 0.683, 1);
  for (const int t : {2, 7}) {
    const auto other = kernels::three_cornered_hat(ab, bc, ca, ms, 0.683, t);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(one.clock[k].dev, other.clock[k].dev) << t << " threads, clock " << k;
      EXPECT_EQ(one.clock[k].edf, other.clock[k].edf) << t << " threads, clock " << k;
      EXPECT_EQ(one.clock[k].dev_lo, other.clock[k].dev_lo) << t << " threads, clock " << k;
      EXPECT_EQ(one.clock[k].dev_hi, other.clock[k].dev_hi) << t << " threads, clock " << k;
    }
  }
}

// Three simulated clocks of white FM (kernels/simulate: avar = N^2 / tau exactly at every m)
// with levels 1, 2 and 3: their pairwise differences give each clock's level back. Tolerance
// from the edf: per tau, the hat estimate of clock A's variance has standard deviation
// sqrt((2 A^2 + A B + A C + B C) / nu) (hat_estimate_variance's derivation, equal edf), nu the
// Greenhall-Riley edf of OADEV for white FM over the record; the test allows 5 of them. The
// estimate is a sum of ~nu/2 products, close to normal for nu >= 30 (m <= N/64 here), so each
// comparison fails by chance with probability ~6e-7, the 3 x 11 of them ~2e-5.
TEST(Hat, RecoversSimulatedClockLevels) {
  const std::size_t n = std::size_t{1} << 17;
  const double level[3] = {1.0, 2.0, 3.0};
  std::vector<double> y[3];
  for (int k = 0; k < 3; ++k) {
    kernels::ChannelSpec spec;
    spec.terms.N = level[k];
    y[k].resize(n);
    kernels::simulate_channel(spec, 2026, static_cast<std::uint64_t>(k), y[k], 1);
  }
  std::vector<double> d[3];  // AB, BC, CA as rate differences
  for (int k = 0; k < 3; ++k) {
    d[k].resize(n);
    for (std::size_t i = 0; i < n; ++i)
      d[k][i] = y[k][i] - y[(k + 1) % 3][i];
  }
  const auto ab = kernels::phase_from_rate(d[0], 1.0, 1);
  const auto bc = kernels::phase_from_rate(d[1], 1.0, 1);
  const auto ca = kernels::phase_from_rate(d[2], 1.0, 1);
  std::vector<std::int64_t> ms;
  for (std::int64_t m = 1; m <= static_cast<std::int64_t>(n) / 64; m *= 2)
    ms.push_back(m);
  const auto h = kernels::three_cornered_hat(ab, bc, ca, ms, 0.683, 1);
  const kernels::FiniteDifferenceKind oadev_kind{2, true, false};
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(h.clock[k].size(), ms.size());
    for (std::size_t i = 0; i < ms.size(); ++i) {
      const double tau = static_cast<double>(ms[i]);
      const double A = level[k] * level[k] / tau;
      const double B = level[(k + 1) % 3] * level[(k + 1) % 3] / tau;
      const double C = level[(k + 2) % 3] * level[(k + 2) % 3] / tau;
      const double nu = kernels::edf_greenhall(0, oadev_kind, ms[i], ab.n_points());
      const double sd = std::sqrt((2 * A * A + A * B + A * C + B * C) / nu);
      const double dev = h.clock[k].dev[i];
      EXPECT_NEAR(std::copysign(dev * dev, dev), A, 5.0 * sd) << "clock " << k << " m=" << ms[i];
      // The interval's edf is the reduced one, 2 A^2 nu / (2 A^2 + AB + AC + BC), from the
      // estimates themselves: within a factor 2 where the estimates are good to ~10 %.
      if (ms[i] <= 64) {
        const double reduced = 2 * A * A / (sd * sd);
        EXPECT_GT(h.clock[k].edf[i], 0.5 * reduced) << "clock " << k << " m=" << ms[i];
        EXPECT_LT(h.clock[k].edf[i], 2.0 * reduced) << "clock " << k << " m=" << ms[i];
      }
    }
  }
}

// The intervals' coverage on simulated clocks: 400 records of three white-PM clocks (sigma 1, 2,
// 3; N = 2000) measured pairwise with an independent instrument noise (sigma 0.3) per pair. The
// hat's clock A estimates sigma_A^2 + e^2 / 2 (half of the pairs' own noise, which the hat gives
// to the clocks), gcodev(AB, CA) -sigma_A (the instruments' noise is not shared). At m = 1, 4
// and 16 (at least 30 averages: the lag-1 noise identification sees white PM, so the pairs' edf
// is right) each 68.3 % interval must hold the truth in 68.3 % of the records, within 4
// binomial standard deviations, sqrt(0.683 0.317 / 400) = 0.023 each. Larger m, where the
// noise identification often takes white PM for flicker PM (B1 cannot tell them apart) and the
// pairs' edf is flicker PM's, give conservative intervals (0.75 at m = 64, 0.99 at m = 128).
TEST(Hat, IntervalsCoverTheTruthAsOftenAsTheyClaim) {
  const int reps = 400;
  const std::size_t n = 2000;
  const double sigma[3] = {1.0, 2.0, 3.0}, e = 0.3, c = 0.683;
  const std::int64_t ms[] = {1, 4, 16};
  int hat_in[3] = {}, codev_in[3] = {};
  std::mt19937_64 gen(5);
  std::normal_distribution<double> d;
  for (int r = 0; r < reps; ++r) {
    std::vector<double> clock[3], pair[3];
    for (int k = 0; k < 3; ++k) {
      clock[k].resize(n);
      for (double& v : clock[k])
        v = sigma[k] * d(gen);
    }
    for (int k = 0; k < 3; ++k) {
      pair[k].resize(n);
      for (std::size_t i = 0; i < n; ++i)
        pair[k][i] = clock[k][i] - clock[(k + 1) % 3][i] + e * d(gen);
    }
    const auto ab = kernels::phase_from_phase(pair[0], 1.0, 1);
    const auto bc = kernels::phase_from_phase(pair[1], 1.0, 1);
    const auto ca = kernels::phase_from_phase(pair[2], 1.0, 1);
    const auto h = kernels::three_cornered_hat(ab, bc, ca, ms, c, 1);
    const auto g = kernels::gcodev_with_confidence(ab, ca, ms, c, 1);
    ASSERT_EQ(h.clock[0].size(), 3u);
    ASSERT_EQ(g.codev.size(), 3u);
    for (int i = 0; i < 3; ++i) {
      const double m = static_cast<double>(ms[i]);
      // Independent phase points of variance s^2: E (x_{i+2m} - 2 x_{i+m} + x_i)^2 = 6 s^2, so
      // AVAR = 6 s^2 / (2 tau^2) = 3 s^2 / m^2 (tau0 = 1).
      const double hat_truth = std::sqrt(3.0 * (sigma[0] * sigma[0] + 0.5 * e * e)) / m;
      const double codev_truth = -std::sqrt(3.0) * sigma[0] / m;
      const auto& a = h.clock[0];
      hat_in[i] += a.dev_lo[static_cast<std::size_t>(i)] <= hat_truth &&
                   hat_truth <= a.dev_hi[static_cast<std::size_t>(i)];
      codev_in[i] += g.codev.dev_lo[static_cast<std::size_t>(i)] <= codev_truth &&
                     codev_truth <= g.codev.dev_hi[static_cast<std::size_t>(i)];
    }
  }
  const double tol = 4.0 * std::sqrt(c * (1.0 - c) / reps);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(hat_in[i] / static_cast<double>(reps), c, tol) << "hat, m=" << ms[i];
    EXPECT_NEAR(codev_in[i] / static_cast<double>(reps), c, tol) << "gcodev, m=" << ms[i];
  }
}

}  // namespace
}  // namespace allanlot
