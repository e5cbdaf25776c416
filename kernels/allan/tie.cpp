#include "kernels/allan/tie.hpp"

#include "kernels/allan/detail/chunked.hpp"
#include "kernels/allan/detail/sweep.hpp"

#include <algorithm>
#include <vector>

namespace allanlot::kernels {
namespace {

// Windows per work item of MTIE: a chunk of W windows reads W + m points, so chunks of at
// least m windows keep the deque set-up below half of the work.
constexpr std::int64_t kMtieChunk = 1 << 16;

// The recorded phase, x_k plus the removed frequency offset (tie.hpp).
struct RawPhase {
  const double* x;
  double slope;  // tau0 * mean_rate, phase units per sample
  double operator()(std::int64_t k) const { return x[k] + slope * static_cast<double>(k); }
};

struct Extremum {
  double value = 0.0;
  std::int64_t n = 0;  // windows used
};

// Largest max - min over the windows [i, i + m], i in [b, e), that are clean, by two monotone
// deques of indices (decreasing values for the maximum, increasing for the minimum).
Extremum mtie_chunk(const PhaseData& p, const RawPhase& r, std::int64_t m, std::int64_t b,
                    std::int64_t e) {
  const std::int64_t len = e - b + m;
  std::vector<std::int64_t> hi(static_cast<std::size_t>(len)), lo(hi.size());
  std::size_t hh = 0, ht = 0, lh = 0, lt = 0;  // heads and tails of the two deques
  Extremum out;
  for (std::int64_t k = b; k < e + m; ++k) {
    const double v = r(k);
    while (ht > hh && r(hi[ht - 1]) <= v)
      --ht;
    hi[ht++] = k;
    while (lt > lh && r(lo[lt - 1]) >= v)
      --lt;
    lo[lt++] = k;
    const std::int64_t i = k - m;  // the window [i, k] is complete
    if (i < b) continue;
    while (hi[hh] < i)
      ++hh;
    while (lo[lh] < i)
      ++lh;
    if (!p.clean(i, k)) continue;
    out.value = std::max(out.value, r(hi[hh]) - r(lo[lh]));
    ++out.n;
  }
  return out;
}

double raw_slope(const PhaseData& p) {
  return p.tau0_s * p.mean_rate;
}

}  // namespace

StatResult mtie(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("mtie", m_list);
  const std::int64_t n = p.n_points();
  const RawPhase r{p.x.data(), raw_slope(p)};
  const auto chunks = detail::make_chunks(
      m_list, [n](std::int64_t m) { return std::max<std::int64_t>(0, n - m); },
      [](std::int64_t m) { return std::max(kMtieChunk, m); });
  const auto best = detail::run_chunks<Extremum>(
      m_list, chunks, nthreads,
      [&](std::int64_t m, std::int64_t b, std::int64_t e) { return mtie_chunk(p, r, m, b, e); },
      [](Extremum& acc, const Extremum& v) {
        acc.value = std::max(acc.value, v.value);
        acc.n += v.n;
      });
  StatResult out;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    if (best[j].n < 1) continue;
    out.m.push_back(m_list[j]);
    out.tau_s.push_back(static_cast<double>(m_list[j]) * p.tau0_s);
    out.dev.push_back(best[j].value);
    out.n.push_back(best[j].n);
  }
  return out;
}

StatResult tierms(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("tierms", m_list);
  const std::int64_t n = p.n_points();
  const double slope = raw_slope(p);
  const auto sums = detail::sums_per_m(m_list, nthreads, [&p, n, slope](std::int64_t m) {
    detail::SumCount sc;
    if (m >= n) return sc;
    const double* x = p.x.data();
    const double offset = slope * static_cast<double>(m);
    // A pair across a gap contributes a zero term and is not counted.
    const auto term = [&p, x, m, offset](std::int64_t k) {
      return p.clean(k, k + m) ? (x[k + m] - x[k]) + offset : 0.0;
    };
    sc.sum = detail::blocked_sum_of_squares(detail::scalar_term(term), n - m);
    if (!p.has_gaps()) {
      sc.n = n - m;
    } else {
      for (std::int64_t k = 0; k + m < n; ++k)
        sc.n += p.clean(k, k + m) ? 1 : 0;
    }
    return sc;
  });
  return detail::rows_from_sums(p.tau0_s, m_list, sums, [](std::int64_t) { return 1.0; });
}

}  // namespace allanlot::kernels
