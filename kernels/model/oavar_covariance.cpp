// The model covariance of overlapping Allan variance estimates (OavarCovariance, fit.hpp): the
// lag sums of the two second-difference filters' cross-covariance and their 14 basis matrices.
#include "kernels/model/fit.hpp"

#include "kernels/common/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kR = static_cast<int>(Term::R);
constexpr int kK = static_cast<int>(Term::K);
constexpr int kB = static_cast<int>(Term::B);
constexpr int kN = static_cast<int>(Term::N);
constexpr int kQ = static_cast<int>(Term::Q);

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

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument(what);
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

}  // namespace

void OavarCovariance::prepare(std::span<const std::int64_t> m, std::span<const std::int64_t> n,
                              double tau0_s, int threads) {
  check_shape(m, n, tau0_s, "OavarCovariance::prepare");
  const auto p = static_cast<Eigen::Index>(m.size());
  m_.assign(m.begin(), m.end());
  n_.assign(n.begin(), n.end());
  tau0_s_ = tau0_s;
  for (auto& b : basis_)
    b.setZero(p, p);
  [[maybe_unused]] const int nt = resolve_threads(threads);  // unused without OpenMP
  ExceptionCollector errors;
  // Row i holds p - i pairs: dynamic scheduling evens out the triangle.
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (Eigen::Index i = 0; i < p; ++i)
    errors.run([&] {
      for (Eigen::Index j = i; j < p; ++j)
        set_pair(i, j);
    });
  errors.rethrow();
}

void OavarCovariance::set_pair(Eigen::Index i, Eigen::Index j) {
  const auto iu = static_cast<std::size_t>(i), ju = static_cast<std::size_t>(j);
  const PairSummer ps(m_[iu], m_[ju], n_[iu], n_[ju], tau0_s_);
  const LagSums s = ps.sum();
  const auto q = quantization_sums(ps);
  const double ti = static_cast<double>(m_[iu]) * tau0_s_;
  const double tj = static_cast<double>(m_[ju]) * tau0_s_;
  const double mm = static_cast<double>(n_[iu]) * static_cast<double>(n_[ju]);
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

}  // namespace allanlot::kernels
