#include "kernels/allan/stats.hpp"

#include "kernels/allan/allan.hpp"
#include "kernels/allan/gaps.hpp"
#include "kernels/allan/hadamard.hpp"
#include "kernels/allan/parabolic.hpp"
#include "kernels/allan/theo.hpp"
#include "kernels/allan/tie.hpp"
#include "kernels/allan/total.hpp"
#include "kernels/allan/total_family.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {

// The Allan family's statistics in the form compute() runs them (the m list already cut to the
// range); `estimable` is MRange::Estimable.
using Kernel = StatResult (*)(const PhaseData& p, const std::vector<std::int64_t>& ms, int nthreads,
                              SumCache* cache, bool estimable);

struct Entry {
  StatInfo info;
  Kernel compute;
};

// Stable32 1.60's column titles, as its tables in tests/data/stable32 print them (spacing
// included); PDEV, which Stable32 lacks, takes the Allan layout.
constexpr std::string_view kAllanTitle =
    "#  AF        Tau        #    Alpha  Min Sigma      Sigma         Max Sigma";
constexpr std::string_view kHadamardTitle =
    "#  AF        Tau         #    Alpha  Min Sigma   Hadamard Sig     Max Sigma";
constexpr std::string_view kTheoTitle =
    "#  AF   Th\xC3\xAAo1 Tau   Th\xC3\xAAo1 #    Alpha   Min Th\xC3\xAAo1    Th\xC3\xAAo1    Max "
    "Th\xC3\xAAo1";

// Differences of Greenhall & Riley's EDF (2003, sec. 2).
constexpr Differences kNone{};
constexpr Differences kAllan{2, false, false}, kOverlappingAllan{2, true, false};
constexpr Differences kModifiedAllan{2, true, true};
constexpr Differences kHadamard{3, false, false}, kOverlappingHadamard{3, true, false};

