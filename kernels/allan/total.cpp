#include "kernels/allan/total.hpp"

#include "kernels/allan/detail/sweep.hpp"

#include <algorithm>
#include <stdexcept>

namespace allanlot::kernels {
namespace detail {
namespace {

bool total_valid(std::int64_t n, std::int64_t m) {
  return n >= 3 && m >= 1 && 2 * m <= n - 1;
}

// The doubly reflected sequence x*_k (header comment): x*_{-k} = 2 x_0 - x_k on the left,
// x*_{N-1+k} = 2 x_{N-1} - x_{N-1-k} on the right; only |k - [0, N-1]| <= m is needed.
//
// Sums over the centres i = 1 .. m-1 (reflected on the left) and i = N-m .. N-2 (reflected on
// the right); the centres m .. N-1-m in between are the OADEV terms k = i - m. With
// 2m <= N-1 (total_valid) a left centre reflects exactly its first point (i - m < 0,
// i + m <= N-1) and a right centre exactly its last (i - m >= 0, i + m > N-1), so the terms
// are written without a branch; each is x*_{i-m} - 2 x*_i + x*_{i+m} evaluated left to right.
struct LeftEnd {
  const double* x;
  std::int64_t m;
  double operator()(std::int64_t k) const {
    const std::int64_t i = k + 1;
    return (2.0 * x[0] - x[m - i]) - 2.0 * x[i] + x[i + m];
  }
  V2 pair(std::int64_t k) const { return V2{(*this)(k), (*this)(k + 1)}; }
};
struct RightEnd {
  const double* x;
  std::int64_t m, n;
  double operator()(std::int64_t k) const {
    const std::int64_t i = k + n - m;
    return x[i - m] - 2.0 * x[i] + (2.0 * x[n - 1] - x[2 * (n - 1) - (i + m)]);
  }
  V2 pair(std::int64_t k) const { return V2{(*this)(k), (*this)(k + 1)}; }
};

// m beyond Stable32's (N-1)/2 (AllanTools' range, MRange::Estimable): a centre may reflect
// both of its ends, so each term looks its points up through the reflection. x*_k is defined
// for -(N-1) <= k <= 2(N-1), which covers every centre i = 1 .. N-2 for m <= N-1.
bool wide_valid(std::int64_t n, std::int64_t m) {
  return n >= 3 && 2 * m > n - 1 && m <= n - 1;
}
double reflected(const double* x, std::int64_t n, std::int64_t k) {
  if (k < 0) return 2.0 * x[0] - x[-k];
  if (k > n - 1) return 2.0 * x[n - 1] - x[2 * (n - 1) - k];
  return x[k];
}
double wide_sum(const PhaseData& p, std::int64_t m) {
  const double* x = p.x.data();
  const std::int64_t n = p.n_points();
  double s = 0.0;
  for (std::int64_t i = 1; i <= n - 2; ++i) {
    const double d = reflected(x, n, i - m) - 2.0 * x[i] + reflected(x, n, i + m);
    s += d * d;
  }
  return s;
}

double left_sum(const PhaseData& p, std::int64_t m) {
  return blocked_sum_of_squares(LeftEnd{p.x.data(), m}, m - 1);
}
double right_sum(const PhaseData& p, std::int64_t m) {
  return blocked_sum_of_squares(RightEnd{p.x.data(), m, p.n_points()}, m - 1);
}

}  // namespace

SumCount total_core(const PhaseData& p, std::int64_t m) {
  SumCount out;
  if (!total_valid(p.n_points(), m)) return out;
  // Left run, inner run, right run, added in index order of the centres.
  out.sum = left_sum(p, m);
  out.sum += blocked_sum_of_squares(SecondDifference{p.x.data(), m}, p.n_points() - 2 * m);
  out.sum += right_sum(p, m);
  out.n = p.n_points() - 2;
  return out;
}

}  // namespace detail

StatResult totdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads,
                  SumCache* cache, bool beyond_half) {
  detail::check_m_list("totdev", m_list);
  if (p.has_gaps())
    throw std::invalid_argument("totdev: cannot run on gapped data (" + std::to_string(p.n_gaps) +
                                " missing samples): the reflected extension of TOTVAR is "
                                "undefined across a gap");
  const std::int64_t n = p.n_points();
  // The inner centres are OADEV's terms and share its cache-tiled sweep (and, through the
  // cache, OADEV's sums themselves); the reflected ends (m - 1 centres each) are summed per m.
  // Same order as total_core: left, inner, right.
  std::vector<std::int64_t> valid_m;
  for (const std::int64_t m : m_list)
    if (detail::total_valid(n, m)) valid_m.push_back(m);
  const auto inner = detail::second_difference_sums(p, valid_m, nthreads, cache);
  std::vector<detail::SumCount> sums(m_list.size());
  for (std::size_t j = 0, v = 0; j < m_list.size(); ++j)
    if (detail::total_valid(n, m_list[j])) sums[j] = inner[v++];
  const auto ends = detail::sums_per_m(m_list, nthreads, [&p, n](std::int64_t m) {
    detail::SumCount lr;  // sum = left run, n = unused
    if (detail::total_valid(n, m)) lr.sum = detail::left_sum(p, m);
    return lr;
  });
  const auto rights = detail::sums_per_m(m_list, nthreads, [&p, n](std::int64_t m) {
    detail::SumCount lr;
    if (detail::total_valid(n, m)) lr.sum = detail::right_sum(p, m);
    return lr;
  });
  const auto wides = detail::sums_per_m(m_list, nthreads, [&p, n, beyond_half](std::int64_t m) {
    detail::SumCount w;
    if (beyond_half && detail::wide_valid(n, m)) w = {detail::wide_sum(p, m), n - 2};
    return w;
  });
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    if (wides[j].n > 0) sums[j] = wides[j];
    if (sums[j].n == 0 || wides[j].n > 0) continue;
    double total = ends[j].sum;
    total += sums[j].sum;
    total += rights[j].sum;
    sums[j].sum = total;
    sums[j].n = n - 2;
  }
  return detail::rows_from_sums(p.tau0_s, m_list, sums, [&p](std::int64_t m) {
    const double tau = static_cast<double>(m) * p.tau0_s;
    return 2.0 * tau * tau;
  });
}

}  // namespace allanlot::kernels
