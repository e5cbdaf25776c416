// Stable32's run tables (docs/formats.md "Stable32 tables"): the layout Stable32 1.60 prints
// for one statistic of one data file, so that a metrologist can diff allanlot's table against
// Stable32's, and readers of Stable32 tables (AllanTools' test helpers among them) read it.
#pragma once

#include "kernels/allan/stat_result.hpp"

#include <cstdint>
#include <string>

namespace allanlot::io {

/// What Stable32 prints above the table: the data file and its samples.
struct Stable32Head {
  std::string file;   // the data file's name, "PHASE.DAT"
  bool phase = true;  // "Phase Data Points", else "Frequency Data Points"
  std::int64_t n_points = 0;
  double max = 0, min = 0, mean = 0;  // NaN: the three lines are left out (unknown)
  std::string trailer;                // '#' comment lines allanlot adds after the table ("" = none)
  /// MTIE on Stable32's fast list (windows of 2^k points, `--taus stable32`): Stable32's
  /// "MTIE (Fast)" table, "#" the N - m windows. Otherwise its non-fast MTIE table: "#" the N
  /// points analysed, rows up to m = (N - 1) / 2 (docs/formats.md "Stable32 tables").
  bool mtie_fast = false;
};

/// One statistic (named as allanlot names it: "oadev", "mtie", ...) as Stable32 prints it:
/// the head, `# Sigma Type:` with Stable32's name, the confidence factor (not for MTIE and
/// TIE rms), the deadtime, Stable32's column titles for that statistic, and one row per tau
/// with Stable32's widths and 5 significant digits (MTIE as Stable32's fast or non-fast run,
/// Stable32Head::mtie_fast). Bounds not computed print as 0, as in
/// Stable32. Every line that is not a row starts with '#'. The layout is the statistic's
/// (kernels/allan/stats.hpp StatInfo); a name that is not a statistic throws
/// std::invalid_argument.
std::string stable32_table(const Stable32Head& head, const std::string& stat,
                           const kernels::StatResult& s);

}  // namespace allanlot::io
