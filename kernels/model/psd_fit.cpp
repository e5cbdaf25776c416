// Eq. (3) fitted to the Welch PSD; see psd_fit.hpp for the model and the estimator.
#include "kernels/model/psd_fit.hpp"

#include "kernels/common/parallel.hpp"

#include "kernels/model/least_squares.hpp"
#include "kernels/spectral/fft.hpp"

#include <fftw3.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr auto kR = static_cast<std::size_t>(Term::R);
constexpr auto kK = static_cast<std::size_t>(Term::K);
constexpr auto kB = static_cast<std::size_t>(Term::B);
constexpr auto kN = static_cast<std::size_t>(Term::N);
constexpr auto kQ = static_cast<std::size_t>(Term::Q);
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Correlation of two Hann periodogram bins d = 1, 2 apart for a locally white spectrum,
// |sum w^2 e^{-2 pi i d t/L}|^2 / (sum w^2)^2 with w^2 = 3/8 - cos/2 + cos(2.)/8: (1/4 / 3/8)^2
// and (1/16 / 3/8)^2 (Percival & Walden 1993, sec. 6.6); 0 beyond.
constexpr double kR1 = 4.0 / 9.0;
constexpr double kR2 = 1.0 / 36.0;

// sum_{t=0}^{M-1} cos(a + b t) = sin(M b / 2) / sin(b / 2) cos(a + (M - 1) b / 2) (Dirichlet),
// for sin(b / 2) != 0.
double cos_sum(double a, double b, std::int64_t m) {
  if (m <= 0) return 0.0;
  const double md = static_cast<double>(m);
  return std::sin(0.5 * md * b) / std::sin(0.5 * b) * std::cos(a + 0.5 * (md - 1.0) * b);
}

// Autocorrelation a(d) = sum_{t=0}^{L-1-d} w_t w_{t+d} of the periodic Hann window
// w_t = 1/2 - cos(theta t)/2, theta = 2 pi / L, in closed form: expanding the product,
// w_t w_{t+d} = 1/4 - cos(theta t)/4 - cos(theta (t+d))/4 + cos(theta d)/8 + cos(theta (2t+d))/8,
// each summed over t = 0 .. M-1, M = L - d, by cos_sum. Exact to rounding (a(0) = 3L/8).
std::vector<double> hann_autocorrelation(std::int64_t L) {
  const double th = 2.0 * kPi / static_cast<double>(L);
  std::vector<double> a(static_cast<std::size_t>(L));
  for (std::int64_t d = 0; d < L; ++d) {
    const std::int64_t m = L - d;
    const double dd = static_cast<double>(d);
    a[static_cast<std::size_t>(d)] = 0.25 * static_cast<double>(m) - 0.25 * cos_sum(0.0, th, m) -
                                     0.25 * cos_sum(th * dd, th, m) +
                                     0.125 * static_cast<double>(m) * std::cos(th * dd) +
                                     0.125 * cos_sum(th * dd, 2.0 * th, m);
  }
  return a;
}

// Rate autocovariance at lag d >= 0 (samples) of unit flicker, up to an additive constant
// (which the Welch sum removes, see psd_fit.hpp): from G(t) = t^2 ln|t| / (2 pi) in units of
// tau0 (tau0's own logarithm only adds a constant), r(d) = [2 G(d) - G(d+1) - G(d-1)].
// For d >= 2 the logarithms are split as ln(d +- 1) = ln d + log1p(+-1/d) so that the d^2 ln d
// parts cancel exactly: r = -2 ln d - (d+1)^2 log1p(1/d) - (d-1)^2 log1p(-1/d), all over 2 pi.
double flicker_rate_cov(std::int64_t d) {
  if (d == 0) return 0.0;
  if (d == 1) return -4.0 * std::numbers::ln2 / (2.0 * kPi);
  const double x = static_cast<double>(d);
  return (-2.0 * std::log(x) - (x + 1) * (x + 1) * std::log1p(1.0 / x) -
          (x - 1) * (x - 1) * std::log1p(-1.0 / x)) /
         (2.0 * kPi);
}

// Runs a length-L real-to-complex FFT of `in` into `out` (L/2 + 1 bins) with fft::Plan
// (FFTW_ESTIMATE, deterministic, see kernels/spectral/fft.hpp).
class RealFft {
public:
  explicit RealFft(std::int64_t L)
      : in_(fft::alloc<double>(static_cast<std::size_t>(L))),
        out_(fft::alloc<fftw_complex>(static_cast<std::size_t>(L / 2 + 1))),
        plan_(fft::Plan::r2c(static_cast<int>(L), in_.get(), out_.get(), "welch_term_psd")) {}
  double* in() { return in_.get(); }
  const fftw_complex* run() {
    plan_.execute();
    return out_.get();
  }

private:
  fft::Buffer<double> in_;
  fft::Buffer<fftw_complex> out_;
  fft::Plan plan_;
};

