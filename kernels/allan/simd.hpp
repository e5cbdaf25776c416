// Which vector instructions the Allan-family sums run on. The sums are formed in one fixed
// order on every path (kernels/allan/detail/sweep.hpp: sixteen interleaved partial sums per block,
// no fused multiply-add), so the level changes the speed, never a bit of a result; the tests
// run every level this CPU has and compare the bits.
#pragma once

#include <string_view>

namespace allanlot::kernels {

enum class SimdLevel {
  Baseline,  // x86-64 baseline (SSE2, two doubles per register) or any other architecture
  Avx2,      // four doubles per register
  Avx512     // eight doubles per register; packed int64 -> double conversion (AVX-512DQ)
};

/// The best level this CPU and build support (GCC on x86-64 builds the wide paths; other
/// compilers and architectures run the baseline loops).
SimdLevel best_simd_level();

/// The level the sums use: best_simd_level(), or the environment variable ALLANLOT_SIMD
/// (baseline, avx2, avx512) when it names a supported level, or set_simd_level()'s.
SimdLevel simd_level();

/// Chooses the level for the rest of the process (tests and benchmarks compare levels);
/// a level above best_simd_level() is lowered to it. Returns the level now in force. Not to
/// be called while a kernel runs on another thread.
SimdLevel set_simd_level(SimdLevel level);

std::string_view simd_level_name(SimdLevel level);

}  // namespace allanlot::kernels
