// Eq. (3) fitted to the Welch PSD; see psd_fit.hpp for the model and the estimator.
#include "kernels/model/psd_fit.hpp"

#include "kernels/model/least_squares.hpp"
#include "kernels/simulate/simulate.hpp"

#include <fftw3.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
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

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};

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

// Runs a length-L real-to-complex FFT of `in` into `out` (L/2 + 1 bins). The plan is made under
// the project's FFTW planner mutex with FFTW_ESTIMATE (deterministic, see psd.hpp).
class RealFft {
public:
  explicit RealFft(std::int64_t L) {
    in_.reset(static_cast<double*>(fftw_malloc(sizeof(double) * static_cast<std::size_t>(L))));
    out_.reset(static_cast<fftw_complex*>(
        fftw_malloc(sizeof(fftw_complex) * static_cast<std::size_t>(L / 2 + 1))));
    if (!in_ || !out_) throw std::bad_alloc();
    std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
    plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(L), in_.get(), out_.get(), FFTW_ESTIMATE);
    if (!plan_) throw std::runtime_error("welch_term_psd: FFTW planning failed");
  }
  ~RealFft() {
    std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
    fftw_destroy_plan(plan_);
  }
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;
  double* in() { return in_.get(); }
  const fftw_complex* run() {
    fftw_execute(plan_);
    return out_.get();
  }

private:
  std::unique_ptr<double[], FftwFree> in_;
  std::unique_ptr<fftw_complex[], FftwFree> out_;
  fftw_plan plan_ = nullptr;
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

std::array<std::vector<double>, kNumTerms> welch_term_psd(std::int64_t L, double rate_hz) {
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
  RealFft fft(L);
  const auto lag_sum_term = [&](auto&& r, std::vector<double>& dst) {
    double* u = fft.in();
    u[0] = r(0) * a[0];
    for (std::int64_t j = 1; j < L; ++j)
      u[j] = r(j) * a[static_cast<std::size_t>(j)] + r(L - j) * a[static_cast<std::size_t>(L - j)];
    const fftw_complex* x = fft.run();
    for (std::int64_t k = 2; k < nb; ++k)
      dst[static_cast<std::size_t>(k)] = c_k(k) * norm * x[k][0];
  };
  // Rate random walk, unit K^2: G(t) = |t|^3 / 12 gives r(0) = -tau0 / 6, r(d) = -tau0 d / 2
  // (the exact second difference of |d|^3 / 12, times tau0^3 / tau0^2).
  lag_sum_term(
      [&](std::int64_t d) { return d == 0 ? -tau0 / 6.0 : -0.5 * tau0 * static_cast<double>(d); },
      out[kK]);
  // Flicker, unit B^2.
  lag_sum_term([&](std::int64_t d) { return flicker_rate_cov(d); }, out[kB]);
  // White, unit N^2: r = delta_d / tau0, so E[P_k] = c_k a(0) / (rate_hz tau0 sum_w2) = c_k.
  // Quantization, unit Q^2: white phase of variance Q^2 differenced, r(0) = 2 / tau0^2,
  // r(+-1) = -1 / tau0^2.
  for (std::int64_t k = 2; k < nb; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    out[kN][ks] = c_k(k);
    const double ck = std::cos(2.0 * kPi * static_cast<double>(k) / static_cast<double>(L));
    out[kQ][ks] = c_k(k) * norm * (2.0 * a[0] - 2.0 * a[1] * ck) / (tau0 * tau0);
  }
  // Ramp, unit R^2: the segment is tau0 R t plus a constant; |sum_t t w_t e^{-2 pi i k t/L}|^2.
  {
    double* u = fft.in();
    for (std::size_t t = 0; t < Ls; ++t)
      u[t] = static_cast<double>(t) *
             (0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(t) / static_cast<double>(L)));
    const fftw_complex* x = fft.run();
    for (std::int64_t k = 2; k < nb; ++k)
      out[kR][static_cast<std::size_t>(k)] =
          c_k(k) * norm * tau0 * tau0 * (x[k][0] * x[k][0] + x[k][1] * x[k][1]);
  }
  return out;
}

const std::array<std::vector<double>, kNumTerms>& WelchTermCache::get(std::int64_t segment_length,
                                                                      double rate_hz) {
  if (segment_length != segment_length_ || rate_hz != rate_hz_ || terms_[0].empty()) {
    terms_ = welch_term_psd(segment_length, rate_hz);
    segment_length_ = segment_length;
    rate_hz_ = rate_hz;
  }
  return terms_;
}

