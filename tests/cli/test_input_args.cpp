// The input options' check (src/workflow/input_args.hpp), which the command line and the Python
// module share: a bad option is a usage error naming the option, with the text the command line
// has always printed ("--units: ..."), and a good one reaches io::InputOptions unchanged.
#include "src/workflow/diagnose.hpp"
#include "src/workflow/input_args.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace allanlot::workflow {
namespace {

TEST(InputArgs, ABadOptionIsAUsageErrorNamingIt) {
  InputArgs a;
  a.units = {"furlong"};
  try {
    (void)checked_input_options(a);
    FAIL() << "no error for an unknown unit";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.option, "--units");
    EXPECT_EQ(std::string(e.what()).rfind("--units: 'furlong'", 0), 0u) << e.what();
  }
  InputArgs r;
  r.sample_rate_hz = 1e13;
  EXPECT_THROW((void)checked_input_options(r), UsageError);
  InputArgs hz;
  hz.units = {"Hz"};  // a frequency needs --nominal-frequency
  EXPECT_THROW((void)checked_input_options(hz), OptionError);
}

TEST(InputArgs, GoodOptionsReachTheReaders) {
  InputArgs a;
  a.data_type = "phase";
  a.tau0_s = 0.01;
  a.units = {"gyro*=deg/s, m/s^2"};
  const io::InputOptions o = checked_input_options(a);
  ASSERT_TRUE(o.data_type.has_value());
  EXPECT_EQ(*o.data_type, kernels::DataType::Phase);
  EXPECT_DOUBLE_EQ(o.sample_rate_hz, 100.0);
  ASSERT_EQ(o.units.size(), 2u);
  EXPECT_EQ(o.units[0].glob, "gyro*");
  EXPECT_EQ(o.units[0].unit, "deg/s");
  EXPECT_EQ(o.units[1].glob, "");
  EXPECT_EQ(o.units[1].unit, "m/s^2");
  EXPECT_EQ(o.memory_limit, physical_memory() / 2);
}

// diagnose's phase samples to rate: x_{k+1} - x_k times the rate, one sample fewer; a NaN point
// makes both of its increments missing.
TEST(InputArgs, PhaseToRateForDiagnose) {
  std::vector<double> y = {0.0, 1.0, 3.0, std::nan(""), 10.0, 11.0};
  phase_to_rate(y, 2.0);
  ASSERT_EQ(y.size(), 5u);
  EXPECT_EQ(y[0], 2.0);
  EXPECT_EQ(y[1], 4.0);
  EXPECT_TRUE(std::isnan(y[2]));
  EXPECT_TRUE(std::isnan(y[3]));
  EXPECT_EQ(y[4], 2.0);
  std::vector<double> none;
  phase_to_rate(none, 2.0);
  EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace allanlot::workflow