// Every statistic, in the order of enum Stat. The stop ratios are Stable32 1.60's largest
// averaging factors (max_m), read off its tables in tests/data/stable32 (PHASE.DAT, N = 1001,
// and pink_frequency, N = 10001 phase points): the non-overlapping ADEV and HDEV stop at (M-1)/5
// for M = N-1 frequency points (199 and 1999: m = 200 is on the all-tau grid but absent), the
// overlapping and modified statistics at (N-1)/4 (247 and 128 printed, 251 the next grid point)
// and TOTDEV at (N-1)/2 (499, next 506): Riley's stop ratios 5, 4 and 2 ("Evolution of
// Stable32", Table III); the others as stats.hpp max_m says. Colours: matplotlib's tab10 order,
// distinct and the same on every plot so that a reader learns them once; the time errors are
// grey. Noise identification's dmax: Stable32 differences the Hadamard family three times.
constexpr std::array<Entry, kStatCount> kTable = {{
    {{Stat::Adev, "adev", "NIST SP1065 eq. (7) (p. 14)", 2, 5, MGrid::Common, true, false, 0,
      EdfModel::Greenhall, kAllan, 2, "Allan", kAllanTitle, Stable32Row::Sigma, "#17becf"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return adev(p, ms, t);
     }},
    {{Stat::Oadev, "oadev", "NIST SP1065 eq. (11) (p. 16)", 1, 4, MGrid::Common, true, false, 1,
      EdfModel::Greenhall, kOverlappingAllan, 2, "Overlapping Allan", kAllanTitle,
      Stable32Row::Sigma, "#1f77b4"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache* c, bool) {
       return oadev(p, ms, t, c);
     }},
    {{Stat::Mdev, "mdev", "NIST SP1065 eq. (14) (p. 17)", 1, 4, MGrid::Common, true, false, 2,
      EdfModel::Greenhall, kModifiedAllan, 2, "Modified Allan",
      "#  AF        Tau         #    Alpha  Min Sigma     Mod Sigma      Max Sigma",
      Stable32Row::Sigma, "#2ca02c"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return mdev(p, ms, t);
     }},
    {{Stat::Tdev, "tdev", "NIST SP1065 eq. (16) (p. 18)", 1, 4, MGrid::Common, true, true, 5,
      EdfModel::Greenhall, kModifiedAllan, 2, "Time",
      "#  AF        Tau         #    Alpha  Min Sigma    Time Sigma      Max Sigma",
      Stable32Row::Sigma, "#7f7f7f"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return tdev(p, ms, t);
     }},
    {{Stat::Hdev, "hdev", "NIST SP1065 eq. (17) (p. 19)", 2, 5, MGrid::Common, true, false, 3,
      EdfModel::Greenhall, kHadamard, 3, "Hadamard", kHadamardTitle, Stable32Row::Sigma, "#9467bd"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return hdev(p, ms, t);
     }},
    {{Stat::Ohdev, "ohdev", "NIST SP1065 eq. (18) (p. 20)", 1, 4, MGrid::Common, true, false, 4,
      EdfModel::Greenhall, kOverlappingHadamard, 3, "Overlapping Hadamard", kHadamardTitle,
      Stable32Row::Sigma, "#d62728"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache* c, bool) {
       return ohdev(p, ms, t, c);
     }},
    {{Stat::Totdev, "totdev", "NIST SP1065 eq. (25) (p. 23)", 1, 2, MGrid::Common, false, false, 6,
      EdfModel::Totvar, kNone, 2, "Total",
      "#  AF        Tau         #    Alpha  Min Sigma    Total Sigma     Max Sigma",
      Stable32Row::Sigma, "#8c564b"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache* c, bool e) {
       return totdev(p, ms, t, c, e);
     }},
    {{Stat::Mtie, "mtie", "NIST SP1065 sec. 5.2.15 (p. 32); ITU-T G.810 eq. (II.4)", 1, 1,
      MGrid::Mtie, true, true, 0, EdfModel::None, kNone, 2, "MTIE",
      "#  AF      Tau           #       MTIE", Stable32Row::TimeError, "#7f7f7f"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return mtie(p, ms, t);
     }},
    {{Stat::Tierms, "tierms", "NIST SP1065 sec. 5.2.16 (p. 33)", 1, 4, MGrid::Common, true, true, 0,
      EdfModel::None, kNone, 2, "TIE rms", "#  AF      Tau           #      TIE rms",
      Stable32Row::TimeError, "#7f7f7f"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return tierms(p, ms, t);
     }},
    {{Stat::Theo1, "theo1", "NIST SP1065 eq. (30) (p. 29)", 1, 1, MGrid::Theo1, false, false, 0,
      EdfModel::Theo1, kNone, 2, "Th\xC3\xAAo1", kTheoTitle, Stable32Row::Theo, "#ff7f0e"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool e) {
       return theo1(p, ms, t, e ? 2 : 10);
     }},
    {{Stat::Mtotdev, "mtotdev", "NIST SP1065 eq. (27) (p. 25)", 1, 3, MGrid::Common, false, false,
      0, EdfModel::Mtotvar, kNone, 2, "Modified Total",
      "# AF          Tau        #     Alpha  Min Sigma     Mod Totdev      Max Sigma",
      Stable32Row::Sigma, "#bcbd22"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return mtotdev(p, ms, t);
     }},
    {{Stat::Ttotdev, "ttotdev", "NIST SP1065 eq. (28) (p. 26)", 1, 3, MGrid::Common, false, true, 0,
      EdfModel::Mtotvar, kNone, 2, "Time Total",
      "#AF          Tau       #      Alpha  Min Sigma    Time Totdev    Max Sigma",
      Stable32Row::Sigma, "#7f7f7f"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return ttotdev(p, ms, t);
     }},
    {{Stat::Htotdev, "htotdev", "NIST SP1065 eq. (29) (p. 27)", 1, 3, MGrid::Common, false, false,
      0, EdfModel::Htotvar, kNone, 3, "Hadamard Total", kHadamardTitle, Stable32Row::Sigma,
      "#e377c2"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return htotdev(p, ms, t);
     }},
    {{Stat::Pdev, "pdev",
      "Vernotte et al., IEEE Trans. UFFC 63 (2016) 611 (parabolic variance); at m = 1 it is NIST "
      "SP1065 eq. (11) (p. 16)",
      1, 4, MGrid::Common, false, false, 0, EdfModel::Pvar, kNone, 2, "Parabolic", kAllanTitle,
      Stable32Row::Sigma, "#98df8a"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return pdev(p, ms, t);
     }},
    {{Stat::Theoh, "theoh", "NIST SP1065 eqs. (31)-(32) (pp. 30-31)", 1, 1, MGrid::Common, false,
      false, 0, EdfModel::Theoh, kNone, 2, "Th\xC3\xAAoH", kTheoTitle, Stable32Row::Theo,
      "#aec7e8"},
     [](const PhaseData& p, const std::vector<std::int64_t>& ms, int t, SumCache*, bool) {
       return theoh(p, ms, t);
     }},
}};

