// Data editing (kernels/edit/edit.hpp): an outlier planted at 90 robust sigmas is found and
// listed, a clean record has none, a phase record's bad first point is found, excluded ranges
// map to their samples.
#include "kernels/edit/edit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

using kernels::DataType;
using kernels::Edit;

std::vector<double> white(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  for (double& v : y)
    v = 1e-11 * g(rng);
  return y;
}

TEST(Edit, OutlierAtNinetySigmaIsFoundAndListed) {
  auto y = white(4096, 3);
  y[1234] = 90e-11;
  const auto e = kernels::find_outliers(y, DataType::Rate, kernels::kDefaultOutlierSigmas);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].kind, Edit::Kind::Outlier);
  EXPECT_EQ(e[0].first, 1234);
  EXPECT_EQ(e[0].last, 1234);
  EXPECT_EQ(e[0].value, 90e-11);
  // The robust sigma of 4096 Gaussian values is within a few per cent of the true one.
  EXPECT_NEAR(e[0].sigmas, 90.0, 5.0);
  kernels::apply_edits(y, e);
  EXPECT_TRUE(std::isnan(y[1234]));
}

TEST(Edit, CleanRecordHasNoEdit) {
  // At 5 sigmas a Gaussian sample is flagged with probability 5.7e-7: 0.002 expected in 4096.
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const auto y = white(4096, seed);
    EXPECT_TRUE(kernels::find_outliers(y, DataType::Rate, 5.0).empty()) << seed;
    std::vector<double> x(y.size());
    double acc = 0;
    for (std::size_t i = 0; i < y.size(); ++i)
      x[i] = acc += y[i];
    EXPECT_TRUE(kernels::find_outliers(x, DataType::Phase, 5.0).empty()) << seed;
  }
}

TEST(Edit, PhaseRecordsFirstPointOffIsTheOutlier) {
  // A clock's first phase point 20 ns off: its one frequency value is far out, and the point
  // (not the record after it) is what is removed.
  const auto y = white(2048, 5);
  std::vector<double> x(y.size());
  double acc = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    x[i] = acc += y[i];
  x[0] += 20e-9;
  x[700] += 20e-9;  // an interior point off moves both of its differences
  const auto e = kernels::find_outliers(x, DataType::Phase, 5.0);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].first, 0);
  EXPECT_EQ(e[1].first, 700);
  EXPECT_GT(e[0].sigmas, 90.0);
}

TEST(Edit, PhaseStepIsNoOutlier) {
  const auto y = white(2048, 6);
  std::vector<double> x(y.size());
  double acc = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    x[i] = acc += y[i] + (i == 1000 ? 1e-8 : 0.0);
  EXPECT_TRUE(kernels::find_outliers(x, DataType::Phase, 5.0).empty());
}

TEST(Edit, ExclusionMapsSecondsToSamples) {
  const kernels::TimeRange r[] = {{1.0, 2.0}, {50.0, 60.0}, {-5.0, 0.05}};
  const auto e = kernels::exclusion_edits(40, 10.0, r);
  ASSERT_EQ(e.size(), 2u);  // 50..60 s lies past the record's 3.9 s
  EXPECT_EQ(e[0].kind, Edit::Kind::Excluded);
  EXPECT_EQ(e[0].first, 10);
  EXPECT_EQ(e[0].last, 20);
  EXPECT_TRUE(std::isnan(e[0].value));
  EXPECT_EQ(e[1].first, 0);
  EXPECT_EQ(e[1].last, 0);
  const kernels::TimeRange bad[] = {{3.0, 1.0}};
  EXPECT_THROW(kernels::exclusion_edits(40, 10.0, bad), std::invalid_argument);
  const std::vector<double> y(10, 1.0);
  EXPECT_THROW(kernels::find_outliers(y, DataType::Rate, 0.0), std::invalid_argument);
}

TEST(Edit, QuantizedConstantDataFlagsNothing) {
  std::vector<double> y(1000, 3.0);
  y[10] = 4.0;  // MAD = 0: no scale to judge by
  EXPECT_TRUE(kernels::find_outliers(y, DataType::Rate, 5.0).empty());
}

}  // namespace
}  // namespace allanlot
