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
constexpr std::array kAll = {Stat::Adev,    Stat::Oadev, Stat::Mdev,    Stat::Tdev,
                             Stat::Hdev,    Stat::Ohdev, Stat::Totdev,  Stat::Mtie,
                             Stat::Tierms,  Stat::Theo1, Stat::Mtotdev, Stat::Ttotdev,
                             Stat::Htotdev, Stat::Pdev,  Stat::Theoh};
}

std::string_view stat_name(Stat s) {
  switch (s) {
  case Stat::Adev:
    return "adev";
  case Stat::Oadev:
    return "oadev";
  case Stat::Mdev:
    return "mdev";
  case Stat::Tdev:
    return "tdev";
  case Stat::Hdev:
    return "hdev";
  case Stat::Ohdev:
    return "ohdev";
  case Stat::Totdev:
    return "totdev";
  case Stat::Mtie:
    return "mtie";
  case Stat::Tierms:
    return "tierms";
  case Stat::Theo1:
    return "theo1";
  case Stat::Mtotdev:
    return "mtotdev";
  case Stat::Ttotdev:
    return "ttotdev";
  case Stat::Htotdev:
    return "htotdev";
  case Stat::Pdev:
    return "pdev";
  case Stat::Theoh:
    return "theoh";
  }
  return "?";
}

std::optional<Stat> parse_stat(std::string_view name) {
  for (const Stat s : kAll)
    if (stat_name(s) == name) return s;
  return std::nullopt;
}

bool supports_gaps(Stat s) {
  return s != Stat::Totdev && s != Stat::Theo1 && s != Stat::Mtotdev && s != Stat::Ttotdev &&
         s != Stat::Htotdev && s != Stat::Pdev && s != Stat::Theoh;
}

bool has_interval(Stat s) {
  return s != Stat::Mtie && s != Stat::Tierms;
}

bool is_time_error(Stat s) {
  return s == Stat::Tdev || s == Stat::Ttotdev || s == Stat::Mtie || s == Stat::Tierms;
}

std::span<const Stat> all_stats() {
  return kAll;
}

std::int64_t max_m(Stat s, std::int64_t n_points) {
  // Stable32 1.60's largest averaging factor, read off its tables in tests/data/stable32
  // (PHASE.DAT, N = 1001, and pink_frequency, N = 10001 phase points): the non-overlapping
  // ADEV and HDEV stop at (M-1)/5 for M = N-1 frequency points (199 and 1999: m = 200 is on
  // the all-tau grid but absent), the overlapping and modified statistics at (N-1)/4 (247 and
  // 128 printed, 251 the next grid point) and TOTDEV at (N-1)/2 (499, next 506). These are
  // Riley's stop ratios 5, 4 and 2 ("Evolution of Stable32", Table III).
  if (n_points < 2) return 0;
  switch (s) {
  case Stat::Adev:
  case Stat::Hdev:
    return (n_points - 2) / 5;
  case Stat::Oadev:
  case Stat::Mdev:
  case Stat::Tdev:
  case Stat::Ohdev:
  case Stat::Tierms:
  case Stat::Pdev:
    return (n_points - 1) / 4;
  case Stat::Totdev:
    return (n_points - 1) / 2;
  case Stat::Mtie:
  case Stat::Theo1:
  case Stat::Theoh:
    return n_points - 1;
  case Stat::Mtotdev:
  case Stat::Ttotdev:
  case Stat::Htotdev:
    return (n_points - 1) / 3;
  }
  return 0;
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
    if (s == Stat::Mtie) {
      std::vector<std::int64_t> out;
      for (std::int64_t w = 2; w - 1 <= m_max; w *= 2) {
        out.push_back(w - 1);
        if (w > std::numeric_limits<std::int64_t>::max() / 2) break;
      }
      return out;
    }
    if (s == Stat::Theo1) return theo1_stable32_m_list(spec, m_max, n_points);
  }
  if (m_max >= 1 && spec.kind == TauGridKind::Decade && s == Stat::Theo1) {
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
  switch (s) {
  case Stat::Adev:
    return adev(p, ms, nthreads);
  case Stat::Oadev:
    return oadev(p, ms, nthreads, cache);
  case Stat::Mdev:
    return mdev(p, ms, nthreads);
  case Stat::Tdev:
    return tdev(p, ms, nthreads);
  case Stat::Hdev:
    return hdev(p, ms, nthreads);
  case Stat::Ohdev:
    return ohdev(p, ms, nthreads, cache);
  case Stat::Totdev:
    return totdev(p, ms, nthreads, cache, range == MRange::Estimable);
  case Stat::Mtie:
    return mtie(p, ms, nthreads);
  case Stat::Tierms:
    return tierms(p, ms, nthreads);
  case Stat::Theo1:
    return theo1(p, ms, nthreads, range == MRange::Estimable ? 2 : 10);
  case Stat::Mtotdev:
    return mtotdev(p, ms, nthreads);
  case Stat::Ttotdev:
    return ttotdev(p, ms, nthreads);
  case Stat::Htotdev:
    return htotdev(p, ms, nthreads);
  case Stat::Pdev:
    return pdev(p, ms, nthreads);
  case Stat::Theoh:
    return theoh(p, ms, nthreads);
  }
  throw std::invalid_argument("unknown statistic");
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
