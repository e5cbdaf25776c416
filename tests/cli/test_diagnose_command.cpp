// `allanlot diagnose` through the binary: a simulated measurement with a hidden sinusoid, the
// JSON object of docs/diagnose.md, the -o group written into an existing file, the corrected model
// accepted by `simulate`, the input never modified, and usage errors with exit status 2; a
// hidden jump named as a step, end to end.
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace allanlot {
namespace {

using test::binary;
using test::run_command;

// Writes dir/given.json (white N = 0.01 and flicker B = 0.003 in deg/s at 100 Hz) and
// dir/truth.json (the same with the model file's `effects`), and simulates 600 s of the truth
// with `seed` into dir/meas.h5, whose path it returns.
std::string measurement(const std::filesystem::path& dir, const std::string& effects, int seed) {
  {
    std::ofstream g(dir / "given.json");
    g << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.01, "B": 0.003}})";
    std::ofstream t(dir / "truth.json");
    t << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.01, "B": 0.003},
             "effects": )"
      << effects << "}";
  }
  const std::string in = (dir / "meas.h5").string();
  std::string out;
  EXPECT_EQ(run_command(binary() + " simulate -q --model " + (dir / "truth.json").string() +
                            " --duration 600 --seed " + std::to_string(seed) + " -o " + in,
                        &out),
            0)
      << out;
  return in;
}

TEST(DiagnoseCommand, NamesTheHiddenSinusoidAndWritesEverything) {
  const auto dir = test::fresh_dir("diagnose_cli");
  const std::string in =
      measurement(dir, R"([{"type": "sinusoid", "amplitude": 0.008, "frequency_hz": 0.5}])", 4);
  ASSERT_FALSE(::testing::Test::HasFailure());
  std::string out;
  const std::string bytes = test::file_bytes(in);
  // -o twice into the same file: the second run replaces the group of the first in a copy.
  const std::string cmd =
      binary() + " diagnose " + in + " --model " + (dir / "given.json").string() + " --threads 2";
  ASSERT_EQ(run_command(cmd + " --replicas 4 --json -o " + (dir / "out.h5").string(), &out), 0)
      << out;
  ASSERT_EQ(run_command(cmd + " --replicas 4 --json -o " + (dir / "out.h5").string() +
                            " --model-out " + (dir / "fixed.json").string() + " 2>/dev/null",
                        &out),
            0)
      << out;
  const auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["channel"], "/imu/gyro_x");
  ASSERT_EQ(j["effects_named"].size(), 1u) << out;
  EXPECT_EQ(j["effects_named"][0], "sinusoid");
  EXPECT_NEAR(j["parameters"]["sinusoid"]["frequency_hz"].get<double>(), 0.5, 0.025);
  EXPECT_GT(j["gap_before"].get<double>(), j["gap_after"].get<double>());
  EXPECT_EQ(j["iterations"].size(), 1u);
  EXPECT_EQ(test::file_bytes(in), bytes);

  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen((dir / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const char* ds :
       {"/imu/gyro_x", "/imu/gyro_x/diagnosis/tau", "/imu/gyro_x/diagnosis/avar_model_after",
        "/imu/gyro_x/diagnosis/mc_after_hi", "/imu/gyro_x/diagnosis/z_before",
        "/imu/gyro_x/diagnosis/effect"})
    EXPECT_GT(H5Lexists(f, ds, H5P_DEFAULT), 0) << ds;
  H5Fclose(f);

  // The corrected model drives simulate.
  EXPECT_EQ(run_command(binary() + " simulate -q --model " + (dir / "fixed.json").string() +
                        " --duration 10 -o " + (dir / "again.h5").string()),
            0);
  // The human report names the effect.
  ASSERT_EQ(run_command(cmd + " --replicas 0", &out), 0) << out;
  EXPECT_NE(out.find("add sinusoid"), std::string::npos) << out;

  // --max-effects is taken (1: the one hidden effect is still named).
  ASSERT_EQ(run_command(cmd + " --replicas 0 --max-effects 1 --json", &out), 0) << out;
  EXPECT_EQ(nlohmann::json::parse(out)["effects_named"].size(), 1u) << out;

  // Usage errors: missing channel, --max-effects out of range, bad model file, -o naming the
  // input.
  EXPECT_EQ(run_command(cmd + " --max-effects 0", &out), 2) << out;
  EXPECT_EQ(run_command(cmd + " --channel nope", &out), 2) << out;
  EXPECT_NE(out.find("no channel 'nope'"), std::string::npos) << out;
  {
    std::ofstream b(dir / "bad.json");
    b << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"X": 1}})";
  }
  EXPECT_EQ(
      run_command(binary() + " diagnose " + in + " --model " + (dir / "bad.json").string(), &out),
      2);
  EXPECT_NE(out.find("terms.X"), std::string::npos) << out;
  EXPECT_EQ(run_command(cmd + " -o " + in, &out), 2) << out;
  // A recording is not a results file: its channel is a dataset, not a group.
  std::filesystem::copy_file(in, dir / "copy.h5");
  EXPECT_EQ(run_command(cmd + " -o " + (dir / "copy.h5").string(), &out), 1) << out;
  EXPECT_NE(out.find("not a group"), std::string::npos) << out;
  // analyze's output folder is not a results file either: the folder is named, not the input.
  std::filesystem::create_directory(dir / "results");
  EXPECT_EQ(run_command(cmd + " -o " + (dir / "results").string(), &out), 1) << out;
  EXPECT_NE(out.find((dir / "results").string() + ": is a folder"), std::string::npos) << out;
  EXPECT_TRUE(std::filesystem::is_empty(dir / "results"));
  EXPECT_EQ(test::file_bytes(in), bytes);
  EXPECT_EQ(run_command(binary() + " diagnose " + (dir / "missing.h5").string() + " --model " +
                            (dir / "given.json").string(),
                        &out),
            1)
      << out;
}

