#include "kernels/allan/codev.hpp"

#include "kernels/allan/detail/chunked.hpp"
#include "kernels/allan/detail/sweep.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

// Terms per work item: large enough that scheduling costs nothing, fixed so that the chunk
// bounds, and with them every bit of the sum, depend on m and N only.
constexpr std::int64_t kChunk = std::int64_t{1} << 16;

struct ProductSum {
  long double sum = 0.0L;
  std::int64_t n = 0;
};

// Sum of the products of the two records' second differences over terms [b, e), in index
// order; a term is skipped when either record misses an increment in x_i .. x_{i+2m}.
ProductSum product_chunk(const PhaseData& x, const PhaseData& y, std::int64_t m, std::int64_t b,
                         std::int64_t e) {
  const detail::SecondDifference dx{x.x.data(), m}, dy{y.x.data(), m};
  const bool gaps = x.has_gaps() || y.has_gaps();
  ProductSum out;
  for (std::int64_t i = b; i < e; ++i) {
    if (gaps && !(x.clean(i, i + 2 * m) && y.clean(i, i + 2 * m))) continue;
    out.sum += static_cast<long double>(dx(i)) * static_cast<long double>(dy(i));
    ++out.n;
  }
  return out;
}

}  // namespace

StatResult gcodev(const PhaseData& x, const PhaseData& y, std::span<const std::int64_t> m_list,
                  int nthreads) {
  detail::check_m_list("gcodev", m_list);
  if (x.n_points() != y.n_points())
    throw std::invalid_argument("gcodev: the records have " + std::to_string(x.n_points()) +
                                " and " + std::to_string(y.n_points()) +
                                " phase points; they must be equally long");
  if (x.tau0_s != y.tau0_s)
    throw std::invalid_argument("gcodev: the records' tau0_s differ (" + std::to_string(x.tau0_s) +
                                " and " + std::to_string(y.tau0_s) + ")");
  const std::int64_t n_points = x.n_points();
  const auto terms = [n_points](std::int64_t m) {
    return std::max<std::int64_t>(0, n_points - 2 * m);
  };
  const auto chunks = detail::make_chunks(m_list, terms, [](std::int64_t) { return kChunk; });
  const auto sums = detail::run_chunks<ProductSum>(
      m_list, chunks, nthreads,
      [&x, &y](std::int64_t m, std::int64_t b, std::int64_t e) {
        return product_chunk(x, y, m, b, e);
      },
      [](ProductSum& acc, const ProductSum& v) {
        acc.sum += v.sum;
        acc.n += v.n;
      });
  StatResult r;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    if (sums[j].n < 1) continue;
    const std::int64_t m = m_list[j];
    const long double tau = static_cast<long double>(m) * x.tau0_s;
    const long double var = sums[j].sum / (2.0L * tau * tau * static_cast<long double>(sums[j].n));
    r.m.push_back(m);
    r.tau_s.push_back(static_cast<double>(m) * x.tau0_s);
    r.n.push_back(sums[j].n);
    r.dev.push_back(
        std::copysign(static_cast<double>(std::sqrt(std::fabs(var))), static_cast<double>(var)));
  }
  return r;
}

}  // namespace allanlot::kernels
