// The statistics `analyze --stats` takes (src/cli/stat_list.hpp): a list in the order given,
// each statistic once, "all" for every one, an unknown name or an empty list a usage error
// naming --stats; and the default list of docs/cli.md from the statistics' table.
#include "src/cli/stat_list.hpp"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace allanlot::cli {
namespace {

kernels::Stat stat(const std::string& name) {
  const auto s = kernels::parse_stat(name);
  EXPECT_TRUE(s.has_value()) << name;
  return *s;
}

std::string usage_error(const std::string& list) {
  try {
    (void)parse_stats(list);
  } catch (const CLI::ValidationError& e) {
    return e.what();
  }
  return "";
}

TEST(StatList, KeepsTheOrderGivenAndEachStatisticOnce) {
  const std::vector<kernels::Stat> want = {stat("mdev"), stat("oadev"), stat("totdev")};
  EXPECT_EQ(parse_stats("mdev,oadev,totdev"), want);
  EXPECT_EQ(parse_stats("mdev,oadev,mdev,totdev,oadev"), want);
}

TEST(StatList, AllIsEveryStatisticAfterThoseNamedBeforeIt) {
  const auto every = kernels::all_stats();
  const std::vector<kernels::Stat> all = parse_stats("all");
  EXPECT_EQ(all, std::vector<kernels::Stat>(every.begin(), every.end()));
  const std::vector<kernels::Stat> first = parse_stats("totdev,all");
  ASSERT_EQ(first.size(), every.size());
  EXPECT_EQ(first.front(), stat("totdev"));
  EXPECT_EQ(std::count(first.begin(), first.end(), stat("totdev")), 1);
}

TEST(StatList, AnUnknownNameOrAnEmptyListIsAUsageErrorNamingTheOption) {
  const std::string unknown = usage_error("oadev,adevv");
  EXPECT_NE(unknown.find("--stats"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown statistic 'adevv'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("oadev"), std::string::npos) << unknown;  // the known names listed
  const std::string empty = usage_error("");
  EXPECT_NE(empty.find("empty list"), std::string::npos) << empty;
  EXPECT_NE(usage_error(",").find("unknown statistic ''"), std::string::npos);
}

TEST(StatList, TheDefaultListIsTheTablesRankedStatisticsInRankOrder) {
  const std::string defaults = default_stats();
  const std::vector<kernels::Stat> parsed = parse_stats(defaults);
  int ranked = 0;
  for (const kernels::Stat s : kernels::all_stats())
    ranked += kernels::stat_info(s).default_rank > 0 ? 1 : 0;
  ASSERT_EQ(static_cast<int>(parsed.size()), ranked) << defaults;
  for (std::size_t i = 1; i < parsed.size(); ++i)
    EXPECT_LT(kernels::stat_info(parsed[i - 1]).default_rank,
              kernels::stat_info(parsed[i]).default_rank)
        << defaults;
  std::stringstream ss(defaults);
  std::string name;
  for (std::size_t i = 0; std::getline(ss, name, ','); ++i)
    EXPECT_EQ(name, kernels::stat_name(parsed.at(i)));
}

}  // namespace
}  // namespace allanlot::cli
