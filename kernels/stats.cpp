#include "kernels/stats.hpp"

#include "kernels/allan.hpp"

#include <array>
#include <stdexcept>
#include <string>

namespace allanlot::kernels {
namespace {
constexpr std::array<Stat, 1> kAll = {Stat::Oadev};
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
  }
  return "?";
}

std::optional<Stat> parse_stat(std::string_view name) {
  for (const Stat s : kAll)
    if (stat_name(s) == name) return s;
  return std::nullopt;
}

std::span<const Stat> all_stats() {
  return kAll;
}

std::int64_t max_m(Stat s, std::int64_t n_points) {
  switch (s) {
  case Stat::Oadev:
    return (n_points - 1) / 4;
  default:
    break;
  }
  return 0;
}

StatResult compute(Stat s, const PhaseData& p, std::span<const std::int64_t> m_list, int nthreads) {
  const std::int64_t mmax = max_m(s, p.n_points());
  std::vector<std::int64_t> ms;
  for (const std::int64_t m : m_list)
    if (m >= 1 && m <= mmax) ms.push_back(m);
  switch (s) {
  case Stat::Oadev:
    return oadev(p, ms, nthreads);
  default:
    break;
  }
  throw std::invalid_argument("statistic " + std::string(stat_name(s)) + " is not implemented yet");
}

}  // namespace allanlot::kernels
