// The Stable32 all-tau grid against every all-tau table of Stable32 1.60 in tests/data/stable32:
// the m column must come out exactly, first to last row.
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "reference/stable32.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot {
namespace {

using kernels::Stat;

// The AF column of any Stable32 table (the TIE rms table has fewer columns than
// read_stable32 expects, so only the first number of each row is read).
std::vector<std::int64_t> table_m(const std::string& file) {
  std::ifstream in(test::reference_path(file));
  if (!in) throw std::runtime_error("cannot open " + test::reference_path(file));
  std::vector<std::int64_t> ms;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::int64_t m = 0;
    if (ss >> m) ms.push_back(m);
  }
  return ms;
}

constexpr std::int64_t kPhaseDatPoints = 1001;  // PHASE.DAT
constexpr std::int64_t kPinkPoints = 10001;     // 10000 frequency points -> 10001 phase points

std::vector<std::int64_t> grid(const char* text, std::int64_t m_max, std::int64_t n_points) {
  return kernels::make_m_list(kernels::parse_tau_grid(text), m_max, n_points);
}

TEST(TauStable32, StepConstantFromN) {
  EXPECT_EQ(kernels::stable32_step_constant(kPhaseDatPoints), 71);
  EXPECT_EQ(kernels::stable32_step_constant(kPinkPoints), 53);
  // An OCXO record of 19982 frequency points: Stable32 1.60 lists 273 OADEV taus, every m up
  // to 53 (AF 50, 51, 52, 53 and then 55), up to its m_max = 19982 / 4.
  constexpr std::int64_t kOcxoPoints = 19983;
  EXPECT_EQ(kernels::stable32_step_constant(kOcxoPoints), 53);
  const auto ms = grid("stable32", kernels::max_m(Stat::Oadev, kOcxoPoints), kOcxoPoints);
  EXPECT_EQ(ms.size(), 273u);
  EXPECT_EQ(ms[52], 53);
  EXPECT_EQ(ms[53], 55);
  // Fewer than 10 frequency points: every m.
  EXPECT_EQ(kernels::stable32_step_constant(9), 1'000'000'000);
}

// PHASE.DAT: every statistic's all-tau run uses K = 71 and stops at the statistic's max_m.
TEST(TauStable32, PhaseDatEveryStatistic) {
  const struct {
    const char* file;
    Stat stat;
  } cases[] = {{"phase_dat_adev.txt", Stat::Adev},    {"phase_dat_oadev.txt", Stat::Oadev},
               {"phase_dat_mdev.txt", Stat::Mdev},    {"phase_dat_tdev.txt", Stat::Tdev},
               {"phase_dat_hdev.txt", Stat::Hdev},    {"phase_dat_ohdev.txt", Stat::Ohdev},
               {"phase_dat_totdev.txt", Stat::Totdev}};
  for (const auto& c : cases) {
    const std::string file = std::string("stable32/phasedat/") + c.file;
    const auto expected = table_m(file);
    ASSERT_GT(expected.size(), 100u) << file;
    EXPECT_EQ(grid("stable32", kernels::max_m(c.stat, kPhaseDatPoints), kPhaseDatPoints), expected)
        << file;
  }
}

// Statistics outside this library's set, on the same grid: their m_max comes from Riley's stop
// ratios (MTOTDEV and TTOTDEV 3, TIE rms 4), which checks the grid's end independently.
TEST(TauStable32, PhaseDatOtherStatisticsShareTheGrid) {
  EXPECT_EQ(grid("stable32", (kPhaseDatPoints - 1) / 3, kPhaseDatPoints),
            table_m("stable32/phasedat/phase_dat_mtotdev.txt"));
  EXPECT_EQ(grid("stable32", (kPhaseDatPoints - 1) / 3, kPhaseDatPoints),
            table_m("stable32/phasedat/phase_dat_ttotdev_all.txt"));
  EXPECT_EQ(grid("stable32", (kPhaseDatPoints - 1) / 4, kPhaseDatPoints),
            table_m("stable32/phasedat/phase_dat_tierms.txt"));
}

// pink_frequency, non-overlapping runs: K = 53 from N, stop at max_m = 1999.
TEST(TauStable32, PinkNonOverlapping) {
  for (const auto& [file, stat] : {std::pair{"adev.txt", Stat::Adev}, {"hdev.txt", Stat::Hdev}}) {
    const auto expected = table_m(std::string("stable32/pink_frequency/") + file);
    ASSERT_EQ(expected.size(), 225u);
    EXPECT_EQ(grid("stable32", kernels::max_m(stat, kPinkPoints), kPinkPoints), expected) << file;
  }
}

// pink_frequency, overlapping and total runs: these five tables step with K = 42, not the 53
// of the same file's ADEV run, and all stop at m = 2369 (tau = 99498 s) although the
// statistics' own limits are 2500 and 5000 and the grid continues with 2426. Both are settings
// of those Stable32 runs rather than functions of N and the statistic: no rule of N alone gives
// 71 (N = 1001) and 53 and 42 (N = 10001), and the common stop is what a maximum tau of 1e5 s
// (m <= 2380 at tau0 = 42 s) produces. So the test gives both, and checks everything else.
TEST(TauStable32, PinkOverlappingWithRunSettings) {
  const std::int64_t run_m_max = 100000 / 42;
  for (const auto& [file, stat] : {std::pair{"oadev.txt", Stat::Oadev},
                                   {"mdev.txt", Stat::Mdev},
                                   {"tdev.txt", Stat::Tdev},
                                   {"ohdev.txt", Stat::Ohdev},
                                   {"totdev_alpha0.txt", Stat::Totdev}}) {
    const auto expected = table_m(std::string("stable32/pink_frequency/") + file);
    ASSERT_EQ(expected.size(), 195u);
    const std::int64_t m_max = std::min(kernels::max_m(stat, kPinkPoints), run_m_max);
    EXPECT_EQ(grid("stable32:42", m_max, kPinkPoints), expected) << file;
  }
}

// MTIE and Thêo1 have averaging-factor lists of their own in Stable32 (stat_m_list): MTIE
// windows of 2^k points (m = 2^k - 1) up to N - 1, Thêo1 twice the K = 71 grid from m' = 5 up to
// 2 m' <= N - 1, and Thêo1's decade run the first m of that list at or above each decade target.
TEST(TauStable32, PhaseDatMtieAndTheo1OwnLists) {
  const auto list = [](const char* text, Stat s) {
    return kernels::stat_m_list(kernels::parse_tau_grid(text), s,
                                kernels::max_m(s, kPhaseDatPoints), kPhaseDatPoints);
  };
  const auto mtie = table_m("stable32/phasedat/phase_dat_mtie.txt");
  ASSERT_EQ(mtie.size(), 9u);
  EXPECT_EQ(list("stable32", Stat::Mtie), mtie);
  const auto theo1 = table_m("stable32/phasedat/phase_dat_theo1_alpha0.txt");
  ASSERT_EQ(theo1.size(), 181u);
  EXPECT_EQ(list("stable32", Stat::Theo1), theo1);
  EXPECT_EQ(table_m("stable32/phasedat/phase_dat_theo1.txt"), theo1);
  const auto decade = table_m("stable32/phasedat/phase_dat_theo1_alpha0_decade.txt");
  ASSERT_EQ(decade.size(), 7u);
  EXPECT_EQ(list("decade", Stat::Theo1), decade);
  // Every other grid and statistic: make_m_list's list unchanged.
  for (const char* text : {"octave", "decade", "all", "log:16", "stable32", "stable32:42", "m:3,9"})
    for (const Stat s : kernels::all_stats()) {
      const bool own = (s == Stat::Theo1 && (std::string(text) == "decade" ||
                                             std::string(text).starts_with("stable32"))) ||
                       (s == Stat::Mtie && std::string(text).starts_with("stable32"));
      if (own) continue;
      const std::int64_t m_max = kernels::max_m(s, kPhaseDatPoints);
      EXPECT_EQ(kernels::stat_m_list(kernels::parse_tau_grid(text), s, m_max, kPhaseDatPoints),
                grid(text, m_max, kPhaseDatPoints))
          << text << " " << kernels::stat_name(s);
    }
  // Small records: MTIE up to m_max, Thêo1 empty when no m' >= 5 fits, nothing for m_max < 1.
  EXPECT_EQ(kernels::stat_m_list(kernels::parse_tau_grid("stable32"), Stat::Mtie, 9, 10),
            (std::vector<std::int64_t>{1, 3, 7}));
  EXPECT_TRUE(
      kernels::stat_m_list(kernels::parse_tau_grid("stable32"), Stat::Theo1, 9, 10).empty());
  EXPECT_TRUE(kernels::stat_m_list(kernels::parse_tau_grid("decade"), Stat::Theo1, 9, 10).empty());
  EXPECT_TRUE(kernels::stat_m_list(kernels::parse_tau_grid("stable32"), Stat::Mtie, 0, 1).empty());
}

TEST(TauStable32, ParsesAndPrints) {
  const auto spec = kernels::parse_tau_grid("stable32");
  EXPECT_EQ(spec.kind, kernels::TauGridKind::Stable32);
  EXPECT_EQ(spec.stable32_k, 0);
  EXPECT_EQ(kernels::to_string(spec), "stable32");
  EXPECT_EQ(kernels::to_string(kernels::parse_tau_grid("stable32:42")), "stable32:42");
  // K depends on N: the two-argument form cannot choose it.
  EXPECT_THROW(kernels::make_m_list(spec, 100), std::invalid_argument);
  EXPECT_EQ(kernels::make_m_list(kernels::parse_tau_grid("stable32:3"), 20),
            (std::vector<std::int64_t>{1, 2, 3, 5, 7, 10, 14, 19}));
  // Few points: every m.
  EXPECT_EQ(grid("stable32", 4, 10), (std::vector<std::int64_t>{1, 2, 3, 4}));
  EXPECT_TRUE(grid("stable32", 0, 10).empty());
  for (const char* bad : {"stable32:", "stable32:0", "stable32:-3", "stable32:x", "stable32x"})
    EXPECT_THROW(kernels::parse_tau_grid(bad), std::invalid_argument) << bad;
  // allantools' "all" keeps every m.
  EXPECT_EQ(kernels::make_m_list(kernels::parse_tau_grid("all"), 100).size(), 100u);
}

}  // namespace
}  // namespace allanlot
