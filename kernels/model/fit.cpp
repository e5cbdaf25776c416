#include "kernels/model/fit.hpp"

#include "kernels/uncertainty/confidence.hpp"
#include "kernels/model/least_squares.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

// Determinism: every product below is a matrix-vector product, a triangular solve with a
// vector right-hand side or a small (<= 5 column) factorization, none of which Eigen hands to
// OpenMP; the P x P factorization is LDLT (unblocked rank-1 updates). So the result is the
// same for any OMP_NUM_THREADS (checked in test_fit.cpp).

namespace allanlot::kernels {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kFlickerFloor = 2.0 * std::numbers::ln2 / kPi;  // eq. (3): B^2 2 ln2 / pi
constexpr int kR = static_cast<int>(Term::R);
constexpr int kK = static_cast<int>(Term::K);
constexpr int kB = static_cast<int>(Term::B);
constexpr int kN = static_cast<int>(Term::N);
constexpr int kQ = static_cast<int>(Term::Q);

// A double in a precondition message: std::to_string prints "%f", which shows 1e-300 as
// 0.000000 and 1e300 as 301 digits; the message must show the value that was wrong.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument(what);
}

// ---------------------------------------------------------------------------------------------
// Lag sums of the covariance model (OavarCovariance).

// 4-point Gauss-Legendre nodes and weights on [-1, 1] (Abramowitz & Stegun, Table 25.4):
// exact for the degree <= 7 polynomial pieces of N and K; on the geometrically graded panels
// below, each panel's nearest flicker singularity is at least its own length away, where the
// 4-point rule's error is below 1e-6 of the panel.
constexpr std::array<double, 2> kGlX = {0.3399810435848563, 0.8611363115940526};
constexpr std::array<double, 2> kGlW = {0.6521451548625461, 0.3478548451521774};

// Lags within this distance of a break point are summed exactly.
constexpr std::int64_t kExactEdge = 2;
// Pieces up to this many lags are summed exactly.
constexpr std::int64_t kExactPiece = 16;
// Flicker tails: geometric panels out to this many times the filters' reach m_i + m_j, then
// the leading asymptote (its relative error there is O(1/32^2) on a tail that carries less
// than 1/32 of the total).
constexpr double kTailPanelsReach = 32.0;

// Sums of n(l) c_p(l) c_q(l) and n(l) c_p(l) over lags, p, q in {N, B, K}.
struct LagSums {
  // NN, NB, NK, BB, BK, KK, then the linear N, B, K.
  std::array<double, 9> s{};
};

