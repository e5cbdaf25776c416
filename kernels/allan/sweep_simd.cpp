// Runtime choice of the vector width for the contiguous Allan-family sums (kernels/allan/simd.hpp).
// The build targets baseline x86-64 so that one binary runs on every machine of a cluster;
// the AVX2 and AVX-512 loops are compiled here under `#pragma GCC target` and chosen once,
// from the CPU, at the first sum. Each level's code lives in its own namespace (no shared
// inline function can be compiled for the wrong level) and rounds exactly like the baseline
// (kernels/allan/detail/sweep_wide.hpp), which the tests check bit for bit.
#include "kernels/allan/simd.hpp"

#include "kernels/allan/allan.hpp"
#include "kernels/allan/detail/sweep.hpp"

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ALLANLOT_WIDE_SIMD 1
#endif

namespace allanlot::kernels {
namespace detail {
namespace {

#ifdef ALLANLOT_WIDE_SIMD

#pragma GCC push_options
#pragma GCC target("avx2")
namespace avx2 {
constexpr int W = 4;
using V = double __attribute__((vector_size(32)));
using U = std::uint64_t __attribute__((vector_size(32)));
// AVX2 has no packed int64 -> double: the baseline's exact two-part conversion (sweep.hpp
// to_double), four lanes wide.
inline V to_double(U v) {
  const U u = v ^ 0x8000000000000000u;
  const U exp52 = U{} + 0x4330000000000000u;  // bit pattern of 2^52
  const V hi = (V)((u >> 32) | exp52) - (4503599627370496.0 + 2147483648.0);
  const V lo = (V)((u & 0xffffffffu) | exp52) - 4503599627370496.0;
  return hi * 4294967296.0 + lo;
}
#include "kernels/allan/detail/sweep_wide.hpp"
}  // namespace avx2
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")
namespace avx512 {
constexpr int W = 8;
using V = double __attribute__((vector_size(64)));
using U = std::uint64_t __attribute__((vector_size(64)));
using I = std::int64_t __attribute__((vector_size(64)));
// vcvtqq2pd rounds to nearest in the default mode, exactly like static_cast<double>(int64).
inline V to_double(U v) {
  return __builtin_convertvector((I)v, V);
}
#include "kernels/allan/detail/sweep_wide.hpp"
}  // namespace avx512
#pragma GCC pop_options

SimdLevel detect() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq"))
    return SimdLevel::Avx512;
  if (__builtin_cpu_supports("avx2")) return SimdLevel::Avx2;
  return SimdLevel::Baseline;
}

#else

SimdLevel detect() {
  return SimdLevel::Baseline;
}

#endif

SimdLevel from_environment(SimdLevel best) {
  const char* env = std::getenv("ALLANLOT_SIMD");
  if (!env) return best;
  const std::string v(env);
  SimdLevel want = best;
  if (v == "baseline") want = SimdLevel::Baseline;
  if (v == "avx2") want = SimdLevel::Avx2;
  if (v == "avx512") want = SimdLevel::Avx512;
  return want < best ? want : best;
}

// The process-wide choice: a CPU property read once, not state of any computation; atomic so
// that the first sums of two threads may race to initialise it harmlessly.
std::atomic<int>& level_store() {
  static std::atomic<int> level{static_cast<int>(from_environment(detect()))};
  return level;
}

SimdLevel active() {
  return static_cast<SimdLevel>(level_store().load(std::memory_order_relaxed));
}

// The wide loops of the active level, or null for the baseline.
struct WideSums {
  double (*second)(const double*, std::int64_t, std::int64_t, std::int64_t);
  double (*third)(const double*, std::int64_t, std::int64_t, std::int64_t);
  double (*modified)(const std::uint64_t*, std::int64_t, double, std::int64_t, std::int64_t);
  void (*second_third)(const double*, std::int64_t, std::int64_t, std::int64_t, std::int64_t,
                       double*, double*);
};

const WideSums* wide() {
#ifdef ALLANLOT_WIDE_SIMD
  static constexpr WideSums kAvx2{avx2::second, avx2::third, avx2::modified, avx2::second_third};
  static constexpr WideSums kAvx512{avx512::second, avx512::third, avx512::modified,
                                    avx512::second_third};
  switch (active()) {
  case SimdLevel::Avx512:
    return &kAvx512;
  case SimdLevel::Avx2:
    return &kAvx2;
  case SimdLevel::Baseline:
    break;
  }
#endif
  return nullptr;
}

}  // namespace

double block_sum(const SecondDifference& f, std::int64_t b, std::int64_t e) {
  const WideSums* w = wide();
  return w ? w->second(f.x, f.m, b, e) : block_sum_baseline(f, b, e);
}

double block_sum(const ThirdDifference& f, std::int64_t b, std::int64_t e) {
  const WideSums* w = wide();
  return w ? w->third(f.x, f.m, b, e) : block_sum_baseline(f, b, e);
}

double block_sum(const ModifiedInnerSum& f, std::int64_t b, std::int64_t e) {
  const WideSums* w = wide();
  return w ? w->modified(f.s, f.m, f.q, b, e) : block_sum_baseline(f, b, e);
}

void block_sums_second_third(const double* x, std::int64_t m, std::int64_t b, std::int64_t e2,
                             std::int64_t e3, double* s2, double* s3) {
  const WideSums* w = wide();
  if (w)
    w->second_third(x, m, b, e2, e3, s2, s3);
  else
    block_sums_second_third_baseline(x, m, b, e2, e3, s2, s3);
}

}  // namespace detail

SimdLevel best_simd_level() {
  return detail::detect();
}

SimdLevel simd_level() {
  return detail::active();
}

SimdLevel set_simd_level(SimdLevel level) {
  const SimdLevel best = best_simd_level();
  const SimdLevel chosen = level < best ? level : best;
  detail::level_store().store(static_cast<int>(chosen), std::memory_order_relaxed);
  return chosen;
}

std::string_view simd_level_name(SimdLevel level) {
  switch (level) {
  case SimdLevel::Avx512:
    return "avx512";
  case SimdLevel::Avx2:
    return "avx2";
  case SimdLevel::Baseline:
    break;
  }
  return "baseline";
}

}  // namespace allanlot::kernels
