// Data editing and the dynamic deviation through a channel's analysis (src/pipeline/
// channel_edits.hpp), the results file and the command line: an excluded range is listed and its
// samples do not enter the statistics, a clock's bad first phase point is removed and listed, a
// clean record has no edit, the drift is recorded, and every group reads back as written.
#include "io/results.hpp"
#include "src/pipeline/channel.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <random>
#include <vector>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

io::ChannelInfo info(kernels::DataType type, std::size_t n) {
  io::ChannelInfo c;
  c.path = "/clock/phase";
  c.units = "1";
  c.sample_rate_hz = 1.0;
  c.data_type = type;
  c.n_samples = static_cast<std::int64_t>(n);
  return c;
}

pipeline::ChannelOptions options() {
  pipeline::ChannelOptions o;
  o.stats = {kernels::Stat::Oadev};
  o.fit = false;
  o.psd = false;
  o.gaps = kernels::GapPolicy{kernels::GapPolicy::Mode::Skip, 0};
  return o;
}

std::vector<double> white_fm(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  for (double& v : y)
    v = 1e-11 * g(rng);
  return y;
}

kernels::LargeVector<double> large(const std::vector<double>& v) {
  kernels::LargeVector<double> l(v.size());
  std::copy(v.begin(), v.end(), l.begin());
  return l;
}

TEST(Editing, ExcludedRangeIsListedAndItsSamplesDoNotCount) {
  const auto y = white_fm(4096, 1);
  auto opt = options();
  opt.edit.exclude = {{1000.0, 1499.0}};
  auto wild = y;
  for (std::size_t i = 1000; i <= 1499; ++i)
    wild[i] = 1e-3 * static_cast<double>(i);
  const auto a = pipeline::analyze_channel(info(kernels::DataType::Rate, y.size()), large(y), opt);
  const auto b =
      pipeline::analyze_channel(info(kernels::DataType::Rate, y.size()), large(wild), opt);
  ASSERT_TRUE(a.ok()) << io::to_string(a.result.status);
  ASSERT_EQ(a.result.edits.size(), 1u);
  EXPECT_EQ(a.result.edits[0].kind, "excluded");
  EXPECT_EQ(a.result.edits[0].first, 1000);
  EXPECT_EQ(a.result.edits[0].last, 1499);
  EXPECT_NE(a.result.notes.find("500 samples excluded"), std::string::npos) << a.result.notes;
  // Whatever the excluded samples were, the statistics are the same bits.
  ASSERT_EQ(a.result.stats.size(), 1u);
  const auto &da = a.result.stats[0].second.dev, &db = b.result.stats[0].second.dev;
  ASSERT_EQ(da.size(), db.size());
  for (std::size_t i = 0; i < da.size(); ++i)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(da[i]), std::bit_cast<std::uint64_t>(db[i]));
  // And without the exclusion the wild samples dominate.
  const auto c =
      pipeline::analyze_channel(info(kernels::DataType::Rate, y.size()), large(wild), options());
  EXPECT_GT(c.result.stats[0].second.dev[0], 100 * da[0]);
}

TEST(Editing, ClocksBadFirstPhasePointIsRemovedAndListed) {
  const auto y = white_fm(2048, 2);
  std::vector<double> x(y.size());
  double acc = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    x[i] = acc += y[i];
  auto opt = options();
  opt.edit.outlier_sigmas = kernels::kDefaultOutlierSigmas;
  const auto clean =
      pipeline::analyze_channel(info(kernels::DataType::Phase, x.size()), large(x), opt);
  ASSERT_TRUE(clean.ok());
  EXPECT_TRUE(clean.result.edits.empty());
  x[0] += 20e-9;
  const auto a = pipeline::analyze_channel(info(kernels::DataType::Phase, x.size()), large(x), opt);
  ASSERT_TRUE(a.ok()) << io::to_string(a.result.status);
  ASSERT_EQ(a.result.edits.size(), 1u);
  EXPECT_EQ(a.result.edits[0].kind, "outlier");
  EXPECT_EQ(a.result.edits[0].first, 0);
  EXPECT_EQ(a.result.edits[0].value, x[0]);
  EXPECT_GT(a.result.edits[0].sigmas, 90.0);
  // The point set the record's MTIE; removed (and filled under the default gap policy), MTIE is
  // the clock's own again.
  opt.stats = {kernels::Stat::Mtie};
  opt.gaps = kernels::GapPolicy{};
  auto plain = opt;
  plain.edit.outlier_sigmas = 0;
  const auto with =
      pipeline::analyze_channel(info(kernels::DataType::Phase, x.size()), large(x), plain);
  const auto without =
      pipeline::analyze_channel(info(kernels::DataType::Phase, x.size()), large(x), opt);
  ASSERT_TRUE(with.ok() && without.ok());
  const double mtie_with = with.result.stats.at(0).second.dev.back();
  const double mtie_without = without.result.stats.at(0).second.dev.back();
  EXPECT_GT(mtie_with, 20e-9);
  EXPECT_LT(mtie_without, 0.25 * mtie_with);
}

