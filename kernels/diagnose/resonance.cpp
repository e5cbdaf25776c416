// Diagnose's resonance (docs/diagnose.md "Why"): its Allan curve under the sensor's filter and
// the search of its frequency and quality factor on the measured curve.
#include "kernels/diagnose/internal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace allanlot::kernels::diagnose_detail {
namespace {

// The quality factors searched. Below 2 the peak is a broad band-pass bump, no narrowband noise:
// a low-frequency one is a Gauss-Markov hump in all but name (`markov`, one parameter fewer),
// and a pair of them named a hump and white PM on 1 of 10 records of the study's markov +
// quantization at q down to 0.5. At the top the coherence time exceeds any record the
// project meets and the process is a line of random phase: q is then a lower limit.
constexpr double kQLo = 2.0, kQHi = kResonanceMaxQ;

}  // namespace

std::vector<double> resonance_curve(const Resonance& r, const Curve& cv, const Lowpass& lp,
                                    double rate_hz) {
  return resonance_avar(r, rate_hz, cv.m, lowpass_autocorrelation(lp, rate_hz));
}

// The frequency on a log grid of 8 per octave from 1 / (longest tau) (a slower resonance shows
// no ripple inside the taus) to 0.4 rate (above, inside a sensor's filter transition, a peak
// acts on the shortest tau alone, where it stood in for the filter's shape on a real z
// gyroscope: frequency_hz > 48 Hz with q > 2048 at 100 Hz), times q on a grid of factors of 4, the free
// coefficients fitted at each point; then, from the best point (or the present values when
// `grid` is false: the final refit), golden-section searches on ln f0 and ln q in turn, each
// within one grid step of the best, three times. The Allan curve oscillates in f0 (its ripples
// are at tau ~ k / f0), so the grid must be finer than a ripple's shift; q moves the curve
// smoothly. A value within a grid step of either end of its range is marked as a bound.
Fit search_resonance(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b,
                     bool grid) {
  const auto eval = [&](double ln_f, double ln_q) {
    comps[idx].nl = std::exp(ln_f);
    comps[idx].q = std::exp(ln_q);
    return fit_components(comps, cv, b);
  };
  const double f_lo = std::log(1.0 / cv.tau.back()), f_hi = std::log(0.4 * b.rate_hz);
  const double q_lo = std::log(kQLo), q_hi = std::log(kQHi);
  const double f_step = std::numbers::ln2 / 8.0, q_step = 2.0 * std::numbers::ln2;
  double best_f = std::log(comps[idx].nl), best_q = std::log(comps[idx].q);
  double best_chi2 = std::numeric_limits<double>::infinity();
  if (grid) {
    const int n_f = static_cast<int>(std::ceil((f_hi - f_lo) / f_step)) + 1;
    const int n_q = static_cast<int>(std::ceil((q_hi - q_lo) / q_step)) + 1;
    for (int i = 0; i < n_f; ++i)
      for (int j = 0; j < n_q; ++j) {
        const double lf = std::min(f_lo + f_step * i, f_hi);
        const double lq = std::min(q_lo + q_step * j, q_hi);
        const double c = eval(lf, lq).chi2;
        if (c < best_chi2) {
          best_chi2 = c;
          best_f = lf;
          best_q = lq;
        }
      }
  }
  double chi2 = grid ? best_chi2 : eval(best_f, best_q).chi2;
  const auto keep = [&](double lf, double lq) {
    const double c = eval(lf, lq).chi2;
    if (!(c <= chi2)) return;
    chi2 = c;
    best_f = lf;
    best_q = lq;
  };
  for (int pass = 0; pass < 3; ++pass) {
    keep(golden_min([&](double x) { return eval(x, best_q).chi2; },
                    std::max(best_f - f_step, f_lo), std::min(best_f + f_step, f_hi)),
         best_q);
    keep(best_f, golden_min([&](double x) { return eval(best_f, x).chi2; },
                            std::max(best_q - q_step, q_lo), std::min(best_q + q_step, q_hi)));
  }
  Fit out = eval(best_f, best_q);
  out.comps[idx].nl_bound = best_f < f_lo + f_step ? -1 : best_f > f_hi - f_step ? 1 : 0;
  out.comps[idx].q_bound = best_q < q_lo + 0.05 ? -1 : best_q > q_hi - 0.05 ? 1 : 0;
  return out;
}

}  // namespace allanlot::kernels::diagnose_detail
