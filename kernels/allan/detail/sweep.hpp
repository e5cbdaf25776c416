// Private to the Allan-family kernels: the sums of squared differences over a list of
// averaging factors that every public statistic shares (argument check, the cache-tiled
// parallel sweep, the rows of the result).
//
// Determinism: every sum of squares is formed in one fixed order, whatever the thread count,
// the SIMD level and whichever path computes it: terms k = 0 .. n-1 in blocks of kBlock,
// inside a block sixteen interleaved partial sums (lane l takes the terms k = l mod 16), a
// block's value by the fixed tree of reduce_lanes, and the block values added in index order.
// Threads and vector widths only decide who computes a block, never how it is rounded.
#pragma once

#ifndef ALLANLOT_KERNELS_FAMILY_HEADER
#error                                                                                             \
    "kernels/allan/detail/sweep.hpp is private: include kernels/allan/allan.hpp (or another family header) first"
#endif

#include "kernels/common/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace allanlot::kernels::detail {

/// Throws std::invalid_argument, naming the statistic, for any m < 1; called before any
/// parallel region so that no exception is ever thrown inside one.
inline void check_m_list(std::string_view stat, std::span<const std::int64_t> m_list) {
  for (const std::int64_t m : m_list)
    if (m < 1)
      throw std::invalid_argument(std::string(stat) + ": m must be >= 1, got " + std::to_string(m));
}

/// Turns each (sum, n) with n >= 1 into a row with dev = sqrt(sum / (norm(m) n)); rows keep
/// the order of m_list, an m without terms gives no row.
template <class Norm>
StatResult rows_from_sums(double tau0_s, std::span<const std::int64_t> m_list,
                          const std::vector<SumCount>& sums, Norm norm) {
  StatResult r;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    if (sums[j].n < 1) continue;
    const std::int64_t m = m_list[j];
    r.m.push_back(m);
    r.tau_s.push_back(static_cast<double>(m) * tau0_s);
    r.n.push_back(sums[j].n);
    r.dev.push_back(std::sqrt(sums[j].sum / (norm(m) * static_cast<double>(sums[j].n))));
  }
  return r;
}

/// Runs `core(m) -> SumCount` for every m of m_list, one m per OpenMP iteration; used for
/// gapped data, where each term needs a gap test and the plain loop is good enough.
template <class Core>
std::vector<SumCount> sums_per_m(std::span<const std::int64_t> m_list, int nthreads, Core core) {
  const auto count = static_cast<std::int64_t>(m_list.size());
  std::vector<SumCount> sums(m_list.size());
  ExceptionCollector errors;
  [[maybe_unused]] const int nt = resolve_threads(nthreads);  // unused without OpenMP
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (std::int64_t j = 0; j < count; ++j)
    errors.run(
        [&] { sums[static_cast<std::size_t>(j)] = core(m_list[static_cast<std::size_t>(j)]); });
  errors.rethrow();
  return sums;
}

/// Terms per block of the blocked summation of squares: the rounding error of a sum of n
/// squares is bounded by (kBlock/16 + n/kBlock) eps (~6e-13 for n = 5.4e6) instead of n eps
/// for one running sum.
inline constexpr std::int64_t kBlock = 1024;

// Two-lane vectors (GCC/Clang vector extension, SSE2 registers): a pair of lanes is two of the
// sixteen partial sums, so the vector code rounds exactly as a scalar sixteen-sum loop would.
using V2 = double __attribute__((vector_size(16)));
using U2 = std::uint64_t __attribute__((vector_size(16)));
using I2 = std::int64_t __attribute__((vector_size(16)));

