// kernels::find_lowpass: the sensor's filter named from an Allan curve alone,
// as analyze's eq. (3) fit uses it. Over seeds, white + flicker + random walk through a
// first-order filter or a fractional boxcar is named (and says where the fit may start), and the
// same noise unfiltered is not named beyond the test's level
// (0.05 / 9 per record: one seed in twenty is already six times the nominal rate).
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/diagnose/diagnose.hpp"
#include "kernels/simulate/lowpass.hpp"
#include "kernels/simulate/simulate.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace allanlot {
namespace {

constexpr double kRate = 100.0;
constexpr std::size_t kSamples = 60000;  // 600 s
constexpr int kSeeds = 20;

kernels::LowpassFinding find(const kernels::ChannelSpec& spec, int seed) {
  kernels::SimulationPlan plan(kSamples);
  std::vector<double> y(kSamples);
  plan.run(spec, 2300, static_cast<std::uint64_t>(seed), y, 1);
  const kernels::PhaseData ph = kernels::phase_from_rate(y, kRate, 1);
  kernels::TauGridSpec grid;
  grid.kind = kernels::TauGridKind::Log;
  grid.per_decade = 16;
  kernels::StatResult oadev = kernels::compute(
      kernels::Stat::Oadev, ph,
      kernels::make_m_list(grid, kernels::max_m(kernels::Stat::Oadev, ph.n_points())), 1);
  kernels::add_confidence(kernels::Stat::Oadev, ph, oadev, kernels::kDefaultConfidence, 1);
  return kernels::find_lowpass(oadev, kRate, static_cast<std::int64_t>(kSamples));
}

kernels::ChannelSpec noise() {
  kernels::ChannelSpec spec;
  spec.rate_hz = kRate;
  spec.terms.N = 0.005;
  spec.terms.B = 0.002;
  spec.terms.K = 1e-3;
  return spec;
}

TEST(FindLowpass, UnfilteredNoiseNamesNoFilter) {
  int named = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const kernels::LowpassFinding f = find(noise(), seed);
    EXPECT_TRUE(std::isfinite(f.delta_ic)) << "seed " << seed;
    named += f.filter.active() ? 1 : 0;
  }
  EXPECT_LE(named, 1) << "of " << kSeeds;
}

TEST(FindLowpass, FilteredNoiseNamesTheFilter) {
  for (const int form : {0, 1}) {
    kernels::ChannelSpec spec = noise();
    if (form == 0)
      spec.lowpass.cutoff_hz = 15.0;
    else
      spec.lowpass.taps = 1.5;
    SCOPED_TRACE(form == 0 ? "first order 15 Hz" : "boxcar of 1.5 samples");
    int named = 0;
    for (int seed = 0; seed < kSeeds; ++seed) {
      const kernels::LowpassFinding f = find(spec, seed);
      if (!f.filter.active()) continue;
      ++named;
      // What analyze takes from the filter is where its fit starts. The form and size found
      // trade against a free Q (white PM fills the shortest taus as a stronger filter empties
      // them), so compare that: starting where the filter found says, no tau is biased by the
      // true filter beyond one sigma. lowpass_first_m puts the bias below half a sigma, and
      // bias / sigma falls as m^-3/2 (bias ~ 1/m, sigma ~ m^1/2), so from 2^-2/3 of the true
      // filter's first m on it is below one sigma.
      const auto n = static_cast<std::int64_t>(kSamples);
      EXPECT_GE(static_cast<double>(kernels::lowpass_first_m(f.filter, kRate, n)),
                std::pow(2.0, -2.0 / 3.0) *
                    static_cast<double>(kernels::lowpass_first_m(spec.lowpass, kRate, n)))
          << "seed " << seed << " cutoff " << f.filter.cutoff_hz << " taps " << f.filter.taps;
    }
    EXPECT_EQ(named, kSeeds);
  }
}

}  // namespace
}  // namespace allanlot
