// The time column of a text recording (io/time_axis.hpp, docs/formats.md "Text recordings"):
// a step of k median steps is k - 1 missing samples, the sample step is the least-squares slope
// of the stamps over their sample numbers, repeated and out-of-order stamps are counted and make
// no gap, and a stamp far off the others is refused by the row it is on.
#include "io/time_axis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {
namespace {

// Stamps k * step for k in [0, n) except `dropped`.
std::vector<double> stamps(std::size_t n, double step, const std::vector<std::size_t>& dropped) {
  std::vector<double> t;
  for (std::size_t k = 0; k < n; ++k)
    if (std::find(dropped.begin(), dropped.end(), k) == dropped.end())
      t.push_back(static_cast<double>(k) * step);
  return t;
}

TEST(TimeAxis, RegularStampsHaveTheirStepAndNoGap) {
  const TimeAxis a = make_time_axis(stamps(1000, 0.01, {}), 0);
  EXPECT_NEAR(a.step, 0.01, 1e-15);
  EXPECT_TRUE(a.gaps.empty());
  EXPECT_EQ(a.missing, 0);
  EXPECT_LT(a.jitter_rms, 1e-15);
  EXPECT_EQ(a.n_duplicate, 0);
  EXPECT_EQ(a.first_duplicate, -1);
  EXPECT_EQ(a.n_decreasing, 0);
  EXPECT_EQ(a.first_decreasing, -1);
}

TEST(TimeAxis, DroppedRowsAreGapsAndWithGapsPutsNanThere) {
  // Samples 3 and 4 and sample 8 left out: 2 missing before row 3, 1 before row 6.
  const std::vector<double> t = stamps(10, 0.5, {3, 4, 8});
  const TimeAxis a = make_time_axis(t, 3);
  const std::vector<std::pair<std::size_t, std::int64_t>> gaps = {{3, 2}, {6, 1}};
  EXPECT_EQ(a.gaps, gaps);
  EXPECT_EQ(a.missing, 3);
  EXPECT_NEAR(a.step, 0.5, 1e-15);  // every kept stamp on its sample's line

  const std::vector<double> x = with_gaps({0, 1, 2, 5, 6, 7, 9}, a);
  ASSERT_EQ(x.size(), 10u);
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (k == 3 || k == 4 || k == 8)
      EXPECT_TRUE(std::isnan(x[k])) << k;
    else
      EXPECT_EQ(x[k], static_cast<double>(k));
  }
}

TEST(TimeAxis, RepeatedAndOutOfOrderStampsAreCountedAndMakeNoGap) {
  // Row 3 repeats row 2's stamp; row 6 is set back. Each is kept as the next sample and the
  // step after it spans it, so no sample is missing.
  const TimeAxis a = make_time_axis({0, 1, 2, 2, 3, 4, 3.5, 5, 6}, 0);
  EXPECT_TRUE(a.gaps.empty());
  EXPECT_EQ(a.missing, 0);
  EXPECT_EQ(a.n_duplicate, 1);
  EXPECT_EQ(a.first_duplicate, 3);
  EXPECT_EQ(a.n_decreasing, 1);
  EXPECT_EQ(a.first_decreasing, 6);
}

TEST(TimeAxis, JitterIsTheScatterOfTheStepsAboutTheStep) {
  // Stamps k + e (-1)^k: steps 1 -+ 2e alternately, so the rms of step - 1 is 2e; the fitted
  // step is 1 but for an end effect of order e / n.
  const double e = 1e-4;
  std::vector<double> t(1001);
  for (std::size_t k = 0; k < t.size(); ++k)
    t[k] = static_cast<double>(k) + (k % 2 ? -e : e);
  const TimeAxis a = make_time_axis(t, 0);
  EXPECT_NEAR(a.step, 1.0, 1e-6);
  EXPECT_NEAR(a.jitter_rms, 2 * e, 1e-3 * e);
  EXPECT_TRUE(a.gaps.empty());
}

TEST(TimeAxis, AStampFarOffAndStampsThatNeverAdvanceAreRefused) {
  try {
    make_time_axis({0, 1, 2, 1000}, 3);
    FAIL() << "a step of 998 samples was taken with 3 allowed";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("before row 4"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_time_axis({5, 5, 4}, 10), std::invalid_argument);
  // Fewer than two stamps: no axis to make, and nothing refused.
  EXPECT_EQ(make_time_axis({7}, 0).step, 0.0);
}

TEST(TimeAxis, FactsAreInSecondsAndReadBackExactly) {
  TimeAxis a;
  a.step = 0.1;
  a.missing = 4;
  a.jitter_rms = 1.0 / 3.0;
  std::vector<std::pair<std::string, std::string>> facts;
  add_time_axis_facts(facts, a, 1.0);
  ASSERT_EQ(facts.size(), 3u);
  EXPECT_EQ(facts[0].first, "time_step_s");
  EXPECT_EQ(std::stod(facts[0].second), 0.1);
  EXPECT_EQ(facts[1], (std::pair<std::string, std::string>{"time_missing_samples", "4"}));
  EXPECT_EQ(facts[2].first, "time_jitter_rms_s");
  EXPECT_EQ(std::stod(facts[2].second), 1.0 / 3.0);  // 17 digits: the same double
  facts.clear();
  add_time_axis_facts(facts, a, 1e-3);  // a column in milliseconds
  EXPECT_EQ(std::stod(facts[0].second), 0.1 * 1e-3);
}

}  // namespace
}  // namespace allanlot::io