class PairSummer {
public:
  PairSummer(std::int64_t mi, std::int64_t mj, std::int64_t ni, std::int64_t nj, double tau0)
      : mi_(mi), mj_(mj), ni_(ni), nj_(nj), tau0_(tau0) {
    const std::array<std::int64_t, 3> a = {0, mi, 2 * mi};
    const std::array<std::int64_t, 3> b = {0, mj, 2 * mj};
    const std::array<double, 3> w = {1.0, -2.0, 1.0};
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) {
        off_[static_cast<std::size_t>(3 * p + q)] =
            b[static_cast<std::size_t>(q)] - a[static_cast<std::size_t>(p)];
        ww_[static_cast<std::size_t>(3 * p + q)] =
            w[static_cast<std::size_t>(p)] * w[static_cast<std::size_t>(q)];
      }
    lag_lo_ = -(ni - 1);
    lag_hi_ = nj - 1;
  }

  std::int64_t lag_lo() const { return lag_lo_; }
  std::int64_t lag_hi() const { return lag_hi_; }
  const std::array<std::int64_t, 9>& offsets() const { return off_; }
  const std::array<double, 9>& weights() const { return ww_; }

  // Number of pairs (k, k + l) with 0 <= k < M_i, 0 <= k + l < M_j (continuous in l).
  double pairs(double l) const {
    const double v =
        std::min(static_cast<double>(ni_), static_cast<double>(nj_) - l) - std::max(0.0, -l);
    return std::max(v, 0.0);
  }

  // c_N, c_B, c_K at lag l (per unit theta), from the generalized autocovariances.
  void cross(double l, double& cn, double& cb, double& ck, bool flicker_only) const {
    cn = cb = ck = 0.0;
    for (std::size_t k = 0; k < 9; ++k) {
      const double t = tau0_ * (l + static_cast<double>(off_[k]));
      const double at = std::abs(t);
      if (at == 0.0) continue;
      const double w = ww_[k];
      cb += w * t * t * std::log(at);
      if (!flicker_only) {
        cn += w * at;
        ck += w * at * at * at;
      }
    }
    cn *= -0.5;
    cb *= 1.0 / (2.0 * kPi);
    ck *= 1.0 / 12.0;
  }

  void add(double l, double weight, LagSums& acc, bool flicker_only) const {
    const double np = pairs(l) * weight;
    if (np == 0.0) return;
    double cn, cb, ck;
    cross(l, cn, cb, ck, flicker_only);
    acc.s[0] += np * cn * cn;
    acc.s[1] += np * cn * cb;
    acc.s[2] += np * cn * ck;
    acc.s[3] += np * cb * cb;
    acc.s[4] += np * cb * ck;
    acc.s[5] += np * ck * ck;
    acc.s[6] += np * cn;
    acc.s[7] += np * cb;
    acc.s[8] += np * ck;
  }

  void exact(std::int64_t first, std::int64_t last, LagSums& acc, bool flicker_only) const {
    for (std::int64_t l = first; l <= last; ++l)
      add(static_cast<double>(l), 1.0, acc, flicker_only);
  }

  // Gauss-Legendre integral over [x0, x1].
  void panel(double x0, double x1, LagSums& acc, bool flicker_only) const {
    const double mid = 0.5 * (x0 + x1);
    const double half = 0.5 * (x1 - x0);
    for (std::size_t k = 0; k < kGlX.size(); ++k) {
      add(mid - half * kGlX[k], half * kGlW[k], acc, flicker_only);
      add(mid + half * kGlX[k], half * kGlW[k], acc, flicker_only);
    }
  }

  // Integral over [x0, x1] of a piece inside the filters' overlap. Near either end a filter
  // knot of the other filter is close, and flicker's c_B varies on the scale of the distance
  // to it (logarithmically when m_i << m_j), so the panels grow geometrically from both ends
  // (first length m_i / 4, at least 1, doubling) and meet in the middle.
  void graded(double x0, double x1, LagSums& acc) const {
    double h = std::max(1.0, 0.25 * static_cast<double>(mi_));
    double a = x0, b = x1;
    while (b - a > 2.0 * h) {
      panel(a, a + h, acc, false);
      panel(b - h, b, acc, false);
      a += h;
      b -= h;
      h *= 2.0;
    }
    panel(a, b, acc, false);
  }

  // Integral over [x0, x1] of a flicker tail piece (no break point inside, entirely on one
  // side of the filters' overlap). c_B varies on the scale of the distance to the nearest
  // filter knot, i.e. to the piece's near end, so the panels grow geometrically from that end
  // (first length m_i / 4, at least 1, doubling); once the distance u from the centre lag
  // lc = m_i - m_j (where the filters are centred on each other) exceeds 32 times the
  // filters' reach m_i + m_j, the leading asymptote takes over.
  void tail(double x0, double x1, LagSums& acc) const {
    const double lc = static_cast<double>(mi_ - mj_);
    const bool right = x0 >= lc;
    const double near = right ? x0 : x1;
    const double dir = right ? 1.0 : -1.0;
    const double length = x1 - x0;
    const double u_near = std::abs(near - lc);
    const double u_asym = kTailPanelsReach * static_cast<double>(mi_ + mj_);
    const double d_asym = std::max(0.0, u_asym - u_near);  // distance from near end
    const double d_end = std::min(length, d_asym);
    double d = 0.0;
    double h = std::max(1.0, 0.25 * static_cast<double>(mi_));
    while (d < d_end) {
      const double d_next = std::min(d + h, d_end);
      const double xa = near + dir * d, xb = near + dir * d_next;
      panel(std::min(xa, xb), std::max(xa, xb), acc, true);
      d = d_next;
      h *= 2.0;
    }
    if (d >= length) return;
    // Beyond: c_B = -C / u^2 with C = tau0^2 m_i^2 m_j^2 / pi (the fourth difference of
    // t^2 ln|t| / (2 pi) is -1 / (pi t^2), and the two filters' second moments are 2 m^2).
    // n(l) is linear on the piece: n = a0 + a1 u.
    const double c = tau0_ * tau0_ * static_cast<double>(mi_) * static_cast<double>(mi_) *
                     static_cast<double>(mj_) * static_cast<double>(mj_) / kPi;
    const double u = u_near + d, u_far = u_near + length;
    const double na = pairs(near + dir * d), nb = pairs(near + dir * length);
    const double a1 = (nb - na) / (u_far - u);
    const double a0 = na - a1 * u;
    // int_u^u_far (a0 + a1 v) v^-p dv for p = 2 and 4.
    const double i2 = a0 * (1.0 / u - 1.0 / u_far) + a1 * std::log(u_far / u);
    const double i4 = a0 * (std::pow(u, -3) - std::pow(u_far, -3)) / 3.0 +
                      a1 * (std::pow(u, -2) - std::pow(u_far, -2)) / 2.0;
    acc.s[3] += c * c * i4;
    acc.s[7] += -c * i2;
  }

  // Sum over every lag in the domain of the N, B, K products.
  LagSums sum() const {
    std::vector<std::int64_t> bp;
    bp.reserve(13);
    for (const auto o : off_)
      bp.push_back(-o);  // c's break points: l + b - a = 0
    bp.push_back(0);
    bp.push_back(nj_ - ni_);  // n's kinks
    bp.push_back(lag_lo_);
    bp.push_back(lag_hi_);
    std::vector<std::int64_t> pts;
    pts.reserve(bp.size());
    for (const auto p : bp)
      if (p >= lag_lo_ && p <= lag_hi_) pts.push_back(p);
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());

    LagSums acc;
    const std::int64_t support_lo = -2 * mj_, support_hi = 2 * mi_;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      const std::int64_t p = pts[k], q = pts[k + 1];
      const bool compact = p >= support_lo && q <= support_hi;
      if (q - p <= kExactPiece) {
        exact(p, q - 1, acc, !compact);
        continue;
      }
      exact(p, p + kExactEdge - 1, acc, !compact);
      exact(q - kExactEdge, q - 1, acc, !compact);
      // Midpoint rule: the integers p + E .. q - E - 1 stand for [p + E - 1/2, q - E - 1/2],
      // with Euler-Maclaurin's first correction -(f'(x1) - f'(x0)) / 24, f' by central
      // differences of the integer values next to each end. The remainder is
      // (7/5760) (f'''(x1) - f'''(x0)): zero for the cubic pieces of N, O(1/L^4) relative for
      // the others (L the piece length).
      const double x0 = static_cast<double>(p + kExactEdge) - 0.5;
      const double x1 = static_cast<double>(q - kExactEdge) - 0.5;
      constexpr double kEm = 1.0 / 24.0;
      add(static_cast<double>(q - kExactEdge), -kEm, acc, !compact);
      add(static_cast<double>(q - kExactEdge - 1), kEm, acc, !compact);
      add(static_cast<double>(p + kExactEdge), kEm, acc, !compact);
      add(static_cast<double>(p + kExactEdge - 1), -kEm, acc, !compact);
      if (compact)
        graded(x0, x1, acc);
      else
        tail(x0, x1, acc);
    }
    exact(pts.back(), pts.back(), acc, pts.back() < support_lo || pts.back() > support_hi);
    return acc;
  }