TEST(DiagnoseCommand, AJumpIsNamedAsAStepAndTheCorrectedModelCarriesIt) {
  // A bias jump of 0.05 at 250.3 s (9 rms of adjacent 10 s means, test_diagnose_support.hpp):
  // simulate draws it, diagnose names it from its time-domain witness, the corrected model
  // holds it under the model file's keys, and that model re-diagnosed names nothing.
  const auto dir = test::fresh_dir("diagnose_cli_step");
  const std::string in =
      measurement(dir, R"([{"type": "step", "size": 0.05, "time_s": 250.3}])", 3);
  ASSERT_FALSE(::testing::Test::HasFailure());
  std::string out;
  const std::string fixed = (dir / "fixed.json").string();
  ASSERT_EQ(run_command(binary() + " diagnose " + in + " --model " + (dir / "given.json").string() +
                            " --replicas 4 --json --model-out " + fixed,
                        &out),
            0)
      << out;
  const auto j = nlohmann::json::parse(out);
  ASSERT_EQ(j["effects_named"], nlohmann::json::array({"step"})) << out;
  EXPECT_NEAR(j["parameters"]["step"]["time_s"].get<double>(), 250.3, 1.0);
  EXPECT_NEAR(j["parameters"]["step"]["size"].get<double>(), 0.05, 0.015);
  EXPECT_TRUE(j["step_witness"]["found"].get<bool>());
  const auto& trend = j["trend_witness"];
  ASSERT_TRUE(trend["searched"].get<bool>()) << out;
  EXPECT_GT(trend["sigma"].get<double>(), 0.0);
  EXPECT_NEAR(trend["z"].get<double>(), trend["slope"].get<double>() / trend["sigma"].get<double>(),
              1e-9);
  std::ifstream f(fixed);
  const auto model = nlohmann::json::parse(f);
  ASSERT_EQ(model["effects"].size(), 1u);
  EXPECT_EQ(model["effects"][0]["type"], "step");
  ASSERT_EQ(run_command(binary() + " diagnose " + in + " --model " + fixed + " --replicas 4 --json",
                        &out),
            0)
      << out;
  EXPECT_TRUE(nlohmann::json::parse(out)["effects_named"].empty()) << out;
}

TEST(DiagnoseCommand, APeakWiderThanALineIsNamedAResonanceMeasuredOnThePeriodogram) {
  // A resonance of q = 100 at 2 Hz (12 bins of 1/600 Hz wide at half power) is no line: the
  // terminal says so, and the JSON names a resonance whose f0 and q come from the periodogram,
  // with sigmas, and reports the peak under psd_line.
  const auto dir = test::fresh_dir("diagnose_cli_narrowband");
  const std::string in =
      measurement(dir, R"([{"type": "resonance", "sigma": 0.1, "frequency_hz": 2, "q": 100}])", 5);
  ASSERT_FALSE(::testing::Test::HasFailure());
  const std::string cmd =
      binary() + " diagnose " + in + " --model " + (dir / "given.json").string() + " --replicas 4";
  std::string out;
  ASSERT_EQ(run_command(cmd, &out), 0) << out;
  EXPECT_NE(out.find("Hz is wider than a line (a narrowband process), as a resonance"),
            std::string::npos)
      << out;
  ASSERT_EQ(run_command(cmd + " --json", &out), 0) << out;
  const auto j = nlohmann::json::parse(out);
  ASSERT_EQ(j["effects_named"], nlohmann::json::array({"resonance"})) << out;
  const auto& nb = j["psd_line"]["narrowband"];
  EXPECT_NEAR(j["psd_line"]["wide_hz"].get<double>(), 2.0, 0.05);
  EXPECT_NEAR(nb["frequency_hz"].get<double>(), 2.0, 4.0 * nb["frequency_sigma"].get<double>());
  EXPECT_NEAR(nb["q"].get<double>(), 100.0, 4.0 * nb["q_sigma"].get<double>());
  EXPECT_EQ(j["parameters"]["resonance"]["q"], nb["q"]);
  EXPECT_EQ(j["parameter_sigmas"]["resonance"]["q"], nb["q_sigma"]);
}

}  // namespace
}  // namespace allanlot