inline V2 load2(const double* p) {
  V2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline U2 load2(const std::uint64_t* p) {
  U2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// Second difference x_{k+2m} - 2 x_{k+m} + x_k (ADEV, OADEV, TOTDEV's inner centres).
struct SecondDifference {
  const double* x;
  std::int64_t m;
  double operator()(std::int64_t k) const { return x[k + 2 * m] - 2.0 * x[k + m] + x[k]; }
  V2 pair(std::int64_t k) const {
    return load2(x + k + 2 * m) - 2.0 * load2(x + k + m) + load2(x + k);
  }
};

/// Third difference (x_{k+3m} - x_k) - 3 (x_{k+2m} - x_{k+m}) (HDEV, OHDEV): two differences of
/// nearby points first keep the rounding relative to the increments rather than to x.
struct ThirdDifference {
  const double* x;
  std::int64_t m;
  double operator()(std::int64_t k) const {
    return (x[k + 3 * m] - x[k]) - 3.0 * (x[k + 2 * m] - x[k + m]);
  }
  V2 pair(std::int64_t k) const {
    return (load2(x + k + 3 * m) - load2(x + k)) - 3.0 * (load2(x + k + 2 * m) - load2(x + k + m));
  }
};

/// Correctly rounded int64 -> double for both lanes with SSE2 integer operations only (SSE2
/// has no packed int64 conversion; the compiler would go through scalar registers): with
/// u = v + 2^63 = hi 2^32 + lo, v = (hi - 2^31) 2^32 + lo, where both parts are exact doubles
/// (read off the bit patterns 2^52 + hi and 2^52 + lo) and the one addition rounds to
/// nearest, exactly like static_cast<double>(v).
inline V2 to_double(U2 v) {
  const U2 u = v ^ U2 { 0x8000000000000000u, 0x8000000000000000u };
  const U2 exp52 = {0x4330000000000000u, 0x4330000000000000u};  // bit pattern of 2^52
  const V2 hi = (V2)((u >> 32) | exp52) - (4503599627370496.0 + 2147483648.0);
  const V2 lo = (V2)((u & U2{0xffffffffu, 0xffffffffu}) | exp52) - 4503599627370496.0;
  return hi * 4294967296.0 + lo;
}

/// MDEV inner sum, the exact integer third difference of the fixed-point window sums s
/// (WindowSums; wrap-around cancels), rounded once to double and scaled by q = 2^-scale_bits.
struct ModifiedInnerSum {
  const std::uint64_t* s;
  std::int64_t m;
  double q;
  double operator()(std::int64_t j) const {
    const std::uint64_t a = s[j + 2 * m] - s[j + m];
    const std::uint64_t d = (s[j + 3 * m] - s[j]) - (a + (a << 1));
    return static_cast<double>(static_cast<std::int64_t>(d)) * q;
  }
  V2 pair(std::int64_t j) const {
    const U2 a = load2(s + j + 2 * m) - load2(s + j + m);
    const U2 d = (load2(s + j + 3 * m) - load2(s + j)) - (a + (a << 1));
    return to_double(d) * q;
  }
};

/// Any term function g(k) seen through the same interface (the pair is formed lane by lane,
/// so the rounding is that of the contiguous functors): for strided or reflected terms.
template <class G>
struct ScalarTerm {
  G g;
  double operator()(std::int64_t k) const { return g(k); }
  V2 pair(std::int64_t k) const { return V2{g(k), g(k + 1)}; }
};
template <class G>
ScalarTerm<G> scalar_term(G g) {
  return ScalarTerm<G>{g};
}

/// Partial sums per block: lane l takes the terms k = b + l (mod kLanes). Sixteen independent
/// additions in flight hide the add latency on every vector width (8 two-double registers,
/// 4 four-double or 2 eight-double registers hold the same lanes), so the order, and with it
/// every bit, is the same on every SIMD level.
inline constexpr int kLanes = 16;

/// A block's value from its lanes, in one fixed tree: lanes l and l + 8, then l and l + 4,
/// l and l + 2, and the last two (the pairing a halving of any vector width produces).
inline double reduce_lanes(const double (&s)[kLanes]) {
  double t[8], u[4];
  for (int l = 0; l < 8; ++l)
    t[l] = s[l] + s[l + 8];
  for (int l = 0; l < 4; ++l)
    u[l] = t[l] + t[l + 4];
  return (u[0] + u[2]) + (u[1] + u[3]);
}

/// Sum of f(k)^2 for k in [b, e), e - b <= kBlock, in the fixed order above, with two-double
/// vectors: the baseline path, and the only one for terms that are not contiguous loads.
template <class Term>
double block_sum_baseline_from(const Term& f, V2* acc, std::int64_t k, std::int64_t b,
                               std::int64_t e) {
  for (; k + kLanes <= e; k += kLanes) {
#pragma GCC unroll 8
    for (int a = 0; a < kLanes / 2; ++a) {
      const V2 d = f.pair(k + 2 * a);
      acc[a] += d * d;
    }
  }
  double s[kLanes];
  std::memcpy(s, acc, sizeof s);
  for (; k < e; ++k) {
    const double d = f(k);
    s[(k - b) & (kLanes - 1)] += d * d;
  }
  return reduce_lanes(s);
}

template <class Term>
double block_sum_baseline(const Term& f, std::int64_t b, std::int64_t e) {
  V2 acc[kLanes / 2] = {};
  return block_sum_baseline_from(f, acc, b, b, e);
}

/// The second and third differences at one m over one block from one set of loads, each in
/// its own lanes and tree: the same two values as block_sum_baseline of SecondDifference over
/// [b, e2) and of ThirdDifference over [b, e3), e3 <= e2.
inline void block_sums_second_third_baseline(const double* x, std::int64_t m, std::int64_t b,
                                             std::int64_t e2, std::int64_t e3, double* s2,
                                             double* s3) {
  V2 a2[kLanes / 2] = {}, a3[kLanes / 2] = {};
  std::int64_t k = b;
  for (; k + kLanes <= e3; k += kLanes) {
#pragma GCC unroll 8
    for (int a = 0; a < kLanes / 2; ++a) {
      const double* p = x + k + 2 * a;
      const V2 x0 = load2(p), x1 = load2(p + m), x2 = load2(p + 2 * m), x3 = load2(p + 3 * m);
      const V2 d2 = x2 - 2.0 * x1 + x0;
      const V2 d3 = (x3 - x0) - 3.0 * (x2 - x1);
      a2[a] += d2 * d2;
      a3[a] += d3 * d3;
    }
  }
  *s3 = block_sum_baseline_from(ThirdDifference{x, m}, a3, k, b, e3);
  *s2 = block_sum_baseline_from(SecondDifference{x, m}, a2, k, b, e2);
}

template <class Term>
double block_sum(const Term& f, std::int64_t b, std::int64_t e) {
  return block_sum_baseline(f, b, e);
}

// The contiguous terms run on the widest vectors the CPU has (kernels/allan/sweep_simd.cpp,
// kernels/allan/simd.hpp); same lanes, same tree, same bits.
double block_sum(const SecondDifference& f, std::int64_t b, std::int64_t e);
double block_sum(const ThirdDifference& f, std::int64_t b, std::int64_t e);
double block_sum(const ModifiedInnerSum& f, std::int64_t b, std::int64_t e);
/// Both block values of block_sums_second_third_baseline, on the widest vectors.
void block_sums_second_third(const double* x, std::int64_t m, std::int64_t b, std::int64_t e2,
                             std::int64_t e3, double* s2, double* s3);

/// Sum of f(k)^2 for k = 0 .. n-1 in the fixed blocked order.
template <class Term>
double blocked_sum_of_squares(const Term& f, std::int64_t n) {
  double total = 0.0;
  for (std::int64_t b = 0; b < n; b += kBlock)
    total += block_sum(f, b, std::min(n, b + kBlock));
  return total;
}

/// Blocks per tile of the multi-tau sweep below: 16 blocks, 16384 terms, 128 KiB of each
/// stream.
inline constexpr std::int64_t kTileBlocks = 16;

/// Sums of squared terms for every m of m_list on gap-free data: the multi-tau sweep. `make(m)`
/// returns the term functor for m and `count(m)` its number of terms. The record is walked in
/// tiles of kTileBlocks blocks (one OpenMP work item per tile) and every m sums its terms of
/// the tile before the next tile starts. The tile's own samples x_k .. (128 KiB) are read by
/// every m from L2; for m up to about 65536 the shifted reads x_{k+m}, x_{k+2m} (x_{k+3m}) of
/// all m fall within ~1 MiB and stay in L2 too, and for larger m only those come from L3 or
/// memory, one stream fewer than a sweep per m (measured: the 21 largest OADEV m take 76 ms
/// against 118 ms one m at a time on 5.4 M samples, bench_allan BM_OadevLargeM). Each block value
/// is formed in the fixed order and the blocks are added in index order, so a result depends
/// neither on the thread count nor on which other m were swept with it.
template <class Make, class Count>
std::vector<SumCount> sums_tiled(std::span<const std::int64_t> m_list, int nthreads, Make make,
                                 Count count) {
  std::vector<SumCount> sums(m_list.size());
  std::vector<std::size_t> active;  // the m with at least one term
  std::int64_t max_blocks = 0;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    sums[j].n = std::max<std::int64_t>(0, count(m_list[j]));
    if (sums[j].n == 0) continue;
    active.push_back(j);
    max_blocks = std::max(max_blocks, (sums[j].n + kBlock - 1) / kBlock);
  }
  const auto n_active = static_cast<std::int64_t>(active.size());
  const std::int64_t n_tiles = (max_blocks + kTileBlocks - 1) / kTileBlocks;
  // block_value[a * max_blocks + b]: block b of active m number a.
  std::vector<double> block_value(static_cast<std::size_t>(n_active * max_blocks), 0.0);
  ExceptionCollector errors;
  [[maybe_unused]] const int nt = resolve_threads(nthreads);  // unused without OpenMP
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (std::int64_t w = 0; w < n_tiles; ++w)
    errors.run([&] {
      const std::int64_t b0 = w * kTileBlocks;
      for (std::int64_t a = 0; a < n_active; ++a) {
        const std::size_t j = active[static_cast<std::size_t>(a)];
        const auto f = make(m_list[j]);
        const std::int64_t n = sums[j].n;
        for (std::int64_t b = b0; b < b0 + kTileBlocks && b * kBlock < n; ++b)
          block_value[static_cast<std::size_t>(a * max_blocks + b)] =
              block_sum(f, b * kBlock, std::min(n, (b + 1) * kBlock));
      }
    });
  errors.rethrow();
  for (std::int64_t a = 0; a < n_active; ++a) {
    const std::size_t j = active[static_cast<std::size_t>(a)];
    double total = 0.0;
    for (std::int64_t b = 0; b * kBlock < sums[j].n; ++b)
      total += block_value[static_cast<std::size_t>(a * max_blocks + b)];
    sums[j].sum = total;
  }
  return sums;
}

/// The sums of m_list: those `hit(m)` (an optional (sum, n)) finds in a SumCache, the rest from
/// `compute(missing)` in m_list's order, each then handed to `store(m, SumCount)`.
template <class Hit, class Compute, class Store>
std::vector<SumCount> sums_through_cache(std::span<const std::int64_t> m_list, Hit hit,
                                         Compute compute, Store store) {
  std::vector<SumCount> sums(m_list.size());
  std::vector<std::int64_t> missing;
  std::vector<std::size_t> where;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    if (const auto h = hit(m_list[j])) {
      sums[j] = {h->first, h->second};
      continue;
    }
    missing.push_back(m_list[j]);
    where.push_back(j);
  }
  const std::vector<SumCount> computed = compute(std::span<const std::int64_t>(missing));
  for (std::size_t i = 0; i < missing.size(); ++i) {
    sums[where[i]] = computed[i];
    store(missing[i], computed[i]);
  }
  return sums;
}