private:
  std::int64_t mi_, mj_, ni_, nj_;
  double tau0_;
  std::array<std::int64_t, 9> off_{};
  std::array<double, 9> ww_{};
  std::int64_t lag_lo_ = 0, lag_hi_ = 0;
};

// The Q (white phase) contributions: c_Q(l) = sum of w_a w_b over the offsets with
// l + b - a = 0, nonzero at those lags only. Returns QQ, QN, QB, QK, Q-linear.
std::array<double, 5> quantization_sums(const PairSummer& ps) {
  std::array<double, 5> out{};
  std::array<std::int64_t, 9> lags{};
  for (std::size_t k = 0; k < 9; ++k)
    lags[k] = -ps.offsets()[k];
  std::array<std::int64_t, 9> sorted = lags;
  std::sort(sorted.begin(), sorted.end());
  const auto end = std::unique(sorted.begin(), sorted.end());
  for (auto it = sorted.begin(); it != end; ++it) {
    const std::int64_t l = *it;
    if (l < ps.lag_lo() || l > ps.lag_hi()) continue;
    double cq = 0.0;
    for (std::size_t k = 0; k < 9; ++k)
      if (lags[k] == l) cq += ps.weights()[k];
    const double np = ps.pairs(static_cast<double>(l));
    double cn, cb, ck;
    ps.cross(static_cast<double>(l), cn, cb, ck, false);
    out[0] += np * cq * cq;
    out[1] += np * cq * cn;
    out[2] += np * cq * cb;
    out[3] += np * cq * ck;
    out[4] += np * cq;
  }
  return out;
}

