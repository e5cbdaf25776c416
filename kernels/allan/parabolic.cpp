#include "kernels/allan/parabolic.hpp"

#include "kernels/allan/detail/chunked.hpp"
#include "kernels/allan/detail/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::kernels {
namespace {

// Terms per chunk: at least 2^16, and at least m so that forming A and B afresh (O(m)) is at
// most half of a chunk's work.
constexpr std::int64_t kChunk = std::int64_t{1} << 16;

std::int64_t pdev_terms(std::int64_t n, std::int64_t m) {
  return m >= 2 ? std::max<std::int64_t>(0, n - 2 * m) : 0;
}

// Sum of A_i^2 for i in [b, e) (parabolic.hpp).
long double pdev_chunk(const double* x, std::int64_t m, std::int64_t b, std::int64_t e) {
  const auto d = [x, m](std::int64_t j) { return static_cast<long double>(x[j] - x[j + m]); };
  const long double w0 = 0.5L * static_cast<long double>(m - 1);
  const long double wm = w0 - static_cast<long double>(m);
  long double a = 0.0L, s = 0.0L;
  for (std::int64_t k = 0; k < m; ++k) {
    a += (w0 - static_cast<long double>(k)) * d(b + k);
    s += d(b + k);
  }
  long double sum = a * a;
  for (std::int64_t i = b; i + 1 < e; ++i) {
    const long double di = d(i), dm = d(i + m);
    s += dm - di;
    a += (wm * dm - w0 * di) + s;
    sum += a * a;
  }
  return sum;
}

}  // namespace

StatResult pdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("pdev", m_list);
  if (p.has_gaps())
    throw std::invalid_argument("pdev: cannot run on gapped data (" + std::to_string(p.n_gaps) +
                                " missing samples): fill the gaps first");
  const std::int64_t n = p.n_points();
  const double* x = p.x.data();
  const auto chunks = detail::make_chunks(
      m_list, [n](std::int64_t m) { return pdev_terms(n, m); },
      [](std::int64_t m) { return std::max(kChunk, m); });
  const auto sums = detail::run_chunks<long double>(
      m_list, chunks, nthreads,
      [x](std::int64_t m, std::int64_t b, std::int64_t e) { return pdev_chunk(x, m, b, e); },
      [](long double& acc, const long double& v) { acc += v; });
  const std::int64_t one[] = {1};
  const bool has_one = std::find(m_list.begin(), m_list.end(), 1) != m_list.end();
  const StatResult oa = has_one ? oadev(p, one, nthreads) : StatResult{};
  StatResult out;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    const std::int64_t m = m_list[j];
    if (m == 1) {
      if (oa.size() == 0) continue;
      out.m.push_back(1);
      out.tau_s.push_back(oa.tau_s[0]);
      out.dev.push_back(oa.dev[0]);
      out.n.push_back(oa.n[0]);
      continue;
    }
    const std::int64_t M = pdev_terms(n, m);
    if (M < 1) continue;
    const long double tau = static_cast<long double>(m) * p.tau0_s;
    const long double m4 = std::pow(static_cast<long double>(m), 4);
    out.m.push_back(m);
    out.tau_s.push_back(static_cast<double>(m) * p.tau0_s);
    out.n.push_back(M);
    out.dev.push_back(static_cast<double>(std::sqrt(72.0L * sums[j] / (M * m4 * tau * tau))));
  }
  return out;
}

}  // namespace allanlot::kernels
