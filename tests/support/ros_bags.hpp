// Test-only helpers that write ROS bags with the official writers (tests/ros/): the samples
// of each Imu topic as a CSV the writer reads, its messages timed at `rate_hz` with the rows
// `dropped` left out (messages lost in recording).
#pragma once

#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <string>
#include <vector>

namespace allanlot::test {

/// Six channels of white noise (gyro x y z, accel x y z) of n messages.
struct ImuSamples {
  std::vector<std::array<double, 6>> rows;
  std::vector<std::int64_t> stamps_ns;  // each row's header stamp
};

/// A fresh directory `stem_<suite>_<test>` for the running test: CTest runs each test of a
/// program as its own process, in parallel, so a fixture's files must not be shared between
/// tests (one test's fresh_dir would empty another's).
inline std::filesystem::path test_dir(const std::string& stem) {
  const auto* t = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = stem + "_" + t->test_suite_name() + "_" + t->name();
  for (char& c : name)
    if (c == '/' || c == '"') c = '_';
  return fresh_dir(name);
}

inline ImuSamples imu_samples(std::size_t n, double rate_hz, unsigned seed) {
  ImuSamples s;
  std::array<std::vector<double>, 6> ch;
  for (unsigned k = 0; k < 6; ++k)
    ch[k] = noise(n, seed * 7 + k);
  const auto step = static_cast<std::int64_t>(1e9 / rate_hz);
  for (std::size_t i = 0; i < n; ++i) {
    s.rows.push_back({ch[0][i], ch[1][i], ch[2][i], ch[3][i] + 9.81, ch[4][i], ch[5][i]});
    s.stamps_ns.push_back(1700000000000000000 + static_cast<std::int64_t>(i) * step);
  }
  return s;
}

/// Writes the rows not in `dropped` as the writer's CSV.
inline void write_imu_csv(const std::filesystem::path& csv, const ImuSamples& s,
                          const std::set<std::size_t>& dropped = {}) {
  std::ofstream out(csv);
  out << std::setprecision(17);
  for (std::size_t i = 0; i < s.rows.size(); ++i) {
    if (dropped.count(i)) continue;
    out << s.stamps_ns[i];
    for (double v : s.rows[i])
      out << "," << v;
    out << "\n";
  }
}

/// Runs tests/ros/write_ros1_bag.py (Debian's python3-rosbag); returns its exit status and
/// output in `log`.
inline int write_ros1_bag(const std::filesystem::path& bag, const std::string& compression,
                          const std::string& topics_and_csvs, std::string* log) {
  return run_command(std::string(ALLANLOT_ROS_PYTHON) + " " + ALLANLOT_TESTS_DIR +
                         "/ros/write_ros1_bag.py " + bag.string() + " " + compression + " " +
                         topics_and_csvs,
                     log);
}

/// Runs tests/ros/write_ros2_db3.py (rosbag2's sqlite3 storage): `bag` a folder, or a .db3.
inline int write_ros2_db3(const std::filesystem::path& bag, const std::string& topics_and_csvs,
                          std::string* log) {
  return run_command(std::string(ALLANLOT_ROS_PYTHON) + " " + ALLANLOT_TESTS_DIR +
                         "/ros/write_ros2_db3.py " + bag.string() + " " + topics_and_csvs,
                     log);
}

}  // namespace allanlot::test