void check_shape(std::span<const std::int64_t> m, std::span<const std::int64_t> n, double tau0_s,
                 const char* who) {
  const std::string w = who;
  if (m.size() != n.size())
    fail(w + ": m and n differ in length (" + std::to_string(m.size()) + " vs " +
         std::to_string(n.size()) + ")");
  if (!(tau0_s > 0.0) || !std::isfinite(tau0_s))
    fail(w + ": tau0_s must be finite and > 0, got " + std::to_string(tau0_s));
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (m[i] < 1) fail(w + ": m must be >= 1, got " + std::to_string(m[i]));
    if (i > 0 && m[i] <= m[i - 1])
      fail(w + ": m must be strictly increasing, got " + std::to_string(m[i - 1]) + " then " +
           std::to_string(m[i]));
    if (n[i] < 1) fail(w + ": n must be >= 1, got " + std::to_string(n[i]));
  }
}

double half_interval(double dev, double edf, double confidence) {
  if (!(dev > 0.0)) return 0.0;
  const Interval ci = chi2_interval(dev, edf, confidence);
  return 0.5 * (ci.hi - ci.lo);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::array<double, kNumTerms> eq3_regressors(double tau_s) {
  std::array<double, kNumTerms> g{};
  g[kR] = 0.5 * tau_s * tau_s;
  g[kK] = tau_s / 3.0;
  g[kB] = kFlickerFloor;
  g[kN] = 1.0 / tau_s;
  g[kQ] = 3.0 / (tau_s * tau_s);
  return g;
}

double eq3_avar(const std::array<double, kNumTerms>& theta, double tau_s) {
  const auto g = eq3_regressors(tau_s);
  double s = 0.0;
  for (std::size_t j = 0; j < g.size(); ++j)
    s += theta[j] * g[j];
  return s;
}

std::string_view fit_status_name(FitStatus s) {
  switch (s) {
  case FitStatus::Ok:
    return "ok";
  case FitStatus::NoData:
    return "no data";
  case FitStatus::RankDeficient:
    return "rank deficient";
  case FitStatus::NoConvergence:
    return "no convergence";
  }
  return "unknown";
}

void OavarCovariance::prepare(std::span<const std::int64_t> m, std::span<const std::int64_t> n,
                              double tau0_s) {
  check_shape(m, n, tau0_s, "OavarCovariance::prepare");
  const auto p = static_cast<Eigen::Index>(m.size());
  m_.assign(m.begin(), m.end());
  n_.assign(n.begin(), n.end());
  tau0_s_ = tau0_s;
  for (auto& b : basis_)
    b.setZero(p, p);
  for (Eigen::Index i = 0; i < p; ++i) {
    for (Eigen::Index j = i; j < p; ++j) {
      const auto iu = static_cast<std::size_t>(i), ju = static_cast<std::size_t>(j);
      const PairSummer ps(m[iu], m[ju], n[iu], n[ju], tau0_s);
      const LagSums s = ps.sum();
      const auto q = quantization_sums(ps);
      const double ti = static_cast<double>(m[iu]) * tau0_s;
      const double tj = static_cast<double>(m[ju]) * tau0_s;
      const double mm = static_cast<double>(n[iu]) * static_cast<double>(n[ju]);
      // 2 / (4 tau_i^2 tau_j^2 M_i M_j): Isserlis' factor 2 over the two estimators' norms.
      const double quad = 1.0 / (2.0 * ti * ti * tj * tj * mm);
      const double lin = 1.0 / mm;
      const std::array<double, 14> v = {
          q[0] * quad,   q[1] * quad,   q[2] * quad,   q[3] * quad,    // QQ QN QB QK
          s.s[0] * quad, s.s[1] * quad, s.s[2] * quad,                 // NN NB NK
          s.s[3] * quad, s.s[4] * quad, s.s[5] * quad,                 // BB BK KK
          q[4] * lin,    s.s[6] * lin,  s.s[7] * lin,  s.s[8] * lin};  // R x Q N B K
      for (std::size_t k = 0; k < v.size(); ++k) {
        basis_[k](i, j) = v[k];
        basis_[k](j, i) = v[k];
      }
    }
  }
}

bool OavarCovariance::matches(std::span<const std::int64_t> m, std::span<const std::int64_t> n,
                              double tau0_s) const {
  return tau0_s == tau0_s_ && std::equal(m.begin(), m.end(), m_.begin(), m_.end()) &&
         std::equal(n.begin(), n.end(), n_.begin(), n_.end());
}

void OavarCovariance::assemble(const std::array<double, kNumTerms>& theta,
                               Eigen::MatrixXd& out) const {
  const auto p = static_cast<Eigen::Index>(m_.size());
  out.setZero(p, p);
  // Random terms in the basis order Q, N, B, K.
  const std::array<double, 4> t = {theta[kQ], theta[kN], theta[kB], theta[kK]};
  std::size_t k = 0;
  for (std::size_t a = 0; a < 4; ++a)
    for (std::size_t b = a; b < 4; ++b, ++k) {
      const double c = (a == b ? 1.0 : 2.0) * t[a] * t[b];
      if (c != 0.0) out += c * basis_[k];
    }
  for (std::size_t a = 0; a < 4; ++a) {
    const double c = theta[kR] * t[a];
    if (c != 0.0) out += c * basis_[10 + a];
  }
}

// ---------------------------------------------------------------------------------------------

Eq3Fit::Eq3Fit(std::size_t max_taus, FitOptions options) : options_(options) {
  if (!(options_.upper_confidence > 0.5 && options_.upper_confidence < 1.0))
    fail("Eq3Fit: options.upper_confidence must be in (0.5, 1), got " +
         std::to_string(options_.upper_confidence));
  if (!(options_.readout_confidence > 0.0 && options_.readout_confidence < 1.0))
    fail("Eq3Fit: options.readout_confidence must be in (0, 1), got " +
         std::to_string(options_.readout_confidence));
  if (options_.max_iterations < 1)
    fail("Eq3Fit: options.max_iterations must be >= 1, got " +
         std::to_string(options_.max_iterations));
  const auto p = static_cast<Eigen::Index>(max_taus);
  m_.reserve(max_taus);
  x_.resize(p, kNumTerms);
  y_.resize(p);
  edf_.resize(p);
  sw_.resize(p);
  sigma_.resize(p, p);
  xs_.resize(p, kNumTerms);
  masked_.resize(p, kNumTerms);
  bs_.resize(p);
  amat_.resize(kNumTerms, p);
  qr_ = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(p, kNumTerms);
}

FitResult Eq3Fit::fit(const StatResult& oadev, double tau0_s, std::int64_t n_samples) {
  if (oadev.edf.size() != oadev.size())
    fail("Eq3Fit::fit: the oadev result has no edf (" + std::to_string(oadev.edf.size()) + " for " +
         std::to_string(oadev.size()) + " rows); run add_confidence first");
  FitInput in;
  in.tau_s = oadev.tau_s;
  in.values = oadev.dev;
  in.is_deviation = true;
  in.n = oadev.n;
  in.edf = oadev.edf;
  in.tau0_s = tau0_s;
  in.n_samples = n_samples;
  return fit(in);
}

FitResult Eq3Fit::fit(const FitInput& in) {
  const std::size_t pu = in.tau_s.size();
  if (in.values.size() != pu || in.n.size() != pu || in.edf.size() != pu)
    fail("Eq3Fit::fit: tau_s, values, n and edf differ in length (" + std::to_string(pu) + ", " +
         std::to_string(in.values.size()) + ", " + std::to_string(in.n.size()) + ", " +
         std::to_string(in.edf.size()) + ")");
  if (!(in.tau0_s > 0.0) || !std::isfinite(in.tau0_s))
    fail("Eq3Fit::fit: tau0_s must be finite and > 0, got " + num(in.tau0_s));
  if (in.n_samples < 1)
    fail("Eq3Fit::fit: n_samples must be >= 1, got " + std::to_string(in.n_samples));
  m_.resize(pu);
  for (std::size_t i = 0; i < pu; ++i) {
    const double tau = in.tau_s[i];
    if (!(tau > 0.0) || !std::isfinite(tau))
      fail("Eq3Fit::fit: tau_s must be finite and > 0, got " + num(tau));
    if (i > 0 && !(tau > in.tau_s[i - 1]))
      fail("Eq3Fit::fit: tau_s must be strictly increasing, got " + num(in.tau_s[i - 1]) +
           " then " + num(tau));
    const double mf = std::round(tau / in.tau0_s);
    if (mf < 1.0 || std::abs(tau - mf * in.tau0_s) > 1e-9 * tau)
      fail("Eq3Fit::fit: tau_s " + num(tau) + " is not a multiple of tau0_s " + num(in.tau0_s));
    m_[i] = static_cast<std::int64_t>(mf);
    const double v = in.values[i];
    if (!(v >= 0.0) || !std::isfinite(v))
      fail("Eq3Fit::fit: values must be finite and >= 0, got " + num(v) + " at tau " + num(tau));
    if (!(in.edf[i] > 0.0) || !std::isfinite(in.edf[i]))
      fail("Eq3Fit::fit: edf must be finite and > 0, got " + num(in.edf[i]) + " at tau " +
           num(tau));
    const std::int64_t n_max = in.n_samples + 1 - 2 * m_[i];
    if (in.n[i] < 1 || in.n[i] > n_max)
      fail("Eq3Fit::fit: n must be in [1, " + std::to_string(n_max) + "] at m " +
           std::to_string(m_[i]) + ", got " + std::to_string(in.n[i]));
  }

  FitResult res;
  const auto p = static_cast<Eigen::Index>(pu);
  y_.resize(p);
  edf_.resize(p);
  x_.resize(p, kNumTerms);
  sw_.resize(p);
  double y_min_pos = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < p; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    const double v = in.values[iu];
    y_(i) = in.is_deviation ? v * v : v;
    edf_(i) = in.edf[iu];
    if (y_(i) > 0.0) y_min_pos = std::min(y_min_pos, y_(i));
    const auto g = eq3_regressors(in.tau_s[iu]);
    for (int j = 0; j < kNumTerms; ++j)
      x_(i, j) = g[static_cast<std::size_t>(j)];
  }
  if (p == 0 || !std::isfinite(y_min_pos)) {
    res.status = FitStatus::NoData;
    return res;
  }

  // Scaled weighted design: rows by sqrt(w), columns to unit norm (the raw columns span up to
  // 24 orders of magnitude over 6 decades of tau).
  Eigen::MatrixXd& xs = xs_;
  Eigen::MatrixXd& masked = masked_;
  Eigen::VectorXd& bs = bs_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr = qr_;
  xs.resize(p, kNumTerms);
  masked.resize(p, kNumTerms);
  bs.resize(p);
  Eigen::Matrix<double, kNumTerms, 1> col_scale;
  qr.setThreshold(options_.rank_threshold);
  Eigen::VectorXd model(p);
  for (Eigen::Index i = 0; i < p; ++i)
    model(i) = std::max(y_(i), y_min_pos);
  const auto build = [&]() {
    for (Eigen::Index i = 0; i < p; ++i)
      sw_(i) = std::sqrt(0.5 * edf_(i)) / model(i);
    xs = sw_.asDiagonal() * x_;
    for (int j = 0; j < kNumTerms; ++j) {
      const double nrm = xs.col(j).norm();
      col_scale(j) = nrm > 0.0 ? 1.0 / nrm : 1.0;
      xs.col(j) *= col_scale(j);
    }
    bs = sw_.cwiseProduct(y_);
  };

  build();
  qr.compute(xs);
  res.rank = static_cast<int>(qr.rank());
  if (res.rank < kNumTerms) {
    res.status = FitStatus::RankDeficient;
    return res;
  }

  // Iteratively reweighted NNLS: weights from the model of the previous iteration.
  Eigen::Matrix<double, kNumTerms, 1> theta = Eigen::Matrix<double, kNumTerms, 1>::Zero();
  bool converged = false;
  for (int it = 1; it <= options_.max_iterations; ++it) {
    res.iterations = it;
    const Eigen::Matrix<double, kNumTerms, 1> z = detail::nnls(xs, bs, masked, qr);
    theta = col_scale.cwiseProduct(z);
    const Eigen::VectorXd next = x_ * theta;
    double change = 0.0;
    for (Eigen::Index i = 0; i < p; ++i)
      change = std::max(change, std::abs(next(i) / model(i) - 1.0));
    model = next;
    if (change <= options_.tolerance) {
      converged = true;
      break;
    }
    build();
  }
  // The weights of the last solve: rebuild so that they and the final model agree.
  build();

  std::array<double, kNumTerms> th{};
  for (int j = 0; j < kNumTerms; ++j)
    th[static_cast<std::size_t>(j)] = theta(j);
  if (!cov_model_.matches(m_, in.n, in.tau0_s)) cov_model_.prepare(m_, in.n, in.tau0_s);
  cov_model_.assemble(th, sigma_);

  // Sandwich covariance of the weighted estimator on a set of free columns:
  // A = D (Xs^T Xs)^-1 Xs^T diag(sw) restricted to the set, cov = A Sigma A^T.
  Eigen::Matrix<double, kNumTerms, Eigen::Dynamic>& amat = amat_;
  amat.resize(kNumTerms, p);
  const auto sandwich = [&](const std::array<bool, kNumTerms>& use,
                            Eigen::Matrix<double, kNumTerms, kNumTerms>& cov) {
    masked = xs;
    for (int j = 0; j < kNumTerms; ++j)
      if (!use[static_cast<std::size_t>(j)]) masked.col(j).setZero();
    qr.compute(masked);
    // Row i of A^T solves the least squares with right-hand side sw_i e_i; column by column
    // (a vector right-hand side each) keeps every operation a serial matrix-vector one.
    Eigen::VectorXd e = Eigen::VectorXd::Zero(p);
    for (Eigen::Index i = 0; i < p; ++i) {
      e(i) = sw_(i);
      Eigen::Matrix<double, kNumTerms, 1> col = qr.solve(e);
      e(i) = 0.0;
      for (int j = 0; j < kNumTerms; ++j)
        amat(j, i) = use[static_cast<std::size_t>(j)] ? col(j) * col_scale(j) : 0.0;
    }
    for (int a = 0; a < kNumTerms; ++a) {
      const Eigen::VectorXd t = sigma_ * amat.row(a).transpose();
      for (int b = 0; b < kNumTerms; ++b)
        cov(a, b) = amat.row(b).dot(t);
    }
  };

  std::array<bool, kNumTerms> free{};
  int n_free = 0;
  for (int j = 0; j < kNumTerms; ++j) {
    free[static_cast<std::size_t>(j)] = theta(j) > 0.0;
    n_free += theta(j) > 0.0 ? 1 : 0;
  }
  sandwich(free, res.theta_cov);
  const Eigen::Matrix<double, kNumTerms, Eigen::Dynamic> a_free = amat;

  const double z_up = detail::normal_quantile(options_.upper_confidence);
  for (int j = 0; j < kNumTerms; ++j) {
    TermFit& t = res.terms[static_cast<std::size_t>(j)];
    t.theta = theta(j);
    t.at_bound = !free[static_cast<std::size_t>(j)];
    if (!t.at_bound) {
      t.theta_free = theta(j);
      t.theta_sigma = std::sqrt(std::max(res.theta_cov(j, j), 0.0));
    } else {
      // The fit with this term released (it may go negative); the same weights.
      std::array<bool, kNumTerms> use = free;
      use[static_cast<std::size_t>(j)] = true;
      Eigen::Matrix<double, kNumTerms, kNumTerms> cov;
      sandwich(use, cov);
      t.theta_free = amat.row(j).dot(y_);
      t.theta_sigma = std::sqrt(std::max(cov(j, j), 0.0));
    }
    detail::finish_term(t, options_.detection_sigmas, z_up);
  }

  // Residuals and goodness of fit with the correlated covariance.
  const Eigen::VectorXd r = y_ - model;
  res.residual_norm = sw_.cwiseProduct(r).norm();
  res.dof = static_cast<int>(p) - n_free;
  // tr(H) = tr(A X) and the expectation of r^T Sigma^-1 r (see the header):
  // P - 2 tr(A X) + tr((X^T Sigma^-1 X) cov).
  double tr_h = 0.0;
  for (int j = 0; j < kNumTerms; ++j)
    tr_h += a_free.row(j).dot(x_.col(j));
  Eigen::LDLT<Eigen::MatrixXd> ldlt(sigma_);
  const bool pd = ldlt.info() == Eigen::Success && ldlt.isPositive() &&
                  ldlt.vectorD().minCoeff() > 1e-14 * ldlt.vectorD().maxCoeff();
  Eigen::MatrixXd sinv_x(p, kNumTerms);
  Eigen::VectorXd sinv_r(p);
  if (pd) {
    sinv_r = ldlt.solve(r);
    for (int j = 0; j < kNumTerms; ++j)
      sinv_x.col(j) = ldlt.solve(x_.col(j).eval());
  } else {
    // Numerically semi-definite model (e.g. a single term whose estimates at the longest taus
    // are almost perfectly correlated): pseudo-inverse with eigenvalues below 1e-14 of the
    // largest dropped.
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sigma_);
    const Eigen::VectorXd& ev = es.eigenvalues();
    const double floor = 1e-14 * ev.maxCoeff();
    Eigen::VectorXd inv(p);
    for (Eigen::Index i = 0; i < p; ++i)
      inv(i) = ev(i) > floor ? 1.0 / ev(i) : 0.0;
    const Eigen::MatrixXd& v = es.eigenvectors();
    const auto apply = [&](const Eigen::VectorXd& b) -> Eigen::VectorXd {
      const Eigen::VectorXd c = v.transpose() * b;
      return v * inv.cwiseProduct(c);
    };
    sinv_r = apply(r);
    for (int j = 0; j < kNumTerms; ++j)
      sinv_x.col(j) = apply(x_.col(j));
  }
  res.chi2 = r.dot(sinv_r);
  double tr_hsh = 0.0;
  for (int a = 0; a < kNumTerms; ++a)
    for (int b = 0; b < kNumTerms; ++b)
      tr_hsh += x_.col(a).dot(sinv_x.col(b)) * res.theta_cov(b, a);
  res.chi2_expected = static_cast<double>(p) - 2.0 * tr_h + tr_hsh;
  res.chi2_dof = res.chi2_expected > 0.0 ? res.chi2 / res.chi2_expected : 0.0;

  res.avar_model.resize(pu);
  res.adev_model.resize(pu);
  for (std::size_t i = 0; i < pu; ++i) {
    res.avar_model[i] = model(static_cast<Eigen::Index>(i));
    res.adev_model[i] = std::sqrt(res.avar_model[i]);
  }

  // Conventional read-outs (see FitResult).
  const double conf = options_.readout_confidence;
  const auto dev_at = [&](std::size_t i) { return std::sqrt(y_(static_cast<Eigen::Index>(i))); };
  {
    Readout& ro = res.n_1s;
    ro.tau_s = 1.0;
    ro.model = std::sqrt(eq3_avar(th, 1.0));
    if (in.tau_s.front() <= 1.0 && in.tau_s.back() >= 1.0) {
      std::size_t k = 0;
      while (k + 1 < pu && in.tau_s[k + 1] <= 1.0)
        ++k;
      double avar1 = y_(static_cast<Eigen::Index>(k));
      double edf1 = edf_(static_cast<Eigen::Index>(k));
      if (in.tau_s[k] < 1.0) {
        const auto k1 = static_cast<Eigen::Index>(k + 1);
        const auto k0 = static_cast<Eigen::Index>(k);
        const double w = std::log(1.0 / in.tau_s[k]) / std::log(in.tau_s[k + 1] / in.tau_s[k]);
        avar1 = (y_(k0) > 0.0 && y_(k1) > 0.0)
                    ? std::exp((1.0 - w) * std::log(y_(k0)) + w * std::log(y_(k1)))
                    : (1.0 - w) * y_(k0) + w * y_(k1);
        edf1 = (1.0 - w) * edf_(k0) + w * edf_(k1);
      }
      ro.valid = res.terms[kN].detected;
      ro.value = std::sqrt(avar1);
      ro.sigma = half_interval(ro.value, edf1, conf);
    }
  }
  std::size_t i_min = 0, i_k = 0;
  double model_min = std::numeric_limits<double>::infinity();
  double model_k = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pu; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    if (y_(ii) < y_(static_cast<Eigen::Index>(i_min))) i_min = i;
    if (y_(ii) / in.tau_s[i] < y_(static_cast<Eigen::Index>(i_k)) / in.tau_s[i_k]) i_k = i;
    model_min = std::min(model_min, model(ii));
    model_k = std::min(model_k, model(ii) / in.tau_s[i]);
  }
  {
    Readout& ro = res.bias_instability;
    const double scale = 1.0 / std::sqrt(kFlickerFloor);
    ro.tau_s = in.tau_s[i_min];
    ro.value = dev_at(i_min) * scale;
    ro.sigma = half_interval(dev_at(i_min), edf_(static_cast<Eigen::Index>(i_min)), conf) * scale;
    ro.model = std::sqrt(model_min) * scale;
    ro.valid = res.terms[kB].detected;
  }
  {
    Readout& ro = res.k_3s;
    const double scale = std::sqrt(3.0 / in.tau_s[i_k]);
    ro.tau_s = in.tau_s[i_k];
    ro.value = dev_at(i_k) * scale;
    ro.sigma = half_interval(dev_at(i_k), edf_(static_cast<Eigen::Index>(i_k)), conf) * scale;
    ro.model = std::sqrt(3.0 * model_k);
    ro.valid = res.terms[kK].detected;
  }

  res.status = converged ? FitStatus::Ok : FitStatus::NoConvergence;
  return res;
}

}  // namespace allanlot::kernels