void check_options(const PsdFitOptions& o) {
  if (o.first_bin < 2)
    throw std::invalid_argument("psd_fit: first_bin must be >= 2, got " +
                                std::to_string(o.first_bin));
  if (o.bins_per_decade < 1 || o.n_linear < 0 || o.max_iterations < 1 ||
      !(o.detection_sigmas > 0) || !(o.upper_confidence > 0.5 && o.upper_confidence < 1) ||
      !(o.tolerance > 0) || !(o.rank_threshold > 0))
    throw std::invalid_argument("psd_fit: options out of range");
}

}  // namespace

std::array<std::vector<double>, kNumTerms> welch_term_psd(std::int64_t L, double rate_hz,
                                                          int threads) {
  if (L < 16 || L % 2 != 0 || L >= (std::int64_t{1} << 30))
    throw std::invalid_argument("welch_term_psd: segment_length must be even, >= 16 and < 2^30, "
                                "got " +
                                std::to_string(L));
  if (!std::isfinite(rate_hz) || rate_hz <= 0)
    throw std::invalid_argument("welch_term_psd: rate_hz must be finite and > 0");
  const double tau0 = 1.0 / rate_hz;
  const std::int64_t nb = L / 2 + 1;
  const auto nbs = static_cast<std::size_t>(nb);
  const auto Ls = static_cast<std::size_t>(L);
  const std::vector<double> a = hann_autocorrelation(L);
  const double sum_w2 = a[0];
  // E[P_k] = c_k / (rate_hz sum_w2) sum_{|d|<L} r(d) a(d) cos(2 pi k d / L); the lag sum is
  // the DFT of u(j) = v(j) + v(L - j) (v = r a, even in d, folded modulo L), which is real.
  const auto c_k = [&](std::int64_t k) { return (k == 0 || k == L / 2) ? 1.0 : 2.0; };
  const double norm = 1.0 / (rate_hz * sum_w2);

  std::array<std::vector<double>, kNumTerms> out;
  for (auto& v : out)
    v.assign(nbs, kNaN);
  const auto lag_sum_term = [&](auto&& r, std::vector<double>& dst) {
    RealFft fft(L);
    double* u = fft.in();
    u[0] = r(0) * a[0];
    for (std::int64_t j = 1; j < L; ++j)
      u[j] = r(j) * a[static_cast<std::size_t>(j)] + r(L - j) * a[static_cast<std::size_t>(L - j)];
    const fftw_complex* x = fft.run();
    for (std::int64_t k = 2; k < nb; ++k)
      dst[static_cast<std::size_t>(k)] = c_k(k) * norm * x[k][0];
  };
  // The four parts below are independent (each writes its own terms), so they run as one
  // OpenMP task each: the same values for any thread count.
  const auto part = [&](int which) {
    switch (which) {
    case 0:
      // Rate random walk, unit K^2: G(t) = |t|^3 / 12 gives r(0) = -tau0 / 6,
      // r(d) = -tau0 d / 2 (the exact second difference of |d|^3 / 12, times tau0^3 / tau0^2).
      lag_sum_term(
          [&](std::int64_t d) {
            return d == 0 ? -tau0 / 6.0 : -0.5 * tau0 * static_cast<double>(d);
          },
          out[kK]);
      break;
    case 1:  // Flicker, unit B^2.
      lag_sum_term([&](std::int64_t d) { return flicker_rate_cov(d); }, out[kB]);
      break;
    case 2:
      // White, unit N^2: r = delta_d / tau0, so E[P_k] = c_k a(0) / (rate_hz tau0 sum_w2) = c_k.
      // Quantization, unit Q^2: white phase of variance Q^2 differenced, r(0) = 2 / tau0^2,
      // r(+-1) = -1 / tau0^2.
      for (std::int64_t k = 2; k < nb; ++k) {
        const auto ks = static_cast<std::size_t>(k);
        out[kN][ks] = c_k(k);
        const double ck = std::cos(2.0 * kPi * static_cast<double>(k) / static_cast<double>(L));
        out[kQ][ks] = c_k(k) * norm * (2.0 * a[0] - 2.0 * a[1] * ck) / (tau0 * tau0);
      }
      break;
    default: {
      // Ramp, unit R^2: the segment is tau0 R t plus a constant; |sum_t t w_t e^{-2 pi i k t/L}|^2.
      RealFft fft(L);
      double* u = fft.in();
      for (std::size_t t = 0; t < Ls; ++t)
        u[t] = static_cast<double>(t) *
               (0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(t) / static_cast<double>(L)));
      const fftw_complex* x = fft.run();
      for (std::int64_t k = 2; k < nb; ++k)
        out[kR][static_cast<std::size_t>(k)] =
            c_k(k) * norm * tau0 * tau0 * (x[k][0] * x[k][0] + x[k][1] * x[k][1]);
    }
    }
  };
  [[maybe_unused]] const int nt = std::min(4, resolve_threads(threads));
  ExceptionCollector errors;
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (int which = 0; which < 4; ++which)
    errors.run([&] { part(which); });
  errors.rethrow();
  return out;
}

