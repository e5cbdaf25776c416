// ROS bags end to end: `analyze --topic` on a ROS 1 bag (official writer, with dropped
// messages and a second Imu topic) gives the OADEV of the same samples in HDF5 (NaN where the
// messages were dropped) to 1e-9, in SI units; `export --format kalibr|openvins|vins` writes the
// fit's N and K in continuous-time SI units under the key names those tools read.
#include "io/recording.hpp"
#include "io/results.hpp"
#include "support/ros_bags.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

constexpr double kRate = 200.0;

struct Fixture {
  fs::path dir, bag, h5;
};

// /imu: 12000 messages of white noise (sd 0.01) without 40 in the middle; /imu2: 3000.
const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    x.dir = test::test_dir("ros_inputs");
    const test::ImuSamples imu = test::imu_samples(12000, kRate, 5);
    std::set<std::size_t> dropped;
    for (std::size_t i = 6000; i < 6040; ++i)
      dropped.insert(i);
    test::write_imu_csv(x.dir / "imu.csv", imu, dropped);
    test::write_imu_csv(x.dir / "imu2.csv", test::imu_samples(3000, kRate, 6));
    x.bag = x.dir / "unit.bag";
    std::string log;
    EXPECT_EQ(test::write_ros1_bag(x.bag, "lz4",
                                   "/imu=" + (x.dir / "imu.csv").string() +
                                       " /imu2=" + (x.dir / "imu2.csv").string(),
                                   &log),
              0)
        << log;
    // The same samples as HDF5, NaN where the messages were dropped.
    const char* names[6] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
    std::vector<std::vector<double>> ch(6);
    for (std::size_t k = 0; k < 6; ++k)
      for (std::size_t i = 0; i < imu.rows.size(); ++i)
        ch[k].push_back(dropped.count(i) ? std::numeric_limits<double>::quiet_NaN()
                                         : imu.rows[i][k]);
    x.h5 = x.dir / "h5" / "unit.h5";
    fs::create_directories(x.h5.parent_path());
    io::RecordingWriter w(x.h5.string(), "unit", kRate, "imu");
    for (std::size_t k = 0; k < 6; ++k)
      w.add_channel({names[k], k < 3 ? "rad/s" : "m/s^2", ch[k]}, {"rate", 0});
    w.commit();
    return x;
  }();
  return f;
}

const kernels::StatResult& oadev(const io::RecordingResult& r, const std::string& path) {
  for (const auto& ch : r.channels)
    if (ch.path == path)
      for (const auto& [name, s] : ch.stats)
        if (name == "oadev") return s;
  throw std::runtime_error("no oadev of " + path);
}

TEST(RosInputs, BagGivesTheOadevOfTheSameSamplesInHdf5) {
  const Fixture& f = fixture();
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze -q --no-psd --topic '/imu' -o " +
                            (f.dir / "res_bag").string() + " " + f.bag.string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(run_command(binary() + " analyze -q --no-psd -o " + (f.dir / "res_h5").string() + " " +
                            f.h5.string(),
                        &out),
            0)
      << out;
  const io::RecordingResult bag = io::read_results(f.dir / "res_bag" / "unit.allan.h5");
  const io::RecordingResult h5 = io::read_results(f.dir / "res_h5" / "unit.allan.h5");
  ASSERT_EQ(bag.channels.size(), 6u);  // --topic: /imu only
  for (const char* axis : {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"}) {
    const auto& a = oadev(bag, std::string("/imu/") + axis);
    const auto& b = oadev(h5, std::string("/imu/") + axis);
    ASSERT_EQ(a.size(), b.size()) << axis;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_NEAR(a.dev[i], b.dev[i], 1e-9 * b.dev[i]) << axis << " tau " << b.tau_s[i];
      EXPECT_NEAR(a.tau_s[i], b.tau_s[i], 1e-9 * b.tau_s[i]);
    }
  }
  for (const auto& ch : bag.channels)
    EXPECT_EQ(ch.units, ch.path.find("gyro") != std::string::npos ? "rad/s" : "m/s^2");
}

