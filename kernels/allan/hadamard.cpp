#include "kernels/allan/hadamard.hpp"

#include "kernels/allan/detail/sweep.hpp"

namespace allanlot::kernels {
namespace detail {

SumCount third_difference_core(const PhaseData& p, std::int64_t m, std::int64_t stride) {
  const double* x = p.x.data();
  const std::int64_t last = p.n_points() - 3 * m;  // terms i = 0 .. last-1
  SumCount out;
  if (last <= 0) return out;
  const ThirdDifference d{x, m};
  if (!p.has_gaps()) {
    if (stride == 1) {
      out.n = last;
      out.sum = blocked_sum_of_squares(d, out.n);
    } else {
      out.n = (last - 1) / stride + 1;
      out.sum = blocked_sum_of_squares(
          scalar_term([d, stride](std::int64_t k) { return d(k * stride); }), out.n);
    }
    return out;
  }
  for (std::int64_t i = 0; i < last; i += stride) {
    if (!p.clean(i, i + 3 * m)) continue;
    const double v = d(i);
    out.sum += v * v;
    ++out.n;
  }
  return out;
}

}  // namespace detail

namespace {
// H sigma^2 = sum / (6 tau^2 n), SP1065 eqs. (17) and (18).
double hadamard_norm(const PhaseData& p, std::int64_t m) {
  const double tau = static_cast<double>(m) * p.tau0_s;
  return 6.0 * tau * tau;
}
}  // namespace

StatResult hdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("hdev", m_list);
  // Non-overlapping: N/m terms per m, cheap enough for one m per work item.
  const auto sums = detail::sums_per_m(
      m_list, nthreads, [&p](std::int64_t m) { return detail::third_difference_core(p, m, m); });
  return detail::rows_from_sums(p.tau0_s, m_list, sums,
                                [&p](std::int64_t m) { return hadamard_norm(p, m); });
}

StatResult ohdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads,
                 SumCache* cache) {
  detail::check_m_list("ohdev", m_list);
  if (p.has_gaps()) {
    const auto sums = detail::sums_per_m(
        m_list, nthreads, [&p](std::int64_t m) { return detail::third_difference_core(p, m, 1); });
    return detail::rows_from_sums(p.tau0_s, m_list, sums,
                                  [&p](std::int64_t m) { return hadamard_norm(p, m); });
  }
  const auto sums = detail::sums_through_cache(
      m_list,
      [cache](std::int64_t m) {
        return cache ? cache->third(m) : std::optional<std::pair<double, std::int64_t>>{};
      },
      [&p, nthreads](std::span<const std::int64_t> missing) {
        return detail::sums_tiled(
            missing, nthreads,
            [&p](std::int64_t m) {
              return detail::ThirdDifference{p.x.data(), m};
            },
            [&p](std::int64_t m) { return p.n_points() - 3 * m; });
      },
      [](std::int64_t, const detail::SumCount&) {});  // third sums come only from priming
  return detail::rows_from_sums(p.tau0_s, m_list, sums,
                                [&p](std::int64_t m) { return hadamard_norm(p, m); });
}

}  // namespace allanlot::kernels