const std::array<std::vector<double>, kNumTerms>& WelchTermCache::get(std::int64_t segment_length,
                                                                      double rate_hz, int threads) {
  if (segment_length != segment_length_ || rate_hz != rate_hz_ || terms_[0].empty()) {
    terms_ = welch_term_psd(segment_length, rate_hz, threads);
    segment_length_ = segment_length;
    rate_hz_ = rate_hz;
  }
  return terms_;
}

namespace {

// The binned PSD and the binned regressors on the rows where every one of them is usable.
struct BinnedDesign {
  BinnedPsd yb;
  std::vector<std::size_t> rows;  // indices into yb
  Eigen::MatrixXd x;              // rows x 5: each term's expected binned value per unit theta
  Eigen::VectorXd y, edf;         // binned PSD and its edf
  std::vector<std::int64_t> n_avg;
  double y_min_pos = std::numeric_limits<double>::infinity();
};

// Bins the PSD and each term's expected value identically; bins below first_bin are NaN in
// the regressors (and masked here), so rows that include them drop out. Returns false when
// fewer rows remain than the fit needs (NoData).
bool bin_design(const PsdResult& psd, const std::array<std::vector<double>, kNumTerms>& regs,
                const PsdFitOptions& opt, BinnedDesign& d) {
  const std::int64_t L = psd.segment_length;
  d.yb = log_bin(psd, opt.bins_per_decade, opt.n_linear);
  std::array<BinnedPsd, kNumTerms> xb;
  for (std::size_t j = 0; j < regs.size(); ++j) {
    PsdResult pj = psd;
    pj.psd = regs[j];
    for (std::int64_t k = 0; k < opt.first_bin && k < L / 2 + 1; ++k)
      pj.psd[static_cast<std::size_t>(k)] = kNaN;
    xb[j] = log_bin(pj, opt.bins_per_decade, opt.n_linear);
  }
  const BinnedPsd& yb = d.yb;
  for (std::size_t i = 0; i < yb.size(); ++i) {
    bool ok = std::isfinite(yb.psd[i]) && yb.psd[i] >= 0 && yb.edf[i] > 0;
    for (const auto& x : xb)
      ok = ok && std::isfinite(x.psd[i]);
    if (ok) d.rows.push_back(i);
  }
  const auto p = static_cast<Eigen::Index>(d.rows.size());
  if (p < kNumTerms + 1) return false;

  d.x.resize(p, kNumTerms);
  d.y.resize(p);
  d.edf.resize(p);
  d.n_avg.resize(d.rows.size());
  for (Eigen::Index i = 0; i < p; ++i) {
    const std::size_t r = d.rows[static_cast<std::size_t>(i)];
    for (int j = 0; j < kNumTerms; ++j)
      d.x(i, j) = xb[static_cast<std::size_t>(j)].psd[r];
    d.y(i) = yb.psd[r];
    d.edf(i) = yb.edf[r];
    d.n_avg[static_cast<std::size_t>(i)] = yb.n_avg[r];
    if (d.y(i) > 0) d.y_min_pos = std::min(d.y_min_pos, d.y(i));
  }
  // Every column is an expected power, >= 0; the lag sums of K and B can round to tiny
  // negative values where their spectra are 1e-16 of the sum's terms, clipped here.
  d.x = d.x.cwiseMax(0.0);
  return true;
}

// Covariance of the binned values under the fitted model: var = 2 model^2 / edf on the
// diagonal; neighbouring rows share the correlation of their adjacent Welch bins (see the
// header), cov(y_b, y_b+1) = sum over the boundary pairs (d = 1 once, d = 2 up to twice) of
// r_d sqrt(var P_k var P_k') / (n_b n_b+1), var P_k = 2 model^2 / nu_k with nu_k the Welch
// bins' edf (taken at the boundary as the rows' values).
Eigen::MatrixXd binned_covariance(const BinnedDesign& d, const Eigen::VectorXd& model,
                                  const PsdResult& psd) {
  const auto p = static_cast<Eigen::Index>(d.rows.size());
  Eigen::MatrixXd sigma = Eigen::MatrixXd::Zero(p, p);
  for (Eigen::Index i = 0; i < p; ++i)
    sigma(i, i) = 2.0 * model(i) * model(i) / d.edf(i);
  for (Eigen::Index i = 0; i + 1 < p; ++i) {
    const std::size_t r0 = d.rows[static_cast<std::size_t>(i)];
    const std::size_t r1 = d.rows[static_cast<std::size_t>(i + 1)];
    if (r1 != r0 + 1) continue;
    const auto na = static_cast<double>(d.n_avg[static_cast<std::size_t>(i)]);
    const auto nb2 = static_cast<double>(d.n_avg[static_cast<std::size_t>(i + 1)]);
    // nu: the edf of one Welch bin, the same for every bin between DC and Nyquist.
    const double nu = psd.edf[2];
    const double rr = kR1 + (na > 1 ? kR2 : 0.0) + (nb2 > 1 ? kR2 : 0.0);
    sigma(i, i + 1) = sigma(i + 1, i) = rr * 2.0 * model(i) * model(i + 1) / (nu * na * nb2);
  }
  return sigma;
}

}  // namespace

