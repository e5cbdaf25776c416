// libFuzzer target: the kernels' entry points with arbitrary lengths and values, in the order
// `analyze` calls them for one channel (src/pipeline/channel.cpp analyze_channel): phase building,
// each statistic on an arbitrary m list, confidence intervals and noise identification, the
// eq. (3) fit, and the Welch PSD with its log binning, eq. (2) cross-check and PSD fit; then the
// two-recording statistics (gcodev, the three-cornered hat) on the record and its reverse.
// Documented preconditions throw std::invalid_argument (docs/development.md "Errors");
// anything else that escapes (another exception, a crash, a sanitizer report) is a finding, and
// so is a deviation that is negative, or NaN where no input sample was.
#include "kernels/allan/allan.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/model/psd_fit.hpp"
#include "kernels/spectral/psd.hpp"
#include "kernels/uncertainty/confidence.hpp"
#include "kernels/uncertainty/hat.hpp"

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace {

using namespace allanlot::kernels;

constexpr double kSpecial[] = {0.0,
                               -0.0,
                               1.0,
                               -1.0,
                               1e-300,
                               5e-324,
                               1e300,
                               -1e300,
                               std::numeric_limits<double>::max(),
                               std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::infinity(),
                               -std::numeric_limits<double>::infinity()};

double value(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange(0, 3)) {
  case 0:
    return in.PickValueInArray(kSpecial);
  case 1:
    return in.ConsumeFloatingPoint<double>();
  case 2:
    return static_cast<double>(in.ConsumeIntegral<std::int16_t>());  // ADC counts
  default:
    return in.ConsumeFloatingPointInRange(-1.0, 1.0);
  }
}

template <class F>
void expect_precondition_or_success(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument&) {
  }
}

void check_rows(const StatResult& r) {
  if (r.tau_s.size() != r.size() || r.dev.size() != r.size() || r.n.size() != r.size())
    std::abort();
  for (std::size_t i = 0; i < r.size(); ++i)
    if (r.m[i] < 1 || r.n[i] < 1 || r.dev[i] < 0) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const double rate_hz =
      in.ConsumeBool() ? in.PickValueInArray({1.0, 100.0, 1000.0, 0.001}) : value(in);
  const DataType type = in.ConsumeBool() ? DataType::Rate : DataType::Phase;
  const auto stat = all_stats()[in.ConsumeIntegralInRange<std::size_t>(0, all_stats().size() - 1)];
  const double confidence = in.ConsumeBool() ? 0.683 : value(in);
  std::vector<std::int64_t> ms;
  if (in.ConsumeBool())
    for (int k = in.ConsumeIntegralInRange(0, 8); k > 0; --k)
      ms.push_back(in.ConsumeIntegralInRange<std::int64_t>(-2, 5000));
  // The samples: a repeated pattern stretches a short input to a length the PSD accepts. The
  // total family and Thêo1/ThêoH cost O(N m) per tau (ThêoH O(N^3 / 900) once;
  // docs/statistics.md): their records stay short, so that one input runs well within the
  // fuzzer's time limit under the sanitizers, and the other statistics keep the long ones.
  const std::string_view name = stat_name(stat);
  const bool superlinear = name == "mtotdev" || name == "ttotdev" || name == "htotdev" ||
                           name == "theo1" || name == "theoh";
  const auto n = in.ConsumeIntegralInRange<std::size_t>(0, superlinear ? 300 : 3000);
  std::vector<double> pattern;
  while (in.remaining_bytes() > 0 && pattern.size() < 512)
    pattern.push_back(value(in));
  if (pattern.empty()) pattern.push_back(0.0);
  std::vector<double> samples(n);
  for (std::size_t i = 0; i < n; ++i)
    samples[i] = pattern[i % pattern.size()] + (i % 7) * 1e-3;

  PhaseData p;
  try {
    p = make_phase(samples, type, rate_hz, 1);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  if (ms.empty()) ms = make_m_list(TauGridSpec{}, max_m(stat, p.n_points()), p.n_points());
  StatResult r;
  expect_precondition_or_success([&] {
    r = compute(stat, p, ms, 1);
    check_rows(r);
    add_confidence(stat, p, r, confidence, 1);
  });

  // The fit and the PSD run on the overlapping Allan deviation, as in analyze.
  const auto oms = make_m_list(TauGridSpec{}, max_m(Stat::Oadev, p.n_points()), p.n_points());
  StatResult oadev_r;
  expect_precondition_or_success([&] {
    oadev_r = compute(Stat::Oadev, p, oms, 1);
    check_rows(oadev_r);
    add_confidence(Stat::Oadev, p, oadev_r, kDefaultConfidence, 1);
    Eq3Fit fit;
    (void)fit.fit(oadev_r, p.tau0_s, static_cast<std::int64_t>(samples.size()));
  });
  // gcodev and the hat: signed deviations, so only the intervals' order is checked: lo <= hi.
  // (Not lo <= dev <= hi: at a small confidence both chi-square quantiles lie on the same side
  // of the edf, and the interval of a chi-square variance need not contain the estimate.)
  std::vector<double> reversed(samples.rbegin(), samples.rend());
  expect_precondition_or_success([&] {
    const PhaseData q = make_phase(reversed, type, rate_hz, 1);
    const CodevResult c = gcodev_with_confidence(p, q, oms, confidence, 1);
    for (std::size_t i = 0; i < c.codev.size(); ++i)
      if (c.codev.dev_lo[i] > c.codev.dev_hi[i]) std::abort();
    const HatResult h = three_cornered_hat(p, q, p, oms, confidence, 1);
    for (const StatResult& k : h.clock)
      if (k.dev.size() != k.size() || k.dev_lo.size() != k.size()) std::abort();
  });
  std::vector<double> rate(p.x.size() > 0 ? p.x.size() - 1 : 0);
  const double r_hz = 1.0 / p.tau0_s;
  for (std::size_t k = 0; k < rate.size(); ++k)
    rate[k] = p.clean(static_cast<std::int64_t>(k), static_cast<std::int64_t>(k) + 1)
                  ? (p.x[k + 1] - p.x[k]) * r_hz
                  : std::nan("");
  expect_precondition_or_success([&] {
    const PsdResult psd = welch_psd(rate, r_hz, 1, in.ConsumeIntegralInRange(1, 32));
    (void)log_bin(psd);
    (void)avar_from_psd(psd, oadev_r.tau_s, {}, 1);
    (void)psd_fit(psd);
  });
  return 0;
}
