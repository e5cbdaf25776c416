// The statistics' table (kernels/allan/stats.hpp StatInfo): its compile-time checks cover the
// shape of every entry; these pin the facts that results and files depend on (Stable32's stop
// ratios, the default --stats order recorded in results files, Greenhall's differences, the lag-1
// depth, the plot colours), so that an edit of one entry that changes a result is seen.
#include "kernels/allan/stats.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::kernels {
namespace {

TEST(StatTable, EveryStatisticHasItsOwnEntry) {
  ASSERT_EQ(all_stats().size(), kStatCount);
  for (std::size_t i = 0; i < kStatCount; ++i) {
    const Stat s = all_stats()[i];
    EXPECT_EQ(static_cast<std::size_t>(s), i);
    EXPECT_EQ(stat_info(s).id, s);
    EXPECT_EQ(parse_stat(stat_name(s)), s) << stat_name(s);
  }
  EXPECT_FALSE(parse_stat("avar"));
  EXPECT_THROW(stat_info(static_cast<Stat>(kStatCount)), std::invalid_argument);
}

TEST(StatTable, StopRatiosAreStable32s) {
  // stats.hpp max_m: (N-2)/5, (N-1)/4, (N-1)/2, (N-1)/3 and N-1 (tests/data/stable32).
  const std::int64_t n = 1001;
  const auto m = [&](const char* name) { return max_m(*parse_stat(name), n); };
  EXPECT_EQ(m("adev"), 199);
  EXPECT_EQ(m("hdev"), 199);
  for (const char* s : {"oadev", "mdev", "tdev", "ohdev", "tierms", "pdev"})
    EXPECT_EQ(m(s), 250) << s;
  EXPECT_EQ(m("totdev"), 500);
  for (const char* s : {"mtotdev", "ttotdev", "htotdev"})
    EXPECT_EQ(m(s), 333) << s;
  for (const char* s : {"mtie", "theo1", "theoh"})
    EXPECT_EQ(m(s), 1000) << s;
  for (const Stat s : all_stats())
    EXPECT_EQ(max_m(s, 1), 0) << stat_name(s);
}

TEST(StatTable, DefaultStatisticsInTheDocumentedOrder) {
  std::vector<const StatInfo*> chosen;
  for (const Stat s : all_stats())
    if (stat_info(s).default_rank > 0) chosen.push_back(&stat_info(s));
  std::sort(chosen.begin(), chosen.end(),
            [](const auto* a, const auto* b) { return a->default_rank < b->default_rank; });
  std::string names;
  for (const auto* info : chosen)
    names += (names.empty() ? "" : ",") + std::string(info->name);
  EXPECT_EQ(names, "oadev,mdev,hdev,ohdev,tdev,totdev");  // docs/cli.md, the golden digest
}

TEST(StatTable, GreenhallDifferencesAndLag1Depth) {
  const auto kind = [](const char* name) { return difference_kind(*parse_stat(name)); };
  EXPECT_EQ(kind("adev").d, 2);
  EXPECT_FALSE(kind("adev").overlapping);
  EXPECT_TRUE(kind("oadev").overlapping);
  EXPECT_TRUE(kind("mdev").modified);
  EXPECT_TRUE(kind("tdev").modified);
  EXPECT_EQ(kind("hdev").d, 3);
  EXPECT_TRUE(kind("ohdev").overlapping);
  EXPECT_FALSE(kind("ohdev").modified);
  EXPECT_THROW(kind("totdev"), std::invalid_argument);
  for (const Stat s : all_stats()) {
    const std::string name(stat_name(s));
    const bool hadamard = name == "hdev" || name == "ohdev" || name == "htotdev";
    EXPECT_EQ(stat_info(s).noise_id_dmax, hadamard ? 3 : 2) << name;
    EXPECT_EQ(has_interval(s), name != "mtie" && name != "tierms") << name;
  }
}

TEST(StatTable, TimeErrorsAndTheirColour) {
  for (const Stat s : all_stats()) {
    const std::string name(stat_name(s));
    const bool te = name == "tdev" || name == "ttotdev" || name == "mtie" || name == "tierms";
    EXPECT_EQ(is_time_error(s), te) << name;
    if (te) {
      EXPECT_EQ(stat_info(s).color, "#7f7f7f") << name;
    }
  }
  EXPECT_EQ(stat_info(Stat::Oadev).color, "#1f77b4");
}

}  // namespace
}  // namespace allanlot::kernels
