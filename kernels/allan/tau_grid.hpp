// Averaging-factor (m) grids: which taus a statistic is evaluated at.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// Grid kinds, with allantools' and Stable32's names.
enum class TauGridKind {
  Octave,    // m = 1, 2, 4, 8, ... (Stable32 "Octave")
  Decade,    // m = 1, 2, 4, 10, 20, 40, 100, ... (Stable32 "Decade")
  All,       // every integer m from 1 to m_max (allantools' "all")
  Stable32,  // Stable32's "all tau" run: every m up to K, then ever wider steps (see below)
  Log,       // K log-spaced m per decade, rounded to integers, duplicates removed
  Explicit   // a caller-given list of m
};

struct TauGridSpec {
  TauGridKind kind = TauGridKind::Log;  // default: dense log spacing
  int per_decade = 16;                  // Log: points per decade (about 100 taus on 5.4 M samples)
  std::vector<std::int64_t> m;          // Explicit: the averaging factors, in any order
  std::int64_t stable32_k = 0;          // Stable32: step constant K; 0 = Stable32's own, from N
};

/// Stable32's "all tau" step constant K for N phase points: floor(215 / floor(log10(N - 1))),
/// at least 1 (every m when N - 1 < 10). Inferred, not documented by Stable32, from three runs
/// of Stable32 1.60: PHASE.DAT (N - 1 = 1000 frequency points) gives K = 71, the
/// pink_frequency ADEV/HDEV runs (10000) give 53, and an OCXO record of 19982 frequency points
/// gives 273 OADEV taus, i.e. K = 53 as well (every m up to 53). The earlier fit
/// floor(215 / log10(N - 1)) gave 49 there (256 taus, diverging at m = 50): K changes with the
/// whole number of decades of N, not with log10(N). Stable32's overlapping runs on
/// pink_frequency use K = 42 instead, a choice no rule of N alone reproduces together with the
/// others (see tests/kernels/test_tau_grid_stable32.cpp); select it with "stable32:42".
std::int64_t stable32_step_constant(std::int64_t n_points);

/// Parses "octave", "decade", "all", "stable32", "stable32:K" (1 <= K <= 10^9), "log:K"
/// (1 <= K <= 1000) or "m:1,2,5" (explicit list).
/// Throws std::invalid_argument naming the offending text.
TauGridSpec parse_tau_grid(std::string_view text);

/// The grid's averaging factors in increasing order, all in [1, m_max]. Explicit lists are
/// sorted, de-duplicated and clipped to [1, m_max]. Empty when m_max < 1.
///
/// Stable32 grid, read off every all-tau table of Stable32 1.60 in tests/data/stable32: it
/// starts at m = 1 and steps by floor(m / K) + 1, i.e. every m up to K, then steps of 2 up to
/// 2K, of 3 up to 3K, ... (PHASE.DAT, K = 71: 1..71, 73..143 step 2, 146..215 step 3, ...), a
/// spacing that tends to K points per factor e of tau; the run ends at the statistic's
/// m_max. With stable32_k = 0 this overload throws std::invalid_argument, because K depends
/// on N: use the overload below.
std::vector<std::int64_t> make_m_list(const TauGridSpec& spec, std::int64_t m_max);

/// As above; `n_points` (the N of the phase data) chooses K for a Stable32 grid with
/// stable32_k = 0 (stable32_step_constant) and is ignored by every other kind.
std::vector<std::int64_t> make_m_list(const TauGridSpec& spec, std::int64_t m_max,
                                      std::int64_t n_points);

/// The text form accepted by parse_tau_grid, for attributes and logs.
std::string to_string(const TauGridSpec& spec);

}  // namespace allanlot::kernels