// The YAML parsed by python3-yaml: one line per key, `key value`.
std::map<std::string, std::string> yaml_keys(const fs::path& file, const std::string& root) {
  std::string out;
  const std::string py = "import sys, yaml\n"
                         "text = open(sys.argv[1]).read()\n"
                         "if text.startswith('%YAML:1.0'): text = text.split('\\n', 1)[1]\n"
                         "d = yaml.safe_load(text)\n"
                         "d = d[sys.argv[2]] if sys.argv[2] else d\n"
                         "for k, v in d.items(): print(k, v)\n";
  std::ofstream(file.string() + ".py") << py;
  EXPECT_EQ(run_command(std::string(ALLANLOT_ROS_PYTHON) + " " + file.string() + ".py " +
                            file.string() + " '" + root + "'",
                        &out),
            0)
      << out;
  std::map<std::string, std::string> keys;
  std::stringstream ss(out);
  std::string k, v;
  while (ss >> k && std::getline(ss, v))
    keys[k] = v.substr(1);
  return keys;
}

TEST(RosInputs, KalibrOpenVinsAndVinsYaml) {
  const Fixture& f = fixture();
  std::string out;
  if (!fs::exists(f.dir / "res_bag" / "unit.allan.h5")) {
    ASSERT_EQ(run_command(binary() + " analyze -q --no-psd --topic '/imu' -o " +
                              (f.dir / "res_bag").string() + " " + f.bag.string(),
                          &out),
              0)
        << out;
  }
  const fs::path res = f.dir / "res_bag" / "unit.allan.h5";
  ASSERT_EQ(run_command(binary() + " export --format kalibr " + res.string() + " -o " +
                            (f.dir / "imu.yaml").string(),
                        &out),
            0)
      << out;
  const auto k = yaml_keys(f.dir / "imu.yaml", "");
  for (const char* key :
       {"accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density",
        "gyroscope_random_walk", "rostopic", "update_rate"})
    EXPECT_TRUE(k.count(key)) << key;
  // White noise of sd 0.01 at 200 Hz: the density is 0.01 / sqrt(200) per sqrt(Hz).
  EXPECT_NEAR(std::stod(k.at("gyroscope_noise_density")), 0.01 / std::sqrt(kRate), 1e-4);
  EXPECT_NEAR(std::stod(k.at("accelerometer_noise_density")), 0.01 / std::sqrt(kRate), 1e-4);
  EXPECT_EQ(k.at("rostopic"), "/imu");
  EXPECT_NEAR(std::stod(k.at("update_rate")), kRate, 1e-6);
  // No random walk in white noise: the written value is the fit's upper bound, and says so.
  const std::string text = test::file_bytes(f.dir / "imu.yaml");
  EXPECT_NE(text.find("its 95 % upper bound"), std::string::npos) << text;
  EXPECT_NE(text.find("/imu/gyro_x"), std::string::npos) << text;

  ASSERT_EQ(run_command(binary() + " export --format openvins " + res.string() + " -o " +
                            (f.dir / "chain.yaml").string(),
                        &out),
            0)
      << out;
  const auto o = yaml_keys(f.dir / "chain.yaml", "imu0");
  EXPECT_EQ(o.at("gyroscope_noise_density"), k.at("gyroscope_noise_density"));
  EXPECT_TRUE(o.count("T_i_b"));
  ASSERT_EQ(run_command(binary() + " export --format vins --combine mean " + res.string() + " -o " +
                            (f.dir / "vins.yaml").string(),
                        &out),
            0)
      << out;
  const auto v = yaml_keys(f.dir / "vins.yaml", "");
  for (const char* key : {"acc_n", "gyr_n", "acc_w", "gyr_w"})
    EXPECT_TRUE(v.count(key)) << key;
  EXPECT_LE(std::stod(v.at("gyr_n")), std::stod(k.at("gyroscope_noise_density")));
}

TEST(RosInputs, ExportNamesTheImusWhenSeveral) {
  const Fixture& f = fixture();
  std::string out;
  ASSERT_EQ(run_command(binary() + " analyze -q --no-psd -o " + (f.dir / "res_all").string() + " " +
                            f.bag.string(),
                        &out),
            0)
      << out;
  EXPECT_EQ(run_command(binary() + " export --format kalibr " +
                            (f.dir / "res_all" / "unit.allan.h5").string(),
                        &out),
            2);
  EXPECT_NE(out.find("2 IMUs (unit:/imu unit:/imu2): select one with --channels"),
            std::string::npos)
      << out;
}

}  // namespace
}  // namespace allanlot