// The table covers every statistic, each at its own index, with what its columns promise.
constexpr bool well_formed() {
  for (std::size_t i = 0; i < kTable.size(); ++i) {
    const StatInfo& s = kTable[i].info;
    if (static_cast<std::size_t>(s.id) != i || s.name.empty() || s.reference.empty() ||
        s.stop_ratio < 1 || s.stop_offset < 1 || s.stable32_sigma_type.empty() ||
        s.stable32_title.empty() || s.color.size() != 7 || s.color[0] != '#' ||
        kTable[i].compute == nullptr)
      return false;
    // Greenhall's EDF needs the differences (d = 2 or 3); no other model has any.
    const bool greenhall = s.edf == EdfModel::Greenhall;
    if (greenhall != (s.differences.d == 2 || s.differences.d == 3)) return false;
    if (!greenhall && s.differences.d != 0) return false;
    if (s.noise_id_dmax != 2 && s.noise_id_dmax != 3) return false;
    // A statistic without an interval prints no Alpha and no bounds in Stable32's table.
    if ((s.edf == EdfModel::None) != (s.stable32_row == Stable32Row::TimeError)) return false;
    for (std::size_t j = 0; j < i; ++j)
      if (kTable[j].info.name == s.name ||
          (s.default_rank > 0 && kTable[j].info.default_rank == s.default_rank))
        return false;
  }
  return true;
}
static_assert(kTable.size() == kStatCount, "one entry per statistic");
static_assert(static_cast<std::size_t>(kTable.back().info.id) + 1 == kStatCount);
static_assert(well_formed(), "every entry at the index of its Stat, complete and consistent");

// Every statistic, in the order results are written and read.
constexpr std::array<Stat, kStatCount> all_in_order() {
  std::array<Stat, kStatCount> out{};
  for (std::size_t i = 0; i < kStatCount; ++i)
    out[i] = kTable[i].info.id;
  return out;
}
constexpr std::array kAll = all_in_order();

}  // namespace

const StatInfo& stat_info(Stat s) {
  const auto i = static_cast<std::size_t>(s);
  if (i >= kTable.size())
    throw std::invalid_argument("stat_info: no statistic " + std::to_string(i));
  return kTable[i].info;
}

std::string_view stat_name(Stat s) {
  return stat_info(s).name;
}

std::optional<Stat> parse_stat(std::string_view name) {
  for (const Entry& e : kTable)
    if (e.info.name == name) return e.info.id;
  return std::nullopt;
}

bool supports_gaps(Stat s) {
  return stat_info(s).supports_gaps;
}

bool has_interval(Stat s) {
  return stat_info(s).edf != EdfModel::None;
}

bool is_time_error(Stat s) {
  return stat_info(s).time_error;
}

std::span<const Stat> all_stats() {
  return kAll;
}

std::int64_t max_m(Stat s, std::int64_t n_points) {
  // The stop ratios of the table (Stable32 1.60's, see there).
  if (n_points < 2) return 0;
  const StatInfo& i = stat_info(s);
  return (n_points - i.stop_offset) / i.stop_ratio;
}

