// kernels/simulate's low-pass filter (issue #23 item 3): the filtered simulation's overlapping
// Allan variance is model_avar_sampled's, the factors have their closed forms where there is
// one, and the filter is sequential (the same bytes for any thread count).
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/simulate/lowpass.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

constexpr double kRate = 100.0;

TEST(SimulateLowpass, FactorsHaveTheirClosedForms) {
  kernels::Lowpass ma2;
  ma2.taps = 2;
  // y' = (y_k + y_{k-1}) / 2: y'_{k+1} - y'_k = (y_{k+1} - y_{k-1}) / 2, variance s^2 / 2 against
  // 2 s^2 unfiltered.
  EXPECT_DOUBLE_EQ(kernels::lowpass_white_fm_factor(ma2, kRate, 1), 0.25);
  // White PM through (1 + z^-1) / 2: sum of (h_k - 2 h_{k-1} + h_{k-2})^2 = 0.25 (1 + 1 + 1 + 1)
  // against 6.
  EXPECT_DOUBLE_EQ(kernels::lowpass_white_pm_factor(ma2, kRate, 1), 1.0 / 6.0);
  // A boxcar of 1.1 samples: h = (1, 0.1) / 1.1, so y'_{k+1} - y'_k has the weights
  // h0, h1 - h0, -h1: factor (h0^2 + (h0 - h1)^2 + h1^2) / 2.
  kernels::Lowpass frac;
  frac.taps = 1.1;
  const double h0 = 1.0 / 1.1, h1 = 0.1 / 1.1;
  EXPECT_NEAR(kernels::lowpass_white_fm_factor(frac, kRate, 1),
              (h0 * h0 + (h0 - h1) * (h0 - h1) + h1 * h1) / 2.0, 1e-15);
  // Far beyond the filter's length the white FM factor is 1 - O(J / m), the white PM one the
  // filter's noise gain sum h^2.
  kernels::Lowpass rc;
  rc.cutoff_hz = 5.0;
  EXPECT_NEAR(kernels::lowpass_white_fm_factor(rc, kRate, 100000), 1.0, 1e-4);
  double h2 = 0.0;
  for (const double v : kernels::lowpass_impulse(rc, kRate))
    h2 += v * v;
  EXPECT_NEAR(kernels::lowpass_white_pm_factor(rc, kRate, 100000), h2, 1e-15);
  EXPECT_DOUBLE_EQ(kernels::lowpass_white_fm_factor(kernels::Lowpass{}, kRate, 3), 1.0);
  EXPECT_NEAR(kernels::lowpass_gain2(rc, kRate, 1e-9), 1.0, 1e-12);
  // The two branches of the white FM factor (m below and above the filter's length) meet.
  const auto j = static_cast<std::int64_t>(kernels::lowpass_impulse(rc, kRate).size());
  EXPECT_NEAR(kernels::lowpass_white_fm_factor(rc, kRate, j - 1),
              kernels::lowpass_white_fm_factor(rc, kRate, j), 2.0 / static_cast<double>(j));
}

TEST(SimulateLowpass, FilteredAllanVarianceIsTheModels) {
  constexpr std::size_t n = 20000;
  constexpr int replicas = 12;
  const std::vector<std::int64_t> m{1, 2, 3, 5, 10, 30, 100};
  for (const int form : {0, 1, 2}) {
    kernels::ChannelSpec spec;
    spec.rate_hz = kRate;
    spec.terms.N = 0.01;
    spec.terms.Q = 1e-3;
    spec.sinusoids.push_back({0.02, 20.0, 0.0});
    if (form == 0)
      spec.lowpass.cutoff_hz = 8.0;
    else
      spec.lowpass.taps = form == 1 ? 4.0 : 2.6;
    SCOPED_TRACE(form == 0 ? "first order" : "moving average");
    std::vector<double> mean(m.size(), 0.0);
    kernels::SimulationPlan plan(n);
    std::vector<double> y(n);
    for (int r = 0; r < replicas; ++r) {
      plan.run(spec, 77, static_cast<std::uint64_t>(r), y, 1);
      const auto s =
          kernels::compute(kernels::Stat::Oadev, kernels::phase_from_rate(y, kRate, 1), m, 1);
      for (std::size_t i = 0; i < m.size(); ++i)
        mean[i] += s.dev[i] * s.dev[i] / replicas;
    }
    const auto taps = static_cast<double>(kernels::lowpass_impulse(spec.lowpass, kRate).size());
    for (std::size_t i = 0; i < m.size(); ++i) {
      const double want = kernels::model_avar_sampled(spec, m[i]);
      // About n / (2 m + J) independent second differences per replica (J the filter's
      // length), so the mean of the replicas has a relative standard deviation of at most
      // sqrt(2 (2 m + J) / (n R)); 5 of them (the sinusoid's fixed phase adds a deterministic
      // end effect of order m / n).
      const double md = static_cast<double>(m[i]);
      const double tol = 5.0 * std::sqrt(2.0 * (2.0 * md + taps) / (n * replicas)) + md / n;
      EXPECT_NEAR(mean[i] / want, 1.0, tol) << "m " << m[i];
    }
    // The filter matters where it should: at m = 1 the model is well below the unfiltered one.
    kernels::ChannelSpec raw = spec;
    raw.lowpass = {};
    EXPECT_LT(kernels::model_avar_sampled(spec, 1), 0.8 * kernels::model_avar_sampled(raw, 1));
  }
}

TEST(SimulateLowpass, SameBytesForAnyThreadCountAndBadSpecsRejected) {
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.terms.N = 0.01;
  spec.terms.K = 1e-3;
  spec.lowpass.cutoff_hz = 10.0;
  std::vector<double> a(50000), b(50000);
  kernels::simulate_channel(spec, 5, 1, a, 1);
  kernels::simulate_channel(spec, 5, 1, b, 2);
  EXPECT_EQ(a, b);
  spec.lowpass.taps = 4;  // both forms
  EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
  spec.lowpass = {};
  spec.lowpass.cutoff_hz = kRate / 2;  // at Nyquist: no filter
  EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
  spec.lowpass = {};
  spec.lowpass.taps = 1;
  EXPECT_THROW(kernels::validate(spec), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
