#include "kernels/allan/allan.hpp"

#include "kernels/allan/detail/sweep.hpp"
#include "kernels/common/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace allanlot::kernels {
namespace detail {
namespace {

// Round to nearest (ties to even, the default mode), like std::llrint, which GCC does not
// inline without -fno-math-errno; |v| < 2^63 is the caller's guarantee.
inline std::int64_t round_to_int64(double v) {
#ifdef __SSE2__
  return _mm_cvtsd_si64(_mm_set_sd(v));
#else
  return std::llrint(v);
#endif
}

}  // namespace

SumCount second_difference_core(const PhaseData& p, std::int64_t m, std::int64_t stride) {
  const double* x = p.x.data();
  const std::int64_t last = p.n_points() - 2 * m;  // terms i = 0 .. last-1
  SumCount out;
  if (last <= 0) return out;
  if (!p.has_gaps()) {
    if (stride == 1) {
      out.n = last;
      out.sum = blocked_sum_of_squares(SecondDifference{x, m}, out.n);
    } else {
      const SecondDifference d{x, m};
      out.n = (last - 1) / stride + 1;
      out.sum = blocked_sum_of_squares(
          scalar_term([d, stride](std::int64_t k) { return d(k * stride); }), out.n);
    }
    return out;
  }
  // Gapped data: the same term values, skipping terms whose span x_i .. x_{i+2m} misses an
  // increment; a plain running sum, as gapped records are the exception.
  const SecondDifference d{x, m};
  for (std::int64_t i = 0; i < last; i += stride) {
    if (!p.clean(i, i + 2 * m)) continue;
    const double v = d(i);
    out.sum += v * v;
    ++out.n;
  }
  return out;
}

std::vector<SumCount> second_difference_sums(const PhaseData& p,
                                             std::span<const std::int64_t> m_list, int nthreads,
                                             SumCache* cache) {
  return sums_through_cache(
      m_list,
      [cache](std::int64_t m) {
        return cache ? cache->second(m) : std::optional<std::pair<double, std::int64_t>>{};
      },
      [&p, nthreads](std::span<const std::int64_t> missing) {
        return sums_tiled(
            missing, nthreads,
            [&p](std::int64_t m) {
              return SecondDifference{p.x.data(), m};
            },
            [&p](std::int64_t m) { return p.n_points() - 2 * m; });
      },
      [cache](std::int64_t m, const SumCount& c) {
        if (cache) cache->store_second(m, c.sum, c.n);
      });
}

WindowSums make_window_sums(const PhaseData& p, std::int64_t m_cap, int nthreads) {
  const std::int64_t n = p.n_points();
  const double* x = p.x.data();
  WindowSums w;
  w.s.resize(static_cast<std::size_t>(n) + 1);  // s[0] here, the rest by pass 1 below
  w.s[0] = 0;
  if (n == 0) return w;
  // Fixed chunks: the maximum is exact and the integer sums are associative, so the chunking
  // only decides the work split, never a bit of the result.
  constexpr std::int64_t kChunk = 1 << 16;
  const std::int64_t nchunks = (n + kChunk - 1) / kChunk;
  [[maybe_unused]] const int nt = resolve_threads(nthreads);  // unused without OpenMP
  std::vector<double> chunk_max(static_cast<std::size_t>(nchunks), 0.0);
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t c = 0; c < nchunks; ++c) {
    double mx = 0.0;
    for (std::int64_t i = c * kChunk, e = std::min(n, (c + 1) * kChunk); i < e; ++i)
      mx = std::max(mx, std::fabs(x[i]));
    chunk_max[static_cast<std::size_t>(c)] = mx;
  }
  double max_abs = 0.0;
  for (const double v : chunk_max)
    max_abs = std::max(max_abs, v);

  // max|X| <= 2^value_bits keeps 4 m max|X| < 2^63 for every m <= m_cap (header comment).
  int cap_bits = 0;
  while ((std::int64_t{1} << cap_bits) < m_cap + 1)
    ++cap_bits;
  const int value_bits = 60 - cap_bits;
  int exponent = 0;  // max_abs < 2^exponent
  if (max_abs > 0.0) std::frexp(max_abs, &exponent);
  w.scale_bits = max_abs > 0.0 ? value_bits - exponent : 0;
  w.inv_scale = std::ldexp(1.0, -w.scale_bits);
  const int bits = w.scale_bits;
  // Multiplying by 2^bits is exact like ldexp and much cheaper, when 2^bits is a normal double.
  const bool use_mul = bits > -1022 && bits < 1023;
  const double scale = use_mul ? std::ldexp(1.0, bits) : 1.0;

  std::vector<std::uint64_t> chunk_sum(static_cast<std::size_t>(nchunks), 0);
  std::uint64_t* s = w.s.data();
  // Pass 1 stores X_i in s[i+1] and sums each chunk; pass 2 turns them into the prefix sums.
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t c = 0; c < nchunks; ++c) {
    std::uint64_t acc = 0;
    for (std::int64_t i = c * kChunk, e = std::min(n, (c + 1) * kChunk); i < e; ++i) {
      // Exact scaling (|x| 2^bits <= 2^value_bits), then round to nearest.
      const double scaled = use_mul ? x[i] * scale : std::ldexp(x[i], bits);
      const auto v = static_cast<std::uint64_t>(round_to_int64(scaled));
      s[i + 1] = v;
      acc += v;
    }
    chunk_sum[static_cast<std::size_t>(c)] = acc;
  }
  std::vector<std::uint64_t> offset(static_cast<std::size_t>(nchunks), 0);
  for (std::int64_t c = 1; c < nchunks; ++c)
    offset[static_cast<std::size_t>(c)] =
        offset[static_cast<std::size_t>(c) - 1] + chunk_sum[static_cast<std::size_t>(c) - 1];
