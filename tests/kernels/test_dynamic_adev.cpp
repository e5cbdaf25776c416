// The dynamic Allan deviation (kernels/allan/dynamic.hpp): each window equals OADEV on that
// slice alone bit for bit, the windows' placement, thread-count independence, the option text.
#include "kernels/allan/allan.hpp"
#include "kernels/allan/dynamic.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

namespace allanlot {
namespace {

using kernels::DataType;

std::vector<double> noisy(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double w = 0;
  for (std::size_t i = 0; i < n; ++i) {
    w += 0.01 * g(rng);
    // The noise grows along the record, as in a warm-up.
    y[i] = 2.0 + (1.0 + static_cast<double>(i) / static_cast<double>(n)) * g(rng) + w;
  }
  return y;
}

TEST(DynamicAdev, EachWindowIsOadevOfItsSliceAlone) {
  auto y = noisy(3000, 1);
  y[1500] = std::nan("");  // a gap in some windows
  for (const DataType type : {DataType::Rate, DataType::Phase}) {
    const auto d = kernels::dynamic_oadev(y, type, 100.0, 1024, 300, 2);
    ASSERT_EQ(d.t_center_s.size(), static_cast<std::size_t>((3000 - 1024) / 300 + 1));
    const std::size_t nm = d.m.size();
    ASSERT_GT(nm, 5u);
    for (std::size_t w = 0; w < d.t_center_s.size(); ++w) {
      const std::span<const double> slice(y.data() + w * 300, 1024);
      const auto p = kernels::make_phase(slice, type, 100.0);
      const auto r = kernels::oadev(p, d.m);
      ASSERT_EQ(r.size(), nm);
      for (std::size_t j = 0; j < nm; ++j)
        EXPECT_EQ(d.oadev[w * nm + j], r.dev[j]) << w << " " << j;
      EXPECT_DOUBLE_EQ(d.t_center_s[w], (static_cast<double>(w * 300) + 511.5) / 100.0);
    }
    EXPECT_DOUBLE_EQ(d.tau_s[0], 0.01);
  }
}

TEST(DynamicAdev, ThreadCountIndependent) {
  const auto y = noisy(6000, 2);
  const auto one = kernels::dynamic_oadev(y, DataType::Rate, 1.0, 700, 97, 1);
  for (const int threads : {2, 7}) {
    const auto many = kernels::dynamic_oadev(y, DataType::Rate, 1.0, 700, 97, threads);
    EXPECT_EQ(many.m, one.m);
    EXPECT_EQ(many.t_center_s, one.t_center_s);
    ASSERT_EQ(many.oadev.size(), one.oadev.size());
    for (std::size_t i = 0; i < one.oadev.size(); ++i)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(many.oadev[i]),
                std::bit_cast<std::uint64_t>(one.oadev[i]));
  }
}

TEST(DynamicAdev, WindowOfMissingSamplesIsNaN) {
  auto y = noisy(400, 3);
  for (std::size_t i = 0; i < 100; ++i)
    y[i] = std::nan("");
  const auto d = kernels::dynamic_oadev(y, DataType::Rate, 1.0, 100, 100);
  for (std::size_t j = 0; j < d.m.size(); ++j)
    EXPECT_TRUE(std::isnan(d.oadev[j]));
  EXPECT_FALSE(std::isnan(d.oadev[d.m.size()]));
}

TEST(DynamicAdev, SpecAndPreconditions) {
  auto s = kernels::parse_dynamic_spec("4096");
  EXPECT_EQ(s.window, 4096);
  EXPECT_EQ(s.step, 0);
  EXPECT_FALSE(s.in_seconds);
  s = kernels::parse_dynamic_spec("3600s:600s");
  EXPECT_TRUE(s.in_seconds);
  EXPECT_EQ(s.step, 600);
  EXPECT_THROW(kernels::parse_dynamic_spec("3600s:600"), std::invalid_argument);
  EXPECT_THROW(kernels::parse_dynamic_spec("x"), std::invalid_argument);
  EXPECT_THROW(kernels::parse_dynamic_spec("-5"), std::invalid_argument);
  const std::vector<double> y(100, 1.0);
  EXPECT_THROW(kernels::dynamic_oadev(y, DataType::Rate, 1.0, 200, 1), std::invalid_argument);
  EXPECT_THROW(kernels::dynamic_oadev(y, DataType::Rate, 1.0, 10, 0), std::invalid_argument);
  const std::vector<double> big(10000, 1.0);
  EXPECT_THROW(kernels::dynamic_oadev(big, DataType::Rate, 1.0, 10, 1), std::invalid_argument);
}

}  // namespace
}  // namespace allanlot
