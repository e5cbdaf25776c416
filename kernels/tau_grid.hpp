// Averaging-factor (m) grids: which taus a statistic is evaluated at.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// Grid kinds, with allantools' and Stable32's names.
enum class TauGridKind {
  Octave,   // m = 1, 2, 4, 8, ... (Stable32 "Octave")
  Decade,   // m = 1, 2, 4, 10, 20, 40, 100, ... (Stable32 "Decade")
  All,      // every integer m from 1 to m_max
  Log,      // K log-spaced m per decade, rounded to integers, duplicates removed
  Explicit  // a caller-given list of m
};

struct TauGridSpec {
  TauGridKind kind = TauGridKind::Log;  // default: dense log spacing
  int per_decade = 16;                  // Log: points per decade (about 100 taus on 5.4 M samples)
  std::vector<std::int64_t> m;          // Explicit: the averaging factors, in any order
};

/// Parses "octave", "decade", "all", "log:K" (1 <= K <= 1000) or "m:1,2,5" (explicit list).
/// Throws std::invalid_argument naming the offending text.
TauGridSpec parse_tau_grid(std::string_view text);

/// The grid's averaging factors in increasing order, all in [1, m_max]. Explicit lists are
/// sorted, de-duplicated and clipped to [1, m_max]. Empty when m_max < 1.
std::vector<std::int64_t> make_m_list(const TauGridSpec& spec, std::int64_t m_max);

/// The text form accepted by parse_tau_grid, for attributes and logs.
std::string to_string(const TauGridSpec& spec);

}  // namespace allanlot::kernels
