// The Allan-family statistics by name: one entry point that the command line and the batch
// driver call, and the per-statistic rules (valid m range) in one place.
#pragma once

#include "kernels/allan/phase.hpp"
#include "kernels/allan/stat_result.hpp"
#include "kernels/allan/sum_cache.hpp"
#include "kernels/allan/tau_grid.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace allanlot::kernels {

/// Statistics, named as in allantools and Stable32.
enum class Stat {
  Adev,     // Allan deviation (non-overlapping), SP1065 eq. (7)
  Oadev,    // overlapping Allan deviation, SP1065 eq. (11)
  Mdev,     // modified Allan deviation, SP1065 eq. (14)
  Tdev,     // time deviation, SP1065 eq. (16)
  Hdev,     // Hadamard deviation, SP1065 eq. (17)
  Ohdev,    // overlapping Hadamard deviation, SP1065 eq. (18)
  Totdev,   // total deviation (doubly reflected TOTVAR), SP1065 eq. (25)
  Mtie,     // maximum time interval error, SP1065 sec. 5.2.15 (a time error, phase units)
  Tierms,   // TIE rms, SP1065 sec. 5.2.16 (a time error, phase units)
  Theo1,    // Thêo1, SP1065 eq. (30) (raw; tau = 0.75 m tau0, m even)
  Mtotdev,  // modified total deviation, SP1065 eq. (27)
  Ttotdev,  // time total deviation, SP1065 eq. (28) (a time error, phase units)
  Htotdev,  // Hadamard total deviation, SP1065 eq. (29), Stable32's bias correction
  Pdev,     // parabolic deviation, Vernotte et al. 2016 / 2020
  Theoh     // ThêoH: OADEV below 10 % of the record, bias-removed Thêo1 above, SP1065 eq. (32)
};

/// The number of statistics: one entry of the table of stats.cpp each (its static_asserts).
inline constexpr std::size_t kStatCount = static_cast<std::size_t>(Stat::Theoh) + 1;

/// Which equivalent degrees of freedom a statistic's confidence interval takes
/// (kernels/uncertainty/confidence.hpp stat_edf).
enum class EdfModel {
  None,       // no chi-square model (MTIE, TIE rms): edf, dev_lo and dev_hi are NaN
  Greenhall,  // Greenhall & Riley's finite differences (StatInfo::differences)
  Totvar,     // Howe's b (T/tau) - c (edf_totvar)
  Mtotvar,    // the MDEV edf below m = 10, SP1065 Table 8 (edf_mtotvar) from m = 10
  Htotvar,    // Howe's fit (edf_htotvar) for FM noise at m >= 16, else the OHDEV edf
  Theo1,      // Howe & Tasset's fits (edf_theo1)
  Theoh,      // the OADEV edf on its OADEV rows, Thêo1's above
  Pvar        // Vernotte et al.'s fit (edf_pvar), the OADEV edf at m = 1
};

/// The finite differences a statistic is built of (Greenhall & Riley 2003, sec. 2): d = 2 (Allan)
/// or 3 (Hadamard), overlapping or not, modified (phase averaged over m points first) or not.
/// d = 0: not a finite-difference variance (its EdfModel is not Greenhall).
struct Differences {
  int d = 0;
  bool overlapping = false;
  bool modified = false;
};

/// Which averaging factors `--taus stable32` and `decade` give a statistic (stat_m_list).
enum class MGrid {
  Common,  // make_m_list's, as for every statistic
  Mtie,    // windows of 2^k points on the Stable32 grid
  Theo1    // twice the Stable32 grid's m >= 5 (and the decade grid taken from it)
};

/// How Stable32 1.60 prints a statistic's rows (io/stable32_table.hpp).
enum class Stable32Row {
  Sigma,     // AF, Tau, #, Alpha, Min Sigma, Sigma, Max Sigma
  Theo,      // the same, "#" a weighted count printed as a number
  TimeError  // AF, Tau, # and the value: no alpha, no bounds, no confidence factor
};

/// Every fact of one statistic, in one place: the table of stats.cpp holds one entry per Stat,
/// in the order of the enum, checked at compile time to cover every statistic. A new statistic
/// is a new entry there (docs/development.md "How to add a statistic").
struct StatInfo {
  Stat id;
  std::string_view name;       // allantools' and Stable32's name: --stats, the results group
                               // allan/<name>/, the Python function allanlot.<name>
  std::string_view reference;  // where it is defined (the Python docstrings)
  std::int64_t stop_offset;    // max_m = (N - stop_offset) / stop_ratio
  std::int64_t stop_ratio;
  MGrid m_grid;
  bool supports_gaps;  // false: refuses gapped data (see supports_gaps)
  bool time_error;     // a time (phase) error in phase units rather than a deviation of the rate
  int default_rank;    // its place in analyze's default --stats (docs/cli.md), 0 = not there
  EdfModel edf;
  Differences differences;  // for EdfModel::Greenhall
  int noise_id_dmax;        // differencing depth of the lag-1 noise identification
                            // (kernels/uncertainty/noise_id.hpp): 3 Hadamard family, else 2
  std::string_view stable32_sigma_type;  // Stable32's "# Sigma Type:"
  std::string_view stable32_title;       // Stable32's column titles, spacing included
  Stable32Row stable32_row;
  std::string_view color;  // its colour on every plot of the report
};