PsdFitResult psd_fit(const PsdResult& psd, const PsdFitOptions& opt, WelchTermCache* terms) {
  check_options(opt);
  const std::int64_t L = psd.segment_length;
  if (L < 16 || psd.size() != static_cast<std::size_t>(L / 2 + 1) || psd.psd.size() != psd.size() ||
      psd.edf.size() != psd.size())
    throw std::invalid_argument("psd_fit: psd is not a Welch result (sizes disagree)");
  PsdFitResult res;
  WelchTermCache local;
  const auto& regs = (terms ? *terms : local).get(L, psd.rate_hz, opt.threads);
  BinnedDesign d;
  if (!bin_design(psd, regs, opt, d)) return res;  // NoData
  if (!std::isfinite(d.y_min_pos)) return res;     // NoData: an all-zero PSD
  const Eigen::MatrixXd& x = d.x;
  const Eigen::VectorXd& y = d.y;

  // Iteratively reweighted NNLS (least_squares.hpp); the model is kept above 1e-300 so that
  // the next weights stay finite.
  Eigen::VectorXd model = y.cwiseMax(d.y_min_pos);
  detail::WeightedDesign design;
  Eigen::MatrixXd masked;
  detail::Qr qr(x.rows(), kNumTerms);
  const detail::Reweighting reweighting{opt.rank_threshold, opt.max_iterations, opt.tolerance,
                                        1e-300};
  const detail::ReweightedNnls solved =
      detail::reweighted_nnls(x, y, d.edf, model, reweighting, design, masked, qr);
  if (!detail::take_solution(res, solved, FitStatus::RankDeficient)) return res;
  const detail::Theta& theta = solved.theta;

  const Eigen::MatrixXd sigma = binned_covariance(d, model, psd);
  // Sandwich covariance of the weighted estimator on a set of free columns.
  const auto sandwich = [&](const detail::Estimator& amat, detail::TermCov& cov) {
    cov = amat * sigma * amat.transpose();
  };
  detail::Estimator a_free;
  const int n_free = detail::fit_terms(theta, y, design, opt.detection_sigmas, opt.upper_confidence,
                                       sandwich, masked, qr, res.terms, res.theta_cov, a_free);

  const Eigen::VectorXd r = y - x * theta;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(sigma);
  res.chi2 = r.dot(ldlt.solve(r));
  res.dof = static_cast<int>(x.rows()) - n_free;
  res.chi2_dof = res.dof > 0 ? res.chi2 / res.dof : 0.0;

  const std::size_t pu = d.rows.size();
  res.f_hz.resize(pu);
  res.psd.resize(pu);
  res.edf.resize(pu);
  res.psd_model.resize(pu);
  const Eigen::VectorXd fitted = x * theta;
  for (std::size_t i = 0; i < pu; ++i) {
    res.f_hz[i] = d.yb.f_hz[d.rows[i]];
    res.psd[i] = y(static_cast<Eigen::Index>(i));
    res.edf[i] = d.edf(static_cast<Eigen::Index>(i));
    res.psd_model[i] = fitted(static_cast<Eigen::Index>(i));
  }
  res.status = solved.converged ? judge_fit(res.chi2, res.dof) : FitStatus::NoConvergence;
  return res;
}

FitAgreement compare_fits(const std::array<TermFit, kNumTerms>& a,
                          const std::array<TermFit, kNumTerms>& b, double threshold) {
  FitAgreement g;
  for (int j = 0; j < kNumTerms; ++j) {
    const auto js = static_cast<std::size_t>(j);
    const double s = std::hypot(a[js].theta_sigma, b[js].theta_sigma);
    g.z[js] = s > 0 ? (a[js].theta_free - b[js].theta_free) / s : 0.0;
    if (s > 0 && (g.worst_term < 0 || std::abs(g.z[js]) > g.max_abs_z)) {
      g.max_abs_z = std::abs(g.z[js]);
      g.worst_term = j;
    }
  }
  g.agree = g.max_abs_z <= threshold;
  return g;
}

}  // namespace allanlot::kernels
