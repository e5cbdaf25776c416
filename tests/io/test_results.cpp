// Results files and lot summaries: written complete or not at all, and read back unchanged.
#include "io/error.hpp"
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

namespace allanlot {
namespace {

io::RecordingResult sample_result() {
  io::RecordingResult r;
  r.device_id = "SN 1";
  r.source_file = "/data/sn1.h5";
  r.tool_version = "0.1.0";
  r.created_utc = "2026-11-22T00:00:00Z";
  r.command_line = "allanlot analyze -o out sn1.h5";
  r.attributes = {{"taus", "octave"}};
  io::ChannelResult ch;
  ch.path = "/imu/gyro_x";
  ch.units = "deg/s";
  ch.sample_rate_hz = 1000;
  ch.n_samples = 5400000;
  ch.n_gaps = 3;
  kernels::StatResult s;
  s.m = {1, 2, 4};
  s.tau_s = {0.001, 0.002, 0.004};
  s.dev = {1e-3, 7e-4, 5e-4};
  s.n = {5399999, 5399997, 5399993};
  ch.stats.emplace_back("oadev", s);
  r.channels.push_back(ch);
  io::ChannelResult bad;
  bad.path = "/imu/temp";
  bad.status = "failed: too short";
  r.channels.push_back(bad);
  return r;
}

TEST(Results, RoundTrip) {
  const auto dir = test::fresh_dir("results_rt");
  const auto path = dir / "SN_1.allan.h5";
  const auto r = sample_result();
  io::write_results(path, r);
  const auto back = io::read_results(path);
  EXPECT_EQ(back.device_id, r.device_id);
  EXPECT_EQ(back.command_line, r.command_line);
  ASSERT_EQ(back.channels.size(), 2u);
  const auto& ch = back.channels[0].path == "/imu/gyro_x" ? back.channels[0] : back.channels[1];
  EXPECT_EQ(ch.units, "deg/s");
  EXPECT_EQ(ch.n_samples, 5400000);
  EXPECT_EQ(ch.n_gaps, 3);
  ASSERT_EQ(ch.stats.size(), 1u);
  EXPECT_EQ(ch.stats[0].first, "oadev");
  EXPECT_EQ(ch.stats[0].second.m, r.channels[0].stats[0].second.m);
  EXPECT_EQ(ch.stats[0].second.dev, r.channels[0].stats[0].second.dev);
  EXPECT_EQ(ch.stats[0].second.n, r.channels[0].stats[0].second.n);
  // Only the final file is left: the temporary was renamed.
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(Results, UnwritableDestinationThrowsAndLeavesNothing) {
  const auto dir = test::fresh_dir("results_bad");
  EXPECT_THROW(io::write_results(dir / "no_such_dir" / "x.allan.h5", sample_result()), io::Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(Results, LotSummaryRoundTripAndCsv) {
  const auto dir = test::fresh_dir("summary_rt");
  std::vector<io::SummaryRow> rows = io::summary_rows(sample_result());
  rows.push_back({"broken", "", "", 0, "failed: not an HDF5 file, \"really\"", "/x/broken.h5"});
  io::write_lot_summary(dir, rows);
  const auto back = io::read_lot_summary(dir / "lot_summary.h5");
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(back[i].device_id, rows[i].device_id);
    EXPECT_EQ(back[i].channel, rows[i].channel);
    EXPECT_EQ(back[i].n_samples, rows[i].n_samples);
    EXPECT_EQ(back[i].status, rows[i].status);
  }
  const std::string csv = test::file_bytes(dir / "lot_summary.csv");
  EXPECT_EQ(csv.rfind("device_id,channel,units,n_samples,status,source_file\n", 0), 0u);
  EXPECT_NE(csv.find("SN 1,/imu/gyro_x,deg/s,5400000,ok,/data/sn1.h5\n"), std::string::npos);
  EXPECT_NE(csv.find("\"failed: not an HDF5 file, \"\"really\"\"\""), std::string::npos);
}

}  // namespace
}  // namespace allanlot