/// OADEV's and OHDEV's sums of squares at every m of m_list at once on gap-free data (the
/// default statistics ask for both): the tiles of sums_tiled, each block's two values from one
/// set of loads (block_sums_second_third), so both results equal sums_tiled's of
/// SecondDifference (N - 2m terms) and ThirdDifference (N - 3m terms) bit for bit, for a
/// fraction of the two sweeps' loads.
inline void sums_tiled_second_third(const double* x, std::int64_t n_points,
                                    std::span<const std::int64_t> m_list, int nthreads,
                                    std::vector<SumCount>& second, std::vector<SumCount>& third) {
  const auto nm = static_cast<std::int64_t>(m_list.size());
  second.assign(m_list.size(), {});
  third.assign(m_list.size(), {});
  std::int64_t max_blocks = 0;
  for (std::size_t j = 0; j < m_list.size(); ++j) {
    second[j].n = std::max<std::int64_t>(0, n_points - 2 * m_list[j]);
    third[j].n = std::max<std::int64_t>(0, n_points - 3 * m_list[j]);
    max_blocks = std::max(max_blocks, (second[j].n + kBlock - 1) / kBlock);
  }
  const std::int64_t n_tiles = (max_blocks + kTileBlocks - 1) / kTileBlocks;
  std::vector<double> value2(static_cast<std::size_t>(nm * max_blocks), 0.0);
  std::vector<double> value3(static_cast<std::size_t>(nm * max_blocks), 0.0);
  [[maybe_unused]] const int nt = resolve_threads(nthreads);  // unused without OpenMP
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
  for (std::int64_t w = 0; w < n_tiles; ++w) {
    const std::int64_t b0 = w * kTileBlocks;
    for (std::int64_t a = 0; a < nm; ++a) {
      const auto j = static_cast<std::size_t>(a);
      const std::int64_t n2 = second[j].n, n3 = third[j].n;
      for (std::int64_t b = b0; b < b0 + kTileBlocks && b * kBlock < n2; ++b) {
        const std::int64_t lo = b * kBlock;
        const auto at = static_cast<std::size_t>(a * max_blocks + b);
        block_sums_second_third(x, m_list[j], lo, std::min(n2, lo + kBlock),
                                std::clamp(n3, lo, lo + kBlock), &value2[at], &value3[at]);
      }
    }
  }
  for (std::int64_t a = 0; a < nm; ++a) {
    const auto j = static_cast<std::size_t>(a);
    for (std::int64_t b = 0; b * kBlock < second[j].n; ++b)
      second[j].sum += value2[static_cast<std::size_t>(a * max_blocks + b)];
    for (std::int64_t b = 0; b * kBlock < third[j].n; ++b)
      third[j].sum += value3[static_cast<std::size_t>(a * max_blocks + b)];
  }
}

}  // namespace allanlot::kernels::detail
