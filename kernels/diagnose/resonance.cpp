// Diagnose's resonance (docs/diagnose.md "Why"): its Allan curve under the sensor's filter and
// the search of its frequency and quality factor on the measured curve, and its candidate.
#include "kernels/diagnose/internal.hpp"

#include "kernels/common/tasks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>

namespace allanlot::kernels::diagnose_detail {
namespace {

// The quality factors searched. Below 2 the peak is a broad band-pass bump, no narrowband noise:
// a low-frequency one is a Gauss-Markov hump in all but name (`markov`, one parameter fewer),
// and a pair of them named a hump and white PM on 1 of 10 records of the study's markov +
// quantization at q down to 0.5. At the top the coherence time exceeds any record the
// project meets and the process is a line of random phase: q is then a lower limit.
constexpr double kQLo = 2.0, kQHi = kResonanceMaxQ;

// An empty resonance candidate, with a note when the channel already has as many resonances as
// the simulator draws streams for.
CandidateFit resonance_room(const std::vector<Component>& base) {
  CandidateFit out;
  out.info.effect = Effect::Resonance;
  const auto n_res = std::count_if(base.begin(), base.end(), is<Resonance>);
  if (static_cast<std::size_t>(n_res) >= EffectTraits<Resonance>::max_count)
    out.info.note = "too many resonances";
  return out;
}

// The half-width at half power of a resonance's peak: f0 / (2 q), plus a wandering one's
// Gaussian's, sqrt(2 ln 2) spread (the two added, an upper bound of the mixture's).
double half_width(const Component& c) {
  const Resonance& r = as<Resonance>(c);
  return r.frequency_hz / (2.0 * r.q) + 1.1774 * r.spread_hz;
}

// Two resonances whose peaks overlap are still two where one is this many times wider than the
// other: a broad pedestal under a narrow peak, a shape no single resonance makes, whereas one
// peak split in two gives two of about its width.
constexpr double kPedestal = 3.0;

// A model resonance as a start of the periodogram's fit.
SpectralLine::Narrowband narrowband_of(const Component& c) {
  SpectralLine::Narrowband nb;
  nb.frequency_hz = as<Resonance>(c).frequency_hz;
  nb.q = as<Resonance>(c).q;
  nb.spread_hz = as<Resonance>(c).spread_hz;
  return nb;
}

// c's search started from (f0, q): q off its bound, and f0 too when `f0_searched`.
void start_at(Component& c, std::pair<double, double> f0_q, bool f0_searched) {
  std::tie(as<Resonance>(c).frequency_hz, as<Resonance>(c).q) = f0_q;
  c.q_bound = 0;
  if (f0_searched) c.nl_bound = 0;
}

// The periodogram's shape for c; a wandering one's wander_s is measured once a start is chosen
// (measure_wander).
void set_shape(Component& c, const SpectralLine::Narrowband& nb) {
  Resonance& r = as<Resonance>(c);
  r.frequency_hz = nb.frequency_hz;
  c.nl_sigma = nb.frequency_sigma;
  r.q = nb.q;
  c.q_sigma = nb.q_sigma;
  r.spread_hz = nb.spread_hz;
  c.spread_sigma = nb.spread_hz > 0.0 ? nb.spread_sigma : kNaN;
  r.wander_s = 0.0;
  c.nl_bound = c.q_bound = 0;
  c.nl_free = false;
  c.psd_shape = true;
}

// The wander's correlation time of every wandering resonance the search added, on its frequency's
// track through the record (the curve's fit does not depend on it: only the edf and the replicas
// do, so the starts that lose never need it).
void measure_wander(std::vector<Component>& comps, const Witnesses& seen) {
  for (Component& c : comps)
    if (Resonance* r = std::get_if<Resonance>(&c.part); r && c.psd_shape && r->spread_hz > 0.0)
      r->wander_s = wander_time(seen.record, psd_rate_hz(*seen.periodogram), r->frequency_hz,
                                r->spread_hz, r->q);
}

// The new resonance comps[idx] and the model's resonances beside its peak measured together on
// the periodogram (fit_peak_shapes), from the curve's f0 and q (and q from 2 to 128 by factors
// of 4: a q at a bound is no start). The new one and the others the search added take the
// periodogram's f0, q and spread (psd_shape: sigma stays the curve's to fit); given and witnessed
// resonances join the fit, so that their peaks are not taken for the new one, and stay as they
// are. False, the components unchanged, when the periodogram shows no new peak there.
bool shape_on_periodogram(Fit& fit, std::size_t idx, const Witnesses& seen, double false_alarm) {
  std::vector<SpectralLine::Narrowband> present;
  std::vector<std::size_t> which;
  for (std::size_t i = 0; i < idx; ++i)
    if (is<Resonance>(fit.comps[i])) {
      which.push_back(i);
      present.push_back(narrowband_of(fit.comps[i]));
    }
  const Component& c = fit.comps[idx];
  const Resonance& r = as<Resonance>(c);
  std::vector<double> q_starts{2.0, 8.0, 32.0, 128.0};
  if (c.q_bound == 0) q_starts.push_back(r.q);
  const auto shapes =
      fit_peak_shapes(*seen.periodogram, present, r.frequency_hz, q_starts, false_alarm);
  if (shapes.empty()) return false;
  for (std::size_t j = 0; j < which.size(); ++j) {
    Component& o = fit.comps[which[j]];
    if (shapes[j].found && !o.given && !o.pinned) set_shape(o, shapes[j]);
  }
  set_shape(fit.comps[idx], shapes.back());
  return true;
}

// The new resonance's shape on the periodogram from the curve's f0 and, beside each resonance
// the periodogram has shaped already, from 1.2 times and 1 / 1.2 times its f0 at q 4: a peak
// need not be one Lorentzian (the ADIS16405 z gyroscopes' has a broad shoulder 3-5 Hz above
// it, q 4-6, which the curve's search, its ripples taken, does not find). Of the starts the
// periodogram confirms, the one whose fit on the curve has the lowest chi-square; no components
// when none. With `beside` false, from the given f0 alone (the other starts: the shoulders were
// tried from the curve's). The wander is measured by the caller, on the start that wins.
Fit shaped_on_periodogram(const Fit& searched, std::size_t idx, const Curve& cv, const Bases& b,
                          const Witnesses& seen, double false_alarm, bool beside = true) {
  Fit best;
  if (seen.periodogram == nullptr) return best;
  const Resonance& r = as<Resonance>(searched.comps[idx]);
  std::vector<std::pair<double, double>> starts{{r.frequency_hz, r.q}};
  for (std::size_t i = 0; i < idx && beside; ++i)
    if (const Component& o = searched.comps[i]; is<Resonance>(o) && o.psd_shape) {
      const double f = as<Resonance>(o).frequency_hz;
      starts.insert(starts.end(), {{1.2 * f, 4.0}, {f / 1.2, 4.0}});
    }
  for (std::size_t s = 0; s < starts.size(); ++s) {
    Fit trial = searched;
    Component& c = trial.comps[idx];
    if (s > 0) start_at(c, starts[s], false);
    if (!shape_on_periodogram(trial, idx, seen, false_alarm)) continue;
    trial = fit_components(std::move(trial.comps), cv, b);
    if (best.comps.empty() || trial.chi2 < best.chi2) best = std::move(trial);
  }
  return best;
}

// The note when resonance comps[idx] is not a distinct instance beside the model's others
// (resonance_candidate); empty when it is.
std::string overlap_note(const std::vector<Component>& comps, std::size_t idx) {
  const Component& r = comps[idx];
  const double f = as<Resonance>(r).frequency_hz;
  for (std::size_t i = 0; i < idx; ++i) {
    const Component& o = comps[i];
    if (!is<Resonance>(o)) continue;
    const double wide = std::max(half_width(r), half_width(o));
    const double narrow = std::min(half_width(r), half_width(o));
    if (std::abs(f - as<Resonance>(o).frequency_hz) <= half_width(r) + half_width(o) &&
        wide < kPedestal * narrow)
      return "its peak at " + std::to_string(f) + " Hz (q " + std::to_string(as<Resonance>(r).q) +
             ") overlaps " + component_label(comps, i) + "'s";
  }
  return {};
}

// Of the other starts, the shaped fit the periodogram confirms, at the false alarm shared among
// them, as a distinct instance, with the lowest chi-square on the curve; no components when
// none is.
Fit other_start_shaped(const Fit& searched, std::size_t idx, const Curve& cv, const Bases& b,
                       const Witnesses& seen,
                       const std::vector<std::pair<double, double>>& starts) {
  const double alarm =
      seen.line_false_alarm / static_cast<double>(std::max<std::size_t>(1, starts.size()));
  Fit best;
  for (const auto& [f0, q] : starts) {
    Fit start = searched;
    start_at(start.comps[idx], {f0, q}, true);
    Fit shaped = shaped_on_periodogram(start, idx, cv, b, seen, alarm, false);
    if (shaped.comps.empty() || !overlap_note(shaped.comps, idx).empty()) continue;
    if (best.comps.empty() || shaped.chi2 < best.chi2) best = std::move(shaped);
  }
  return best;
}

// The starts beside the curve's best: its grid's other minima (`curve`), then the
// periodogram's broad humps (broad_peaks, at q 8) away from the peaks of the model's resonances
// (two half-widths, or the hump's band, 1/16 octave), the new one (comps' last) not counted.
std::vector<std::pair<double, double>> other_starts(std::vector<std::pair<double, double>> curve,
                                                    const std::vector<Component>& comps,
                                                    const Curve& cv, const Witnesses& seen) {
  for (const auto& peak : broad_peaks(*seen.periodogram, 1.0 / cv.tau.back(), kOtherStarts)) {
    const double f = peak.first;
    const bool modelled = std::any_of(comps.begin(), comps.end() - 1, [&](const Component& o) {
      if (!is<Resonance>(o)) return false;
      const double f0 = as<Resonance>(o).frequency_hz;
      return std::abs(f - f0) <= 2.0 * half_width(o) || std::abs(std::log2(f / f0)) <= 1.0 / 16.0;
    });
    if (!modelled) curve.emplace_back(f, 8.0);
  }
  return curve;
}

// The grid's best chi-square at one frequency, over q.
struct GridRow {
  double ln_f = 0.0, ln_q = 0.0;
  double chi2 = std::numeric_limits<double>::infinity();
};

// The grid's local minima over the frequency other than the best's (at ln_best_f), best first:
// at most kOtherStarts, each an octave or more from the best and from those before it (the
// ripples of one peak are within an octave of it).
std::vector<std::pair<double, double>> other_minima(const std::vector<GridRow>& rows,
                                                    double ln_best_f) {
  std::vector<const GridRow*> minima;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if ((i == 0 || rows[i].chi2 < rows[i - 1].chi2) &&
        (i + 1 == rows.size() || rows[i].chi2 <= rows[i + 1].chi2))
      minima.push_back(&rows[i]);
  std::sort(minima.begin(), minima.end(),
            [](const GridRow* a, const GridRow* c) { return a->chi2 < c->chi2; });
  std::vector<double> taken{ln_best_f};
  std::vector<std::pair<double, double>> out;
  for (const GridRow* r : minima) {
    if (out.size() == kOtherStarts) break;
    if (std::any_of(taken.begin(), taken.end(),
                    [&](double f) { return std::abs(r->ln_f - f) < std::numbers::ln2; }))
      continue;
    taken.push_back(r->ln_f);
    out.emplace_back(std::exp(r->ln_f), std::exp(r->ln_q));
  }
  return out;
}

}  // namespace

std::vector<double> resonance_curve(const Resonance& r, const Curve& cv, const Lowpass& lp,
                                    double rate_hz) {
  return resonance_avar(r, rate_hz, cv.m, lowpass_autocorrelation(lp, rate_hz));
}

// The frequency on a log grid of 8 per octave from 1 / (longest tau) (a slower resonance shows
// no ripple inside the taus) to 0.4 rate (above, inside a sensor's filter transition, a peak
// acts on the shortest tau alone, where it stood in for the filter's shape on a real z
// gyroscope: frequency_hz > 48 Hz with q > 2048 at 100 Hz), times q on a grid of factors of 4, the
// free coefficients fitted at each point; then, from the best point (or the present values when
// `grid` is false: the final refit), golden-section searches on ln f0 and ln q in turn, each
// within one grid step of the best, three times (once in the final refit). The Allan curve
// oscillates in f0 (its ripples are at tau ~ k / f0), so the grid must be finer than a ripple's
// shift; q moves the curve smoothly. A frequency within a grid step of either end of its range, a q
// within 5 % of either end of its, is marked as a bound.
Fit search_resonance(std::vector<Component> comps, std::size_t idx, const Curve& cv, const Bases& b,
                     bool grid, std::vector<std::pair<double, double>>* others) {
  const auto eval_on = [&](std::vector<Component>& own, double ln_f, double ln_q) {
    as<Resonance>(own[idx]).frequency_hz = std::exp(ln_f);
    as<Resonance>(own[idx]).q = std::clamp(std::exp(ln_q), kQLo, kQHi);  // exp(log(x)) may round
    return fit_components(own, cv, b);
  };
  const auto eval = [&](double ln_f, double ln_q) { return eval_on(comps, ln_f, ln_q); };
  const double f_lo = std::log(1.0 / cv.tau.back()), f_hi = std::log(0.4 * b.rate_hz);
  // q beyond pi f0 (longest tau) keeps the ripples past every tau measured, where the curve
  // cannot tell it from a line: the top of q's range at f0, a lower limit when reached.
  const double q_lo = std::log(kQLo);
  const auto q_top = [&](double ln_f) {
    return std::log(
        std::min(kQHi, std::max(4.0 * kQLo, std::numbers::pi * std::exp(ln_f) * cv.tau.back())));
  };
  const double f_step = std::numbers::ln2 / 8.0, q_step = 2.0 * std::numbers::ln2;
  double best_f = std::log(as<Resonance>(comps[idx]).frequency_hz),
         best_q = std::log(as<Resonance>(comps[idx]).q);
  double best_chi2 = std::numeric_limits<double>::infinity();
  if (grid) {
    const int n_f = static_cast<int>(std::ceil((f_hi - f_lo) / f_step)) + 1;
    std::vector<GridRow> rows(static_cast<std::size_t>(n_f));
    // Each frequency's fits over q are independent of the others' (fit_components of a copy of
    // the components): they are made as tasks (for_each_index, a row each) and read in the grid's
    // order below, so the best point is the same whatever thread made each fit.
    std::vector<std::vector<std::pair<double, double>>> fits(rows.size());
    for_each_index(n_f, 1, [&](std::int64_t i) {
      const auto row = static_cast<std::size_t>(i);
      std::vector<Component> own = comps;
      rows[row].ln_f = std::min(f_lo + f_step * static_cast<double>(i), f_hi);
      const double ln_f = rows[row].ln_f;
      for (int j = 0; q_lo + q_step * (j - 1) < q_top(ln_f); ++j) {
        const double lq = std::min(q_lo + q_step * j, q_top(ln_f));
        fits[row].emplace_back(lq, eval_on(own, ln_f, lq).chi2);
      }
    });
    for (std::size_t i = 0; i < rows.size(); ++i) {
      GridRow& row = rows[i];
      for (const auto& [lq, c] : fits[i]) {
        if (c < row.chi2) std::tie(row.chi2, row.ln_q) = std::tuple(c, lq);
        if (c < best_chi2) {
          best_chi2 = c;
          best_f = row.ln_f;
          best_q = lq;
        }
      }
    }
    if (others != nullptr) *others = other_minima(rows, best_f);
  }
  double chi2 = grid ? best_chi2 : eval(best_f, best_q).chi2;
  // Searched again (not `grid`), the values move only for a chi-square lower by more than 1, a
  // change of one standard deviation in one parameter: q is often weakly determined (q = 29 +- 18
  // on a 600 s record of a q = 40 resonance), and a flat direction let three passes walk it to
  // 1201 with no gain.
  const double margin = grid ? 0.0 : 1.0;
  const auto keep = [&](double lf, double lq) {
    const double c = eval(lf, lq).chi2;
    if (!(c <= chi2 - margin)) return;
    chi2 = c;
    best_f = lf;
    best_q = lq;
  };
  for (int pass = 0; pass < (grid ? 3 : 1); ++pass) {
    keep(golden_min([&](double x) { return eval(x, best_q).chi2; }, std::max(best_f - f_step, f_lo),
                    std::min(best_f + f_step, f_hi)),
         best_q);
    keep(best_f,
         golden_min([&](double x) { return eval(best_f, x).chi2; }, std::max(best_q - q_step, q_lo),
                    std::min(best_q + q_step, q_top(best_f))));
  }
  Fit out = eval(best_f, best_q);
  out.comps[idx].nl_bound = best_f < f_lo + f_step ? -1 : best_f > f_hi - f_step ? 1 : 0;
  out.comps[idx].q_bound = best_q < q_lo + 0.05 ? -1 : best_q > q_top(best_f) - 0.05 ? 1 : 0;
  return out;
}

// Resonance candidate: a new component, its frequency and q searched over their whole range
// with the others' coefficients as `base` has them, then its shape measured on the periodogram.
// A second resonance is a distinct instance only where the two peaks are resolved: their
// frequencies further apart than the sum of their half-widths at half power (half_width;
// closer, two are one peak re-split) or one of them a pedestal under the other (kPedestal); else
// the candidate comes back with a note and no fit. A real narrowband noise need not be one
// Lorentzian: the ADIS16405 z gyroscopes' wandering peak at 17-21 Hz has a broad pedestal about
// 2 Hz above it (q 4-5).
CandidateFit resonance_candidate(std::vector<Component> base, const Curve& cv, const Bases& b,
                                 const Witnesses& seen, const std::function<double(int)>& penalty) {
  CandidateFit out = resonance_room(base);
  if (!out.info.note.empty()) return out;
  base.push_back(searched_component(Resonance{}));
  const std::size_t idx = base.size() - 1;
  std::vector<std::pair<double, double>> others;
  out.fit = search_resonance(std::move(base), idx, cv, b, true, &others);
  // The periodogram measures the peak's shape, which the curve sees only through its ripples: a
  // q at either end of its range on the curve is no estimate (beyond a few hundred, and for a
  // broad peak beside the sensor's filter, the curve's shape hardly depends on it: the ADIS16405
  // accelerometers' hump at 9.5-11 Hz, q about 10 in their periodograms, went to q > 79380 on the
  // curve as a line), and a peak whose frequency wanders is a Lorentzian to the curve (the
  // ADIS16405 z gyroscopes'). Where the periodogram shows no peak near a q at a bound, the
  // curve's feature is no narrowband process (an ADIS16405 z gyroscope's curve named one at
  // 6.9 Hz with q > 51511 beside its real peak at 19.5 Hz). The other starts (other_starts:
  // the curve's next minima and the periodogram's broad humps) are tried too, the periodogram's
  // false alarm shared among them, and the one with the lowest chi-square replaces the curve's
  // own when it fits better, its parameters charged (`penalty`: the criterion's threshold for
  // k parameters in chi-square units), or the curve's was withdrawn: two humps' ripples can
  // cancel on the curve, so that neither is its best (the ADIS16405 imu2 z accelerometer's at
  // 10 and 35 Hz; the curve was best at 0.0012 Hz, q at 2, where its periodogram has nothing).
  bool withdrawn = false;
  const Fit searched = out.fit;
  if (Fit shaped = shaped_on_periodogram(out.fit, idx, cv, b, seen, seen.line_false_alarm);
      !shaped.comps.empty()) {
    out.fit = std::move(shaped);
  } else if (seen.periodogram != nullptr && out.fit.comps[idx].q_bound != 0) {
    const Resonance& r = as<Resonance>(out.fit.comps[idx]);
    out.info.note = "q at a bound of its range on the curve (" + std::to_string(r.q) + " at " +
                    std::to_string(r.frequency_hz) +
                    " Hz) and no peak near there in the periodogram";
    withdrawn = true;
  }
  if (!withdrawn) out.info.note = overlap_note(out.fit.comps, idx);
  withdrawn = withdrawn || !out.info.note.empty();
  if (seen.periodogram == nullptr) {
    if (withdrawn) out.fit = {};
    return out;
  }
  Fit next = other_start_shaped(searched, idx, cv, b, seen,
                                other_starts(std::move(others), searched.comps, cv, seen));
  if (!next.comps.empty() &&
      (withdrawn || next.chi2 + penalty(resonance_parameters(next.comps[idx])) <
                        out.fit.chi2 + penalty(resonance_parameters(out.fit.comps[idx])))) {
    out.info.note += (out.info.note.empty() ? "" : "; ") + std::string("a peak at ") +
                     std::to_string(as<Resonance>(next.comps[idx]).frequency_hz) +
                     " Hz from another start";
    out.fit = std::move(next);
  } else if (withdrawn) {
    out.fit = {};
  }
  measure_wander(out.fit.comps, seen);
  return out;
}

// Resonance named from its PSD witness, a periodogram peak wider than a line: f0, q and sigma as
// the periodogram measured them (fit_narrowband), pinned like a witnessed line's. The peak is
// seen through the sensor's filter; the model's resonance is the one before it, sigma divided by
// the filter's gain at f0 (the peak is narrow against the filter's response).
CandidateFit witnessed_resonance(std::vector<Component> base, const SpectralLine::Narrowband& nb,
                                 const Curve& cv, const Bases& b) {
  CandidateFit out = resonance_room(base);
  if (!out.info.note.empty()) return out;
  const double gain = std::sqrt(lowpass_gain2(lowpass_of(base), b.rate_hz, nb.frequency_hz));
  Component c = component(Resonance{nb.sigma / gain, nb.frequency_hz, nb.q});
  c.nl_sigma = nb.frequency_sigma;
  c.q_sigma = nb.q_sigma;
  c.coef_sigma = nb.sigma_sigma / gain;
  c.pinned = true;
  base.push_back(c);
  out.fit = fit_components(std::move(base), cv, b);
  out.info.note = "PSD peak at " + std::to_string(nb.frequency_hz) +
                  " Hz wider than a line, fitted as a resonance: q " + std::to_string(nb.q) +
                  " +- " + std::to_string(nb.q_sigma) + ", sigma " +
                  std::to_string(as<Resonance>(c).sigma);
  return out;
}

}  // namespace allanlot::kernels::diagnose_detail
