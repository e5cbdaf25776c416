// Counter-based random numbers for reproducible parallel noise synthesis.
//
// Philox4x32-10 (Salmon, Moraes, Dror & Shaw, "Parallel random numbers: as easy as 1, 2, 3",
// SC'11) maps a 128-bit counter and a 64-bit key to 128 random bits with no state. Every
// random number of a simulation is therefore a pure function of (seed, stream, component,
// index): any thread may produce any block of samples in any order and the bytes are the same
// for every thread count and every block decomposition.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

namespace allanlot::kernels::rng {

using Counter = std::array<std::uint32_t, 4>;
using Key = std::array<std::uint32_t, 2>;

/// Philox4x32 with 10 rounds, as Random123's philox4x32_10 (multipliers 0xD2511F53 and
/// 0xCD9E8D57, Weyl key increments 0x9E3779B9 and 0xBB67AE85). Checked against Random123's
/// published known-answer vectors in tests/kernels/test_simulate.cpp.
inline Counter philox4x32_10(Counter c, Key k) {
  constexpr std::uint64_t kM0 = 0xD2511F53u;
  constexpr std::uint64_t kM1 = 0xCD9E8D57u;
  constexpr std::uint32_t kW0 = 0x9E3779B9u;
  constexpr std::uint32_t kW1 = 0xBB67AE85u;
  for (int round = 0; round < 10; ++round) {
    const std::uint64_t p0 = kM0 * c[0];
    const std::uint64_t p1 = kM1 * c[2];
    const auto hi0 = static_cast<std::uint32_t>(p0 >> 32);
    const auto lo0 = static_cast<std::uint32_t>(p0);
    const auto hi1 = static_cast<std::uint32_t>(p1 >> 32);
    const auto lo1 = static_cast<std::uint32_t>(p1);
    c = {hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0};
    k[0] += kW0;
    k[1] += kW1;
  }
  return c;
}

/// Who draws the numbers inside one channel's stream. Each component of a simulated channel
/// has its own sequence so that adding or removing one term does not change the others.
/// Values must stay below 256 (they occupy the top byte of the counter's second word).
enum class Component : std::uint32_t {
  White = 1,         // white rate noise (N)
  Flicker = 2,       // Kasdin's driving noise of the flicker term (B)
  RandomWalk = 3,    // rate random walk (K): endpoint increments and bridge integrals
  Quantization = 4,  // white phase noise differenced (Q)
  LotSpread = 5,     // draw_unit's per-unit coefficient factors
  FlickerPm = 6,     // Kasdin's driving noise of the flicker PM phase (ChannelSpec::flicker_pm)
};
/// The effects' streams (each effect's EffectProcess<E>::first_stream, kernels/simulate/
/// effects.hpp checks them) start here, leaving 7 .. 15 to a channel's own components.
inline constexpr std::uint32_t kFirstEffectStream = 16;

/// The random bits for one index of one component's sequence. The counter layout is
/// injective: index (< 2^56) in the first 56 bits, the component in the next 8, the stream
/// in the last 64; the 64-bit seed is the key.
inline Counter bits(std::uint64_t seed, std::uint64_t stream, std::uint32_t component,
                    std::uint64_t index) {
  const Counter c = {static_cast<std::uint32_t>(index),
                     static_cast<std::uint32_t>((index >> 32) & 0xFFFFFFu) | (component << 24),
                     static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32)};
  return philox4x32_10(c,
                       {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)});
}

/// Uniform in (0, 1] with 53 random bits, from two 32-bit words; never 0, so log() is finite.
inline double uniform53(std::uint32_t hi, std::uint32_t lo) {
  const std::uint64_t x = (static_cast<std::uint64_t>(hi) << 32) | lo;
  return static_cast<double>((x >> 11) + 1) * 0x1.0p-53;
}

/// Two independent standard normal deviates for pair `index` of a component's sequence, by
/// the Box-Muller transform (Box & Muller 1958) of two 53-bit uniforms. The tails reach
/// |z| = sqrt(-2 ln 2^-53) = 8.57, beyond anything a 10^10-sample record exercises.
inline std::pair<double, double> normal_pair(std::uint64_t seed, std::uint64_t stream,
                                             std::uint32_t component, std::uint64_t index) {
  const Counter r = bits(seed, stream, component, index);
  const double radius = std::sqrt(-2.0 * std::log(uniform53(r[0], r[1])));
  const double angle = 2.0 * std::numbers::pi * uniform53(r[2], r[3]);
  return {radius * std::cos(angle), radius * std::sin(angle)};
}

/// Standard normal deviate number `index` of a component's sequence: the first (cosine) or
/// second (sine) member of pair index/2.
inline double normal(std::uint64_t seed, std::uint64_t stream, std::uint32_t component,
                     std::uint64_t index) {
  const auto [a, b] = normal_pair(seed, stream, component, index / 2);
  return index % 2 == 0 ? a : b;
}

}  // namespace allanlot::kernels::rng
