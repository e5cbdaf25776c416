#include "kernels/allan.hpp"

#include "kernels/parallel.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace detail {

SumCount second_difference_core(const PhaseData& p, std::int64_t m, std::int64_t stride) {
  const double* x = p.x.data();
  const std::int64_t last = p.n_points() - 2 * m;  // terms i = 0 .. last-1
  SumCount out;
  if (last <= 0) return out;
  if (!p.has_gaps() && stride == 1) {
    // Four fixed partial sums: lets the compiler keep several additions in flight while the
    // summation order (and so the rounding) stays fixed for every thread count.
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    std::int64_t i = 0;
    for (; i + 4 <= last; i += 4) {
      const double d0 = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
      const double d1 = x[i + 1 + 2 * m] - 2.0 * x[i + 1 + m] + x[i + 1];
      const double d2 = x[i + 2 + 2 * m] - 2.0 * x[i + 2 + m] + x[i + 2];
      const double d3 = x[i + 3 + 2 * m] - 2.0 * x[i + 3 + m] + x[i + 3];
      s0 += d0 * d0;
      s1 += d1 * d1;
      s2 += d2 * d2;
      s3 += d3 * d3;
    }
    for (; i < last; ++i) {
      const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
      s0 += d * d;
    }
    out.sum = (s0 + s1) + (s2 + s3);
    out.n = last;
    return out;
  }
  for (std::int64_t i = 0; i < last; i += stride) {
    if (!p.clean(i, i + 2 * m)) continue;
    const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    out.sum += d * d;
    ++out.n;
  }
  return out;
}

}  // namespace detail

StatResult oadev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  for (const std::int64_t m : m_list)
    if (m < 1) throw std::invalid_argument("oadev: m must be >= 1, got " + std::to_string(m));
  const std::int64_t count = static_cast<std::int64_t>(m_list.size());
  std::vector<detail::SumCount> sums(m_list.size());
  const int nt = resolve_threads(nthreads);
  // One tau per iteration: each output is written by one thread in a fixed order.
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (std::int64_t j = 0; j < count; ++j)
    sums[static_cast<std::size_t>(j)] =
        detail::second_difference_core(p, m_list[static_cast<std::size_t>(j)], 1);

  StatResult r;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    if (sums[j].n < 1) continue;
    const double tau = static_cast<double>(m_list[j]) * p.tau0_s;
    r.m.push_back(m_list[j]);
    r.tau_s.push_back(tau);
    r.n.push_back(sums[j].n);
    r.dev.push_back(std::sqrt(sums[j].sum / (2.0 * tau * tau * static_cast<double>(sums[j].n))));
  }
  return r;
}

}  // namespace allanlot::kernels
