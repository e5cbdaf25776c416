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
  double sum = 0.0;
  std::int64_t n = 0;
};

// Sum of the products of the two records' second differences over terms [b, e) in a fixed
// order, as the sweeps sum squares (detail/sweep.hpp): sixteen interleaved partial sums (lane
// l takes the terms i = b + l mod 16), reduced by detail::reduce_lanes. Independent lanes let
// the compiler use vectors; the order, and every bit, depend only on b and e. A term is
// skipped when either record misses an increment in x_i .. x_{i+2m}. Rounding: about
// (e - b) / 16 eps of sum |products| <= sqrt(sum dx^2 sum dy^2), i.e. relative to the
// geometric mean of the two records' Allan variances, not to the (possibly cancelling) sum.
ProductSum product_chunk(const PhaseData& x, const PhaseData& y, std::int64_t m, std::int64_t b,
                         std::int64_t e) {
  const detail::SecondDifference dx{x.x.data(), m}, dy{y.x.data(), m};
  double lane[detail::kLanes] = {};
  ProductSum out;
  if (!x.has_gaps() && !y.has_gaps()) {
    std::int64_t i = b;
    for (; i + detail::kLanes <= e; i += detail::kLanes)
      for (int l = 0; l < detail::kLanes; ++l)
        lane[l] += dx(i + l) * dy(i + l);
    for (; i < e; ++i)
      lane[(i - b) & (detail::kLanes - 1)] += dx(i) * dy(i);
    out.n = e - b;
  } else {
    for (std::int64_t i = b; i < e; ++i) {
      if (!(x.clean(i, i + 2 * m) && y.clean(i, i + 2 * m))) continue;
      lane[(i - b) & (detail::kLanes - 1)] += dx(i) * dy(i);
      ++out.n;
    }
  }
  out.sum = detail::reduce_lanes(lane);
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
    const double tau = static_cast<double>(m) * x.tau0_s;
    const double var = sums[j].sum / (2.0 * tau * tau * static_cast<double>(sums[j].n));
    r.m.push_back(m);
    r.tau_s.push_back(static_cast<double>(m) * x.tau0_s);
    r.n.push_back(sums[j].n);
    r.dev.push_back(
        std::copysign(static_cast<double>(std::sqrt(std::fabs(var))), static_cast<double>(var)));
  }
  return r;
}

}  // namespace allanlot::kernels