namespace {

// Thêo1's Stable32 all-tau list: twice every m' >= 5 of the Stable32 grid, up to m_max.
std::vector<std::int64_t> theo1_stable32_m_list(const TauGridSpec& spec, std::int64_t m_max,
                                                std::int64_t n_points) {
  TauGridSpec half = spec;
  half.kind = TauGridKind::Stable32;
  std::vector<std::int64_t> out;
  for (const std::int64_t m : make_m_list(half, m_max / 2, n_points))
    if (m >= 5) out.push_back(2 * m);
  return out;
}

}  // namespace

std::vector<std::int64_t> stat_m_list(const TauGridSpec& spec, Stat s, std::int64_t m_max,
                                      std::int64_t n_points) {
  if (m_max >= 1 && spec.kind == TauGridKind::Stable32) {
    if (stat_info(s).m_grid == MGrid::Mtie) {
      std::vector<std::int64_t> out;
      for (std::int64_t w = 2; w - 1 <= m_max; w *= 2) {
        out.push_back(w - 1);
        if (w > std::numeric_limits<std::int64_t>::max() / 2) break;
      }
      return out;
    }
    if (stat_info(s).m_grid == MGrid::Theo1) return theo1_stable32_m_list(spec, m_max, n_points);
  }
  if (m_max >= 1 && spec.kind == TauGridKind::Decade && stat_info(s).m_grid == MGrid::Theo1) {
    TauGridSpec all;
    all.kind = TauGridKind::Stable32;  // K from N
    const auto list = theo1_stable32_m_list(all, m_max, n_points);
    std::vector<std::int64_t> out;
    if (list.empty()) return out;
    for (const std::int64_t target : make_m_list(spec, m_max, n_points)) {
      const auto it = std::lower_bound(list.begin(), list.end(), target);
      const std::int64_t m = it == list.end() ? list.back() : *it;
      if (out.empty() || out.back() != m) out.push_back(m);
    }
    return out;
  }
  return make_m_list(spec, m_max, n_points);
}

std::optional<std::pair<double, std::int64_t>> SumCache::second(std::int64_t m) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (const auto it = second_.find(m); it != second_.end()) return it->second;
  return std::nullopt;
}

void SumCache::store_second(std::int64_t m, double sum, std::int64_t n) {
  const std::lock_guard<std::mutex> lock(mutex_);
  second_.emplace(m, std::make_pair(sum, n));
}

std::optional<std::pair<double, std::int64_t>> SumCache::third(std::int64_t m) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (const auto it = third_.find(m); it != third_.end()) return it->second;
  return std::nullopt;
}

void SumCache::store_third(std::int64_t m, double sum, std::int64_t n) {
  const std::lock_guard<std::mutex> lock(mutex_);
  third_.emplace(m, std::make_pair(sum, n));
}

namespace {

StatResult dispatch(Stat s, const PhaseData& p, const std::vector<std::int64_t>& ms, int nthreads,
                    SumCache* cache, MRange range) {
  return kTable[static_cast<std::size_t>(stat_info(s).id)].compute(p, ms, nthreads, cache,
                                                                   range == MRange::Estimable);
}

}  // namespace

StatResult compute(Stat s, const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads,
                   SumCache* cache, MRange range) {
  for (const std::int64_t m : m_list)
    if (m < 1)
      throw std::invalid_argument(std::string(stat_name(s)) + ": m must be >= 1, got " +
                                  std::to_string(m));
  const std::int64_t mmax = range == MRange::Stable32 ? max_m(s, p.n_points()) : p.n_points() - 1;
  std::vector<std::int64_t> ms;
  for (const std::int64_t m : m_list)
    if (m <= mmax) ms.push_back(m);
  if (p.skip_gaps.empty() || !supports_gaps(s)) return dispatch(s, p, ms, nthreads, cache, range);
  // Filled samples (gaps.hpp): each row from the filled record or, where that costs little,
  // with the terms touching them left out. The cache holds the filled record's sums only.
  const StatResult filled = dispatch(s, p, ms, nthreads, cache, range);
  const StatResult skipped = skipped_rows(
      skip_view(p), ms, filled, [&](const PhaseData& view, const std::vector<std::int64_t>& part) {
        return dispatch(s, view, part, nthreads, nullptr, range);
      });
  return merge_filled_skipped(filled, skipped);
}

}  // namespace allanlot::kernels