PsdFitResult psd_fit(const PsdResult& psd, const PsdFitOptions& opt, WelchTermCache* terms) {
  check_options(opt);
  const std::int64_t L = psd.segment_length;
  if (L < 16 || psd.size() != static_cast<std::size_t>(L / 2 + 1) || psd.psd.size() != psd.size() ||
      psd.edf.size() != psd.size())
    throw std::invalid_argument("psd_fit: psd is not a Welch result (sizes disagree)");
  PsdFitResult res;
  WelchTermCache local;
  const auto& regs = (terms ? *terms : local).get(L, psd.rate_hz);

  // Bin the PSD and each term's expected value identically; bins below first_bin are NaN in
  // the regressors (and masked here), so rows that include them drop out.
  const BinnedPsd yb = log_bin(psd, opt.bins_per_decade, opt.n_linear);
  std::array<BinnedPsd, kNumTerms> xb;
  for (std::size_t j = 0; j < regs.size(); ++j) {
    PsdResult pj = psd;
    pj.psd = regs[j];
    for (std::int64_t k = 0; k < opt.first_bin && k < L / 2 + 1; ++k)
      pj.psd[static_cast<std::size_t>(k)] = kNaN;
    xb[j] = log_bin(pj, opt.bins_per_decade, opt.n_linear);
  }
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < yb.size(); ++i) {
    bool ok = std::isfinite(yb.psd[i]) && yb.psd[i] >= 0 && yb.edf[i] > 0;
    for (const auto& x : xb)
      ok = ok && std::isfinite(x.psd[i]);
    if (ok) rows.push_back(i);
  }
  const auto p = static_cast<Eigen::Index>(rows.size());
  if (p < kNumTerms + 1) return res;  // NoData

  Eigen::MatrixXd x(p, kNumTerms);
  Eigen::VectorXd y(p), edf(p);
  std::vector<std::int64_t> n_avg(rows.size());
  double y_min_pos = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < p; ++i) {
    const std::size_t r = rows[static_cast<std::size_t>(i)];
    for (int j = 0; j < kNumTerms; ++j)
      x(i, j) = xb[static_cast<std::size_t>(j)].psd[r];
    y(i) = yb.psd[r];
    edf(i) = yb.edf[r];
    n_avg[static_cast<std::size_t>(i)] = yb.n_avg[r];
    if (y(i) > 0) y_min_pos = std::min(y_min_pos, y(i));
  }
  if (!std::isfinite(y_min_pos)) return res;  // NoData: an all-zero PSD
  // Every column is an expected power, >= 0; the lag sums of K and B can round to tiny
  // negative values where their spectra are 1e-16 of the sum's terms, clipped here.
  x = x.cwiseMax(0.0);

  Eigen::VectorXd model = y.cwiseMax(y_min_pos);
  Eigen::VectorXd sw(p);
  Eigen::MatrixXd xs(p, kNumTerms);
  Eigen::Matrix<double, kNumTerms, 1> col_scale;
  Eigen::VectorXd bs(p);
  const auto build = [&]() {
    for (Eigen::Index i = 0; i < p; ++i)
      sw(i) = std::sqrt(0.5 * edf(i)) / model(i);
    xs = sw.asDiagonal() * x;
    for (int j = 0; j < kNumTerms; ++j) {
      const double nrm = xs.col(j).norm();
      col_scale(j) = nrm > 0 ? 1.0 / nrm : 1.0;
      xs.col(j) *= col_scale(j);
    }
    bs = sw.cwiseProduct(y);
  };
  build();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(p, kNumTerms);
  qr.setThreshold(opt.rank_threshold);
  qr.compute(xs);
  res.rank = static_cast<int>(qr.rank());
  if (res.rank < kNumTerms) {
    res.status = FitStatus::RankDeficient;
    return res;
  }
  Eigen::MatrixXd masked;
  Eigen::Matrix<double, kNumTerms, 1> theta = Eigen::Matrix<double, kNumTerms, 1>::Zero();
  bool converged = false;
  for (int it = 1; it <= opt.max_iterations; ++it) {
    res.iterations = it;
    theta = col_scale.cwiseProduct(detail::nnls(xs, bs, masked, qr));
    const Eigen::VectorXd next = x * theta;
    double change = 0;
    for (Eigen::Index i = 0; i < p; ++i)
      change = std::max(change, std::abs(next(i) / model(i) - 1.0));
    model = next.cwiseMax(1e-300);
    if (change <= opt.tolerance) {
      converged = true;
      break;
    }
    build();
  }
  build();

  // Covariance of the binned values under the fitted model: var = 2 model^2 / edf on the
  // diagonal; neighbouring rows share the correlation of their adjacent Welch bins (see the
  // header), cov(y_b, y_b+1) = sum over the boundary pairs (d = 1 once, d = 2 up to twice) of
  // r_d sqrt(var P_k var P_k') / (n_b n_b+1), var P_k = 2 model^2 / nu_k with nu_k the Welch
  // bins' edf (taken at the boundary as the rows' values).
  Eigen::MatrixXd sigma = Eigen::MatrixXd::Zero(p, p);
  for (Eigen::Index i = 0; i < p; ++i)
    sigma(i, i) = 2.0 * model(i) * model(i) / edf(i);
  for (Eigen::Index i = 0; i + 1 < p; ++i) {
    const std::size_t r0 = rows[static_cast<std::size_t>(i)];
    const std::size_t r1 = rows[static_cast<std::size_t>(i + 1)];
    if (r1 != r0 + 1) continue;
    const auto na = static_cast<double>(n_avg[static_cast<std::size_t>(i)]);
    const auto nb2 = static_cast<double>(n_avg[static_cast<std::size_t>(i + 1)]);
    // nu: the edf of one Welch bin, the same for every bin between DC and Nyquist.
    const double nu = psd.edf[2];
    const double rr = kR1 + (na > 1 ? kR2 : 0.0) + (nb2 > 1 ? kR2 : 0.0);
    sigma(i, i + 1) = sigma(i + 1, i) = rr * 2.0 * model(i) * model(i + 1) / (nu * na * nb2);
  }

  // Sandwich covariance of the weighted estimator on a set of free columns.
  const auto sandwich = [&](const std::array<bool, kNumTerms>& use,
                            Eigen::Matrix<double, kNumTerms, kNumTerms>& cov,
                            Eigen::Matrix<double, kNumTerms, Eigen::Dynamic>& amat) {
    masked = xs;
    for (int j = 0; j < kNumTerms; ++j)
      if (!use[static_cast<std::size_t>(j)]) masked.col(j).setZero();
    qr.compute(masked);
    amat.setZero(kNumTerms, p);
    Eigen::VectorXd e = Eigen::VectorXd::Zero(p);
    for (Eigen::Index i = 0; i < p; ++i) {
      e(i) = sw(i);
      const Eigen::Matrix<double, kNumTerms, 1> col = qr.solve(e);
      e(i) = 0;
      for (int j = 0; j < kNumTerms; ++j)
        amat(j, i) = use[static_cast<std::size_t>(j)] ? col(j) * col_scale(j) : 0.0;
    }
    cov = amat * sigma * amat.transpose();
  };
  std::array<bool, kNumTerms> free{};
  int n_free = 0;
  for (int j = 0; j < kNumTerms; ++j) {
    free[static_cast<std::size_t>(j)] = theta(j) > 0;
    n_free += theta(j) > 0 ? 1 : 0;
  }
  Eigen::Matrix<double, kNumTerms, Eigen::Dynamic> amat;
  sandwich(free, res.theta_cov, amat);
  const double z_up = detail::normal_quantile(opt.upper_confidence);
  for (int j = 0; j < kNumTerms; ++j) {
    TermFit& t = res.terms[static_cast<std::size_t>(j)];
    t.theta = theta(j);
    t.at_bound = !free[static_cast<std::size_t>(j)];
    if (!t.at_bound) {
      t.theta_free = theta(j);
      t.theta_sigma = std::sqrt(std::max(res.theta_cov(j, j), 0.0));
    } else {
      std::array<bool, kNumTerms> use = free;
      use[static_cast<std::size_t>(j)] = true;
      Eigen::Matrix<double, kNumTerms, kNumTerms> cov;
      Eigen::Matrix<double, kNumTerms, Eigen::Dynamic> a_j;
      sandwich(use, cov, a_j);
      t.theta_free = a_j.row(j).dot(y);
      t.theta_sigma = std::sqrt(std::max(cov(j, j), 0.0));
    }
    detail::finish_term(t, opt.detection_sigmas, z_up);
  }

  const Eigen::VectorXd r = y - x * theta;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(sigma);
  res.chi2 = r.dot(ldlt.solve(r));
  res.dof = static_cast<int>(p) - n_free;
  res.chi2_dof = res.dof > 0 ? res.chi2 / res.dof : 0.0;

  const auto pu = static_cast<std::size_t>(p);
  res.f_hz.resize(pu);
  res.psd.resize(pu);
  res.edf.resize(pu);
  res.psd_model.resize(pu);
  const Eigen::VectorXd fitted = x * theta;
  for (std::size_t i = 0; i < pu; ++i) {
    res.f_hz[i] = yb.f_hz[rows[i]];
    res.psd[i] = y(static_cast<Eigen::Index>(i));
    res.edf[i] = edf(static_cast<Eigen::Index>(i));
    res.psd_model[i] = fitted(static_cast<Eigen::Index>(i));
  }
  res.status = converged ? FitStatus::Ok : FitStatus::NoConvergence;
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
