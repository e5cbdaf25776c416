#include "kernels/uncertainty/confidence.hpp"

#include "kernels/common/parallel.hpp"
#include "kernels/uncertainty/chi2.hpp"
#include "kernels/uncertainty/noise_id.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

void check_confidence(double c) {
  if (!(c > 0.0 && c < 1.0))
    throw std::invalid_argument("confidence must be in (0, 1), got " + std::to_string(c));
}

}  // namespace

Interval chi2_interval(double dev, double edf, double confidence) {
  check_confidence(confidence);
  if (!(edf > 0.0) || !std::isfinite(edf))
    throw std::invalid_argument("chi2_interval: edf must be finite and > 0, got " +
                                std::to_string(edf));
  const double q_hi = chi2_quantile(0.5 * (1.0 + confidence), edf);  // > edf: lower bound
  const double q_lo = chi2_quantile(0.5 * (1.0 - confidence), edf);  // < edf: upper bound
  return {dev * std::sqrt(edf / q_hi), dev * std::sqrt(edf / q_lo)};
}

FiniteDifferenceKind difference_kind(Stat s) {
  const StatInfo& info = stat_info(s);
  if (info.edf != EdfModel::Greenhall)
    throw std::invalid_argument("difference_kind: " + std::string(info.name) +
                                " is not a finite-difference variance");
  return {info.differences.d, info.differences.overlapping, info.differences.modified};
}

namespace {

// The edf of the estimators whose edf is a fit in the record length T / tau (SP1065 eq. (47),
// Table 8; Howe & Tasset; Vernotte et al.): N - F informative points of N scale it by
// (N - F) / N, the fits' leading term b (T / tau).
double shorter(double edf, std::int64_t n_phase, std::int64_t n_filled) {
  if (n_filled <= 0) return edf;
  return edf * static_cast<double>(n_phase - n_filled) / static_cast<double>(n_phase);
}

double edf_rows(Stat s, int alpha, std::int64_t m, std::int64_t n_phase, std::int64_t terms,
                std::int64_t n_filled) {
  switch (stat_info(s).edf) {
  case EdfModel::None:
    return std::numeric_limits<double>::quiet_NaN();
  case EdfModel::Mtotvar:
    // Below m = 10, SP1065 Table 8 promises up to 1.4 times the edf that Stable32's bounds on
    // PHASE.DAT imply (1099 against 791 at m = 1), while MDEV's edf over the same N - 3m + 1
    // terms is within 1.5 % of it at m = 1 .. 8 (docs/statistics.md); from m = 10 on Stable32
    // is above Table 8, which stays (the published, conservative side).
    if (m < 10) return edf_rows(Stat::Mdev, alpha, m, n_phase, terms, n_filled);
    return shorter(edf_mtotvar(alpha, m, n_phase), n_phase, n_filled);
  case EdfModel::Htotvar:
    // Howe's HTOT fits (edf_htotvar) cover FM noise from m = 16 on; below, and for PM noise,
    // the overlapping Hadamard variance's edf (Greenhall & Riley) over the same terms stands
    // in: HTOT averages more (reflected) terms than OHVAR, so this is the conservative side.
    if (m >= 16 && alpha <= 0) return shorter(edf_htotvar(alpha, m, n_phase), n_phase, n_filled);
    return edf_rows(Stat::Ohdev, alpha, m, n_phase, terms, n_filled);
  case EdfModel::Theo1:
    return shorter(edf_theo1(alpha, m, n_phase), n_phase, n_filled);
  case EdfModel::Theoh:
    // Below k = floor(0.1 (N - 1)) a ThêoH row is OADEV (theo.hpp), above it bias-removed Thêo1.
    if (m < (n_phase - 1) / 10) return edf_rows(Stat::Oadev, alpha, m, n_phase, terms, n_filled);
    return shorter(edf_theo1(alpha, m, n_phase), n_phase, n_filled);
  case EdfModel::Pvar:
    // PVAR at m = 1 is the overlapping Allan variance (parabolic.hpp).
    if (m == 1) return edf_rows(Stat::Oadev, alpha, m, n_phase, terms, n_filled);
    return shorter(edf_pvar(alpha, m, n_phase), n_phase, n_filled);
  case EdfModel::Totvar: {
    // Stable32 prints N - 1 terms for every m; fewer mean samples lost to gaps.
    const std::int64_t n_eff = std::min(n_phase, terms + 1);
    return shorter(edf_totvar(alpha, m, n_eff), n_eff, std::min(n_filled, n_eff - 1));
  }
  case EdfModel::Greenhall:
    break;
  }
  const FiniteDifferenceKind kind = difference_kind(s);
  if (n_filled > 0) {
    // F filled points of N: the terms N - F points would give fewer, G(N) - G(N - F), the
    // terms a filled record gains over the same record with its filled points left out.
    const std::int64_t full = greenhall_terms(kind, m, n_phase);
    const std::int64_t kept =
        greenhall_terms(kind, m, std::max<std::int64_t>(n_phase - n_filled, 0));
    terms = std::max<std::int64_t>(terms - (full - kept), 1);
  }
  std::int64_t n_eff = n_phase;
  if (terms < greenhall_terms(kind, m, n_phase))
    n_eff = greenhall_phase_points(kind, m, std::max<std::int64_t>(terms, 1));
  return edf_greenhall(alpha, kind, m, n_eff);
}

}  // namespace