TEST(Editing, DriftAndDynamicReadBackAsWritten) {
  auto y = white_fm(4096, 3);
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] += 1e-14 * static_cast<double>(i);
  y[77] = 5e-9;
  auto opt = options();
  opt.edit.drift = kernels::DriftModel::Linear;
  opt.edit.outlier_sigmas = 5;
  opt.edit.exclude = {{10.0, 12.0}};
  opt.edit.dynamic = kernels::DynamicSpec{1024, 512, false};
  const auto a = pipeline::analyze_channel(info(kernels::DataType::Rate, y.size()), large(y), opt);
  ASSERT_TRUE(a.ok()) << io::to_string(a.result.status);
  ASSERT_TRUE(a.result.drift && a.result.dynamic);
  EXPECT_EQ(a.result.drift->parameter.back(), "drift");
  EXPECT_NEAR(a.result.drift->value.back(), 1e-14, 4 * a.result.drift->sigma.back());
  EXPECT_EQ(a.result.edits.size(), 2u);
  EXPECT_EQ(a.result.dynamic->t_center.size(), 7u);

  io::RecordingResult rec;
  rec.device_id = "clock";
  rec.channels.push_back(a.result);
  const fs::path path = test::fresh_dir("editing_rt") / "clock.allan.h5";
  io::write_results(path, rec);
  const io::ChannelResult back = io::read_results(path).channels.at(0);
  ASSERT_TRUE(back.drift && back.dynamic);
  EXPECT_EQ(back.drift->parameter, a.result.drift->parameter);
  EXPECT_EQ(back.drift->value, a.result.drift->value);
  EXPECT_EQ(back.drift->sigma, a.result.drift->sigma);
  EXPECT_EQ(back.drift->unit, a.result.drift->unit);
  EXPECT_EQ(back.drift->residual, a.result.drift->residual);
  ASSERT_EQ(back.edits.size(), a.result.edits.size());
  for (std::size_t i = 0; i < back.edits.size(); ++i) {
    EXPECT_EQ(back.edits[i].kind, a.result.edits[i].kind);
    EXPECT_EQ(back.edits[i].first, a.result.edits[i].first);
    EXPECT_EQ(back.edits[i].last, a.result.edits[i].last);
  }
  EXPECT_EQ(back.dynamic->m, a.result.dynamic->m);
  EXPECT_EQ(back.dynamic->t_center, a.result.dynamic->t_center);
  ASSERT_EQ(back.dynamic->oadev.size(), a.result.dynamic->oadev.size());
  for (std::size_t i = 0; i < back.dynamic->oadev.size(); ++i)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back.dynamic->oadev[i]),
              std::bit_cast<std::uint64_t>(a.result.dynamic->oadev[i]));
}

TEST(Editing, CommandLineAndReport) {
  const fs::path dir = test::fresh_dir("editing_cli");
  std::vector<double> x(3000);
  const auto y = white_fm(x.size(), 4);
  double acc = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = acc += y[i] + 1e-15 * static_cast<double>(i);
  x[0] += 20e-9;
  {
    std::ofstream f(dir / "PHASE.DAT");
    f.precision(17);
    for (const double v : x)
      f << v << "\n";
  }
  const std::string before = test::file_bytes(dir / "PHASE.DAT");
  const std::string run = test::binary() + " analyze -q --data-type phase --sample-rate 1 " +
                          "--no-fit --no-psd --stats oadev --outliers mad --drift linear " +
                          "--exclude 100:199 --exclude 2000:2009 --dynamic 1024:256 -o " +
                          (dir / "out").string() + " " + (dir / "PHASE.DAT").string();
  ASSERT_EQ(std::system(run.c_str()), 0) << run;
  EXPECT_EQ(test::file_bytes(dir / "PHASE.DAT"), before);  // the recording is never altered
  const auto rec = io::read_results(dir / "out" / "PHASE.allan.h5");
  const io::ChannelResult& ch = rec.channels.at(0);
  ASSERT_TRUE(ch.drift && ch.dynamic);
  EXPECT_EQ(ch.drift->model, "quadratic");
  ASSERT_EQ(ch.edits.size(), 3u);
  EXPECT_EQ(ch.edits[2].kind, "outlier");
  EXPECT_EQ(ch.edits[2].first, 0);
  const std::string report = test::binary() + " report " + (dir / "out").string() + " > /dev/null";
  ASSERT_EQ(std::system(report.c_str()), 0);
  std::string html;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out"))
    if (e.path().extension() == ".html") html += test::file_bytes(e.path());
  EXPECT_NE(html.find("Dynamic Allan deviation"), std::string::npos);
  EXPECT_NE(html.find("Drift removed (quadratic"), std::string::npos);
  EXPECT_NE(html.find("Edits (3"), std::string::npos);
  const std::string bad = test::binary() + " analyze -q --drift cubic -o " +
                          (dir / "bad").string() + " " + (dir / "PHASE.DAT").string() +
                          " 2> /dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2);
}

}  // namespace
}  // namespace allanlot