#pragma omp parallel for num_threads(nt) schedule(static)
  for (std::int64_t c = 0; c < nchunks; ++c) {
    std::uint64_t acc = offset[static_cast<std::size_t>(c)];
    for (std::int64_t i = c * kChunk, e = std::min(n, (c + 1) * kChunk); i < e; ++i) {
      acc += s[i + 1];
      s[i + 1] = acc;
    }
  }
  return w;
}

SumCount modified_core(const PhaseData& p, const WindowSums& w, std::int64_t m) {
  const std::int64_t terms = p.n_points() - 3 * m + 1;  // j = 0 .. N-3m
  SumCount out;
  if (terms <= 0) return out;
  const ModifiedInnerSum inner{w.s.data(), m, w.inv_scale};
  if (!p.has_gaps()) {
    out.n = terms;
    out.sum = blocked_sum_of_squares(inner, terms);
    return out;
  }
  for (std::int64_t j = 0; j < terms; ++j) {
    if (!p.clean(j, j + 3 * m - 1)) continue;  // the inner sum uses x_j .. x_{j+3m-1}
    const double d = inner(j);
    out.sum += d * d;
    ++out.n;
  }
  return out;
}

}  // namespace detail

namespace {

double allan_norm(const PhaseData& p, std::int64_t m) {  // sigma^2 = sum / (2 tau^2 n)
  const double tau = static_cast<double>(m) * p.tau0_s;
  return 2.0 * tau * tau;
}

}  // namespace

StatResult adev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  detail::check_m_list("adev", m_list);
  // Non-overlapping: N/m terms per m, cheap enough for one m per work item.
  const auto sums = detail::sums_per_m(
      m_list, nthreads, [&p](std::int64_t m) { return detail::second_difference_core(p, m, m); });
  return detail::rows_from_sums(p.tau0_s, m_list, sums,
                                [&p](std::int64_t m) { return allan_norm(p, m); });
}

StatResult oadev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads,
                 SumCache* cache) {
  detail::check_m_list("oadev", m_list);
  const auto sums = p.has_gaps()
                        ? detail::sums_per_m(m_list, nthreads,
                                             [&p](std::int64_t m) {
                                               return detail::second_difference_core(p, m, 1);
                                             })
                        : detail::second_difference_sums(p, m_list, nthreads, cache);
  return detail::rows_from_sums(p.tau0_s, m_list, sums,
                                [&p](std::int64_t m) { return allan_norm(p, m); });
}

namespace {

// MDEV and TDEV share the core and the window sums; they differ only in the normalization:
// Mod sigma^2 = sum / (2 m^2 tau^2 n) (eq. 14) and TDEV^2 = tau^2/3 Mod sigma^2 = sum / (6 m^2 n)
// (eq. 16).
template <class Norm>
StatResult modified_family(std::string_view stat, const PhaseData& p,
                           std::span<const std::int64_t> m_list, int nthreads, Norm norm) {
  detail::check_m_list(stat, m_list);
  // m_cap from N alone (N/3, the largest m with a term), not from m_list: the fixed-point
  // scale, and so every bit of a row, then does not depend on which other m were requested.
  const std::int64_t m_cap = std::max<std::int64_t>(1, p.n_points() / 3);
  const detail::WindowSums w = detail::make_window_sums(p, m_cap, nthreads);
  const auto sums =
      p.has_gaps()
          ? detail::sums_per_m(m_list, nthreads,
                               [&p, &w](std::int64_t m) { return detail::modified_core(p, w, m); })
          : detail::sums_tiled(
                m_list, nthreads,
                [&w](std::int64_t m) {
                  return detail::ModifiedInnerSum{w.s.data(), m, w.inv_scale};
                },
                [&p](std::int64_t m) { return p.n_points() - 3 * m + 1; });
  return detail::rows_from_sums(p.tau0_s, m_list, sums, norm);
}

}  // namespace

StatResult mdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  return modified_family("mdev", p, m_list, nthreads, [&p](std::int64_t m) {
    const double md = static_cast<double>(m);
    const double tau = md * p.tau0_s;
    return 2.0 * md * md * tau * tau;
  });
}

// TDEV is always MDEV scaled (SP1065 eq. (16)), so that a TDEV computed alone has the same
// bits as the one the pipeline derives from the MDEV it has already computed.
StatResult tdev(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  return tdev_from_mdev(mdev(p, m_list, nthreads));
}

StatResult tdev_from_mdev(const StatResult& mdev) {
  StatResult r;
  r.m = mdev.m;
  r.tau_s = mdev.tau_s;
  r.n = mdev.n;
  r.dev.resize(mdev.dev.size());
  for (std::size_t i = 0; i < mdev.dev.size(); ++i)
    r.dev[i] = mdev.tau_s[i] / std::sqrt(3.0) * mdev.dev[i];
  return r;
}

void prime_second_third(const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads,
                        SumCache& cache) {
  if (p.has_gaps()) return;
  detail::check_m_list("prime_second_third", m_list);
  std::vector<std::int64_t> ms;  // those with a term of either kind
  for (const std::int64_t m : m_list)
    if (p.n_points() - 2 * m > 0) ms.push_back(m);
  std::vector<detail::SumCount> second, third;
  detail::sums_tiled_second_third(p.x.data(), p.n_points(), ms, nthreads, second, third);
  for (std::size_t j = 0; j < ms.size(); ++j) {
    cache.store_second(ms[j], second[j].sum, second[j].n);
    if (third[j].n > 0) cache.store_third(ms[j], third[j].sum, third[j].n);
  }
}

}  // namespace allanlot::kernels