double stat_edf(Stat s, int alpha, std::int64_t m, std::int64_t n_phase, std::int64_t terms,
                std::int64_t n_filled) {
  if (n_filled < 0 || (n_filled > 0 && n_filled >= n_phase))
    throw std::invalid_argument("stat_edf: n_filled must be in [0, n_phase), got " +
                                std::to_string(n_filled));
  return edf_rows(s, alpha, m, n_phase, terms, n_filled);
}

void add_confidence(Stat s, const PhaseData& p, StatResult& r, double confidence, int nthreads,
                    Lag1Cache* cache) {
  check_confidence(confidence);
  const std::size_t rows = r.size();
  if (r.tau_s.size() != rows || r.dev.size() != rows || r.n.size() != rows)
    throw std::invalid_argument("add_confidence: m, tau_s, dev and n must have equal lengths");
  const std::vector<int> alpha = identify_alpha(s, p, r, nthreads, cache);
  std::vector<double> edf(rows), lo(rows), hi(rows);
  ExceptionCollector errors;
  const std::int64_t count = static_cast<std::int64_t>(rows);
#pragma omp parallel for num_threads(resolve_threads(nthreads)) schedule(dynamic, 1)
  for (std::int64_t j = 0; j < count; ++j) {
    errors.run([&] {
      const auto i = static_cast<std::size_t>(j);
      // HTOT's bias correction (Stable32; edf.hpp htotvar_bias) needs this row's noise type;
      // at m = 1 HTOT is OHDEV, which is unbiased.
      if (s == Stat::Htotdev && r.m[i] > 1) r.dev[i] /= std::sqrt(htotvar_bias(alpha[i]));
      edf[i] = stat_edf(s, alpha[i], r.m[i], p.n_points(), r.n[i], p.n_filled);
      if (!has_interval(s)) {
        lo[i] = hi[i] = std::numeric_limits<double>::quiet_NaN();
      } else if (r.dev[i] > 0.0) {
        const Interval ci = chi2_interval(r.dev[i], edf[i], confidence);
        lo[i] = ci.lo;
        hi[i] = ci.hi;
      }
    });
  }
  errors.rethrow();
  r.alpha = alpha;
  r.edf = std::move(edf);
  r.dev_lo = std::move(lo);
  r.dev_hi = std::move(hi);
  r.confidence = confidence;
}

}  // namespace allanlot::kernels
