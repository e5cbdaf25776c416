#include "kernels/allan/theo.hpp"

#include "kernels/allan/detail/chunked.hpp"
#include "kernels/allan/detail/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::kernels {
namespace {

// Inner terms (i, d) per work item: chunks of about 2^20 terms keep the fixed chunk count per
// m small while giving both threads work at the largest m.
constexpr std::int64_t kTermsPerChunk = std::int64_t{1} << 20;

// One i of eq. (30) with k = m/2 - d running 1 .. m/2: the pair (x_{i+k}, x_{i+m-k}) is the
// pair (x_{i+m/2-d}, x_{i+m/2+d}) of the equation. Summed in double (at most m/2 positive
// terms); the chunk adds the i in long double.
double theo1_inner(const double* x, std::int64_t i, std::int64_t m,
                   const std::vector<double>& inv) {
  const std::int64_t h = m / 2;
  const double a = x[i], b = x[i + m];
  double s = 0.0;
  for (std::int64_t k = 1; k <= h; ++k) {
    const double t = (a - x[i + k]) + (b - x[i + m - k]);
    s += t * t * inv[static_cast<std::size_t>(k)];
  }
  return s;
}

}  // namespace

bool theo1_valid(std::int64_t m, std::int64_t n_points, std::int64_t m_min) {
  return m % 2 == 0 && m >= std::max<std::int64_t>(m_min, 2) && m <= n_points - 1;
}

StatResult theo1(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads,
                 std::int64_t m_min) {
  detail::check_m_list("theo1", m_list);
  if (p.has_gaps())
    throw std::invalid_argument("theo1: cannot run on gapped data (" + std::to_string(p.n_gaps) +
                                " missing samples): fill the gaps first");
  const std::int64_t n = p.n_points();
  std::int64_t h_max = 0;
  for (const std::int64_t m : m_list)
    if (theo1_valid(m, n, m_min)) h_max = std::max(h_max, m / 2);
  // 1/k once, so that the inner loop multiplies (the same double for every thread count).
  std::vector<double> inv(static_cast<std::size_t>(h_max + 1), 0.0);
  for (std::int64_t k = 1; k <= h_max; ++k)
    inv[static_cast<std::size_t>(k)] = 1.0 / static_cast<double>(k);
  const auto chunks = detail::make_chunks(
      m_list,
      [n, m_min](std::int64_t m) { return theo1_valid(m, n, m_min) ? n - m : std::int64_t{0}; },
      [](std::int64_t m) { return kTermsPerChunk / std::max<std::int64_t>(1, m / 2); });
  const double* x = p.x.data();
  const auto sums = detail::run_chunks<long double>(
      m_list, chunks, nthreads,
      [&](std::int64_t m, std::int64_t b, std::int64_t e) {
        long double s = 0.0L;
        for (std::int64_t i = b; i < e; ++i)
          s += theo1_inner(x, i, m, inv);
        return s;
      },
      [](long double& acc, const long double& v) { acc += v; });
  StatResult out;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    const std::int64_t m = m_list[j];
    if (!theo1_valid(m, n, m_min)) continue;
    const long double tau = static_cast<long double>(m) * p.tau0_s;
    const long double var = sums[j] / (0.75L * static_cast<long double>(n - m) * tau * tau);
    out.m.push_back(m);
    out.tau_s.push_back(0.75 * static_cast<double>(m) * p.tau0_s);
    out.dev.push_back(static_cast<double>(std::sqrt(var)));
    out.n.push_back((n - m) * (m / 2));
  }
  return out;
}

StatResult theoh(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("theoh", m_list);
  if (p.has_gaps())
    throw std::invalid_argument("theoh: cannot run on gapped data (" + std::to_string(p.n_gaps) +
                                " missing samples): fill the gaps first");
  const std::int64_t n = p.n_points();
  const std::int64_t nbr =
      static_cast<std::int64_t>(std::floor(0.1 * static_cast<double>(n) / 3.0 - 3.0));
  if (nbr < 0) return {};
  const std::int64_t k = (n - 1) / 10;
  // The bias ratio of SP1065 eq. (31): OAVAR at 9 + 3i over Thêo1 at 12 + 4i, i = 0 .. nbr.
  std::vector<std::int64_t> ma, mt;
  for (std::int64_t i = 0; i <= nbr; ++i) {
    ma.push_back(9 + 3 * i);
    mt.push_back(12 + 4 * i);
  }
  const StatResult avar = oadev(p, ma, nthreads);
  const StatResult th = theo1(p, mt, nthreads);
  if (avar.size() != ma.size() || th.size() != mt.size()) return {};
  long double ratio = 0.0L;
  for (std::size_t i = 0; i < ma.size(); ++i) {
    const long double a = static_cast<long double>(avar.dev[i]) * avar.dev[i];
    const long double t = static_cast<long double>(th.dev[i]) * th.dev[i];
    ratio += t > 0.0L ? a / t : 0.0L;
  }
  ratio /= static_cast<long double>(ma.size());
  std::vector<std::int64_t> short_m, long_m;
  for (const std::int64_t m : m_list) {
    if (m < k) short_m.push_back(m);
    if (theo1_valid(m, n) && 3 * m >= 4 * k) long_m.push_back(m);
  }
  const StatResult a = oadev(p, short_m, nthreads);
  const StatResult t = theo1(p, long_m, nthreads);
  StatResult out;  // the rows in the order of m_list
  std::size_t ia = 0, it = 0;
  for (const std::int64_t m : m_list) {
    if (ia < a.size() && a.m[ia] == m && m < k) {
      out.m.push_back(m);
      out.tau_s.push_back(a.tau_s[ia]);
      out.dev.push_back(a.dev[ia]);
      out.n.push_back(a.n[ia++]);
    } else if (it < t.size() && t.m[it] == m) {
      out.m.push_back(m);
      out.tau_s.push_back(t.tau_s[it]);
      out.dev.push_back(static_cast<double>(t.dev[it] * std::sqrt(ratio)));
      out.n.push_back(t.n[it++]);
    }
  }
  return out;
}

}  // namespace allanlot::kernels