/// The entry of statistic s.
const StatInfo& stat_info(Stat s);

/// "oadev" etc.
std::string_view stat_name(Stat s);
/// Inverse of stat_name; nullopt for an unknown name.
std::optional<Stat> parse_stat(std::string_view name);
/// False for the statistics that refuse gapped data (totdev: its reflections have no meaning
/// across a gap, see kernels/allan/total.hpp; theo1, see kernels/allan/theo.hpp); the others
/// leave out the terms that touch a gap.
bool supports_gaps(Stat s);
/// True for the statistics with a confidence interval (kernels::add_confidence, with the edf of
/// kernels/uncertainty/confidence.hpp stat_edf); false for MTIE and TIE rms, whose
/// distribution has no chi-square model: their edf, dev_lo and dev_hi are NaN.
bool has_interval(Stat s);
/// True for the statistics that are a time (phase) error, in phase units (u*s for rate input),
/// rather than a deviation of the rate: tdev, ttotdev, mtie, tierms.
bool is_time_error(Stat s);
/// Every statistic this build computes, in the order results are written.
std::span<const Stat> all_stats();

/// Largest averaging factor Stable32 1.60 evaluates for `n_points` phase points N (its
/// tables in tests/data/stable32): (N-2)/5 for ADEV and HDEV, (N-1)/4 for OADEV, MDEV, TDEV and
/// OHDEV, (N-1)/2 for TOTDEV (Riley's stop ratios 5, 4, 2), so that every estimate keeps a
/// reasonable number of terms. For the further statistics: (N-1)/4 for TIE rms (its
/// Stable32 table stops at 247 for N = 1001) and PDEV (as OADEV), (N-1)/3 for MTOT, TTOT and
/// HTOT (3m points per window; Stable32 1.53's all-tau MTOT stops at 332 for N = 1001), N-1
/// for MTIE (one window of the whole record), Thêo1 and ThêoH (SP1065 eq. (30): m <= N-1; its
/// Stable32 table stops at 998). 0 when N < 2.
std::int64_t max_m(Stat s, std::int64_t n_points);

/// The averaging factors of `spec` for statistic `s`, in increasing order, all in [1, m_max]
/// (m_max: normally max_m(s, n_points)). As make_m_list(spec, m_max, n_points) except where
/// Stable32 1.60 gives a statistic an averaging-factor list of its own (tables in
/// tests/data/stable32/phasedat):
///  - Stable32 grid, MTIE: m = 2^k - 1, k >= 1 (windows of 2^k points), up to m_max
///    (PHASE.DAT: 1, 3, 7, ..., 511);
///  - Stable32 grid, Thêo1: 2 m' for every m' >= 5 of the Stable32 grid (same K) with
///    2 m' <= m_max (PHASE.DAT, K = 71: 10..142 step 2, 146..286 step 4, ..., 872..998 step 14);
///  - Decade grid, Thêo1: for each target of the decade grid, the smallest m of Thêo1's
///    Stable32 list that is >= it, or that list's last m, duplicates removed (PHASE.DAT: 10, 20,
///    40, 100, 202, 400, 998).
/// Throws std::invalid_argument as make_m_list does.
std::vector<std::int64_t> stat_m_list(const TauGridSpec& spec, Stat s, std::int64_t m_max,
                                      std::int64_t n_points);

/// Which averaging factors compute() evaluates.
enum class MRange {
  Stable32,  // m <= max_m(s, N): Stable32's stop ratios, the command line's range
  Estimable  // every m whose estimator has at least one term (AllanTools' range, the Python API)
};

/// Computes statistic `s` at every m of `m_list` with m <= max_m(s, N) (with MRange::Estimable:
/// m <= N - 1, and each statistic leaves out the m its estimator has no term for); larger m
/// give no row.
/// Throws std::invalid_argument for any m < 1, for gapped data with a statistic that refuses
/// gaps (supports_gaps), and for the preconditions of the statistic's own function (allan.hpp,
/// hadamard.hpp, total.hpp, tie.hpp, theo.hpp, total_family.hpp, parabolic.hpp).
/// Parallel over m with `nthreads` (0 = OpenMP default); results are bit-identical for any
/// thread count because each tau's sum is formed by one thread in a fixed order. With a
/// cache, OADEV and TOTDEV share their second-difference sums (same bits as without).
/// On a record with filled samples (p.skip_gaps not empty, gaps.hpp) a statistic that supports
/// gaps is computed on p and, at the m where its row may be taken (skipped_rows), on
/// skip_view(p), and each row taken from one of the two by merge_filled_skipped; the statistics
/// that refuse gaps run on the filled record alone.
StatResult compute(Stat s, const PhaseData& p, std::span<const std::int64_t> m_list,
                   int nthreads = 0, SumCache* cache = nullptr, MRange range = MRange::Stable32);

}  // namespace allanlot::kernels
