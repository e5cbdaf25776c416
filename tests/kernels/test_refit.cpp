// The fit of a diagnosed structure on the curve it is drawn against (kernels::fit_to_curve,
// kernels/diagnose/refit.cpp; docs/fit-and-psd.md "When eq. (3) is a poor fit"): a hump the
// structure lacks, which the curve's intervals resolve, is added and found where it is; a
// structure that describes the curve gains nothing.
#include "kernels/allan/tau_grid.hpp"
#include "kernels/diagnose/diagnose.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace allanlot {
namespace {

constexpr double kRateHz = 100.0;
constexpr std::int64_t kSamples = 360000;  // an hour at 100 Hz

// White noise and flicker crossing near 57 s, and a Gauss-Markov hump of tau_c 5 s whose Allan
// variance peaks near 1.9 tau_c at 0.38 sigma^2 = 9.5e-6, 0.77 times the other two there: a hump
// that the flicker floor and the random walk, free beside the structure, cannot stand in for
// within the intervals of an hour's record.
kernels::ChannelSpec truth() {
  kernels::ChannelSpec s;
  s.rate_hz = kRateHz;
  s.terms.N = 0.01;
  s.terms.B = 0.002;
  s.markovs.push_back({0.005, 5.0});
  return s;
}

// The curve `model` predicts on a log grid of 8 taus a decade, with the edf it gives each
// estimate (kernels::diagnose_model_edf): the measurement of a record of `model` without its
// noise, so that every difference from it is the fit's.
kernels::StatResult expected_curve(const kernels::ChannelSpec& model) {
  kernels::TauGridSpec grid;
  grid.kind = kernels::TauGridKind::Log;
  grid.per_decade = 8;
  kernels::StatResult r;
  r.m = kernels::make_m_list(grid, kSamples / 4);
  r.edf = kernels::diagnose_model_edf(model, r.m, kSamples);
  for (const std::int64_t m : r.m) {
    r.tau_s.push_back(static_cast<double>(m) / kRateHz);
    r.dev.push_back(std::sqrt(kernels::model_avar_sampled(model, m, kSamples)));
    r.n.push_back(kSamples - 2 * m + 1);
  }
  return r;
}

TEST(FitToCurve, HumpTheStructureLacksIsAddedWhereItIs) {
  kernels::ChannelSpec given = truth();
  given.markovs.clear();
  const kernels::ChannelSpec drawn =
      kernels::fit_to_curve(given, expected_curve(truth()), kSamples);
  ASSERT_EQ(drawn.markovs.size(), 1u);
  // A curve without noise: what remains is the fit's correction of each log variance for its
  // chi-square bias (about 1 / edf, 0.3-1 % at the hump's taus), far inside the 2 % allowed to
  // tau_c, sigma and B, which stood in for the hump before it was added.
  EXPECT_NEAR(drawn.markovs[0].tau_c_s, 5.0, 0.1);
  EXPECT_NEAR(drawn.markovs[0].sigma, 0.005, 1e-4);
  EXPECT_NEAR(drawn.terms.B, 0.002, 4e-5);
  EXPECT_NEAR(drawn.terms.N, 0.01, 2e-4);
}

TEST(FitToCurve, StructureThatDescribesTheCurveGainsNothing) {
  const kernels::ChannelSpec drawn =
      kernels::fit_to_curve(truth(), expected_curve(truth()), kSamples);
  EXPECT_EQ(drawn.markovs.size(), 1u);
  EXPECT_TRUE(drawn.resonances.empty());
  EXPECT_NEAR(drawn.markovs[0].tau_c_s, 5.0, 0.1);
}

}  // namespace
}  // namespace allanlot
