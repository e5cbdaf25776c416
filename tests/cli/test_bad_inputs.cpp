// Bad inputs, in the spirit of FINUFFT's "dumbinputs": every kind of broken,
// hostile or merely odd recording goes through the real binary in one lot beside good units.
// For each case: the documented exit status (docs/cli.md: 1 when some inputs or channels fail),
// a message naming the file, the dataset and the reason, the good inputs analysed, no
// results file for an input that failed as a whole, the failure in the lot summary, and every
// input byte for byte as it was (compared by hash).
#include "io/results.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::H5Fixture;
using test::noise;
using test::run_command;

constexpr double kInf = std::numeric_limits<double>::infinity();

// FNV-1a over the file's bytes: enough to see that an input changed (not a security hash).
std::uint64_t file_hash(const fs::path& p) {
  std::uint64_t h = 1469598103934665603ull;
  for (const char c : test::file_bytes(p)) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

// One good channel in the simulate layout: /imu/gyro_x, 100 Hz.
void good_unit(const fs::path& path, unsigned seed) {
  H5Fixture f(path);
  f.dataset("/imu/gyro_x", noise(3000, seed), H5T_IEEE_F64LE);
  f.attr("/imu", "sample_rate_hz", 100.0);
  f.attr("/imu", "units", "deg/s");
}

// A file whose only channel is /imu/gyro_x with `rate` on /imu; `extra` adds the defect.
void one_channel(const fs::path& path, std::vector<double> v, double rate,
                 const std::function<void(H5Fixture&)>& extra = {}) {
  H5Fixture f(path);
  f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
  f.attr("/imu", "sample_rate_hz", rate);
  if (extra) extra(f);
}

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<long>(bytes.size()));
}

enum class Outcome {
  FileFails,     // no results file; the input's row in the summary is "failed: ..."
  ChannelFails,  // a results file whose channel `dataset` has status "failed: ..."
  Ok             // a results file whose every channel is "ok"
};

struct Case {
  std::string stem;  // the input is <stem>.h5 and, without device_id, <stem>.allan.h5 its results
  std::function<void(const fs::path&)> make;
  Outcome outcome;
  std::string dataset;               // the dataset the message must name ("" = the file only)
  std::vector<std::string> reasons;  // one of these must be in the message
};

std::vector<Case> cases(const fs::path& dir) {
  const auto good_bytes = [&] {
    const fs::path p = dir / "template.h5";
    {
      H5Fixture f(p);
      f.dataset("/imu/gyro_x", noise(50000, 99), H5T_IEEE_F64LE);
      f.attr("/imu", "sample_rate_hz", 100.0);
    }
    std::string b = test::file_bytes(p);
    fs::remove(p);
    return b;
  }();
  const auto v = noise(3000, 7);
  std::vector<Case> c;
  // Not HDF5, or HDF5 that cannot be read.
  c.push_back({"empty",
               [](const fs::path& p) { write_bytes(p, ""); },
               Outcome::FileFails,
               "",
               {"not an HDF5 file"}});
  c.push_back({"random_bytes",
               [](const fs::path& p) {
                 std::mt19937 rng(4);
                 std::string b(8192, '\0');
                 for (auto& ch : b)
                   ch = static_cast<char>(rng());
                 write_bytes(p, b);
               },
               Outcome::FileFails,
               "",
               {"not an HDF5 file"}});
  c.push_back({"signature_only",
               [](const fs::path& p) { write_bytes(p, std::string("\x89HDF\r\n\x1a\n", 8)); },
               Outcome::FileFails,
               "",
               {"not an HDF5 file", "corrupt"}});
  for (const double frac : {0.5, 0.02}) {
    c.push_back({"truncated_" + std::to_string(static_cast<int>(frac * 100)),
                 [good_bytes, frac](const fs::path& p) {
                   write_bytes(
                       p, good_bytes.substr(0, static_cast<std::size_t>(
                                                   frac * static_cast<double>(good_bytes.size()))));
                 },
                 Outcome::FileFails,
                 "",
                 {"truncated", "corrupt", "not an HDF5 file"}});
  }
  // Metadata overwritten: superblock fields, then the object headers after it.
  for (const std::size_t at :
       {std::size_t{9}, std::size_t{40}, std::size_t{96}, std::size_t{800}}) {
    c.push_back({"corrupt_at_" + std::to_string(at),
                 [good_bytes, at](const fs::path& p) {
                   std::string b = good_bytes;
                   for (std::size_t i = at; i < at + 64 && i < b.size(); ++i)
                     b[i] = static_cast<char>(0xA5);
                   write_bytes(p, b);
                 },
                 Outcome::FileFails,
                 "",
                 {"truncated", "corrupt", "not an HDF5 file", "no channel"}});
  }
  // Valid HDF5 without a channel.
  c.push_back({"no_channels",
               [](const fs::path& p) {
                 H5Fixture f(p);
                 f.dataset("/data/x", {1, 2, 3}, H5T_IEEE_F64LE);
                 f.group("/empty/group");
               },
               Outcome::FileFails,
               "",
               {"no channel found"}});
  c.push_back({"only_time",
               [](const fs::path& p) {
                 H5Fixture f(p);
                 f.dataset("/imu/time", {0, 1, 2, 3}, H5T_IEEE_F64LE);
                 f.attr("/imu", "sample_rate_hz", 1.0);
               },
               Outcome::FileFails,
               "",
               {"no channel found"}});
  // sample_rate_hz that is not a positive finite number.
  const std::pair<const char*, double> bad_rates[] = {{"rate_zero", 0.0},
                                                      {"rate_negative", -100.0},
                                                      {"rate_nan", std::nan("")},
                                                      {"rate_inf", kInf},
                                                      {"rate_minus_inf", -kInf}};
  for (const auto& [stem, rate] : bad_rates)
    c.push_back({stem,
                 [v, rate = rate](const fs::path& p) { one_channel(p, v, rate); },
                 Outcome::FileFails,
                 "/imu/gyro_x",
                 {"sample_rate_hz = ", "must be finite and > 0"}});
  c.push_back({"rate_string",
               [v](const fs::path& p) {
                 H5Fixture f(p);
                 f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
                 f.attr("/imu", "sample_rate_hz", "100 Hz");
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"attribute 'sample_rate_hz' must be a number"}});
  c.push_back({"rate_array",
               [v](const fs::path& p) {
                 H5Fixture f(p);
                 f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
                 f.attr_array("/imu", "sample_rate_hz", {100.0, 200.0});
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"attribute 'sample_rate_hz' must be a single number"}});
  // Channels too short for any tau, empty, or of the wrong shape or type.
  // Channels too short for any tau: fewer than 2 samples. Two samples give totdev at m = 1 but
  // no tau of the overlapping Allan curve, so no fit and no PSD: a failure with its reason,
  // not "ok" with empty tables. Four samples give one tau of every default statistic. A record too
  // short for the statistics asked for fails with "too short for any tau",
  // tests/cli/test_analyze.cpp.
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}})
    c.push_back({"short_" + std::to_string(n),
                 [n](const fs::path& p) { one_channel(p, std::vector<double>(n, 1.0), 10.0); },
                 Outcome::FileFails,
                 "/imu/gyro_x",
                 {"need at least 2 rate samples"}});
  c.push_back({"short_2",
               [](const fs::path& p) { one_channel(p, std::vector<double>(2, 1.0), 10.0); },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"too short for the fit and the PSD"}});
  for (const std::size_t n : {std::size_t{4}})
    c.push_back({"short_" + std::to_string(n),
                 [n](const fs::path& p) { one_channel(p, std::vector<double>(n, 1.0), 10.0); },
                 Outcome::Ok,
                 "",
                 {}});
  // Channels of the wrong shape or type.
  c.push_back({"two_d",
               [](const fs::path& p) {
                 H5Fixture f(p);
                 f.dataset("/imu/gyro_x", std::vector<double>(200, 1.0), H5T_IEEE_F64LE, {100, 2});
                 f.attr("/imu", "sample_rate_hz", 10.0);
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"2 dimensions"}});
  c.push_back({"string_channel",
               [](const fs::path& p) {
                 H5Fixture f(p);
                 f.string_dataset("/imu/gyro_x", {"1.0", "2.0", "3.0"});
                 f.attr("/imu/gyro_x", "sample_rate_hz", 10.0);
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"type string cannot be a channel"}});
  c.push_back({"compound_channel",
               [](const fs::path& p) {
                 H5Fixture f(p);
                 f.compound_dataset("/imu/gyro_x", 100);
                 f.attr("/imu/gyro_x", "sample_rate_hz", 10.0);
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"type compound cannot be a channel"}});
  // Sample values: all missing, infinite.
  c.push_back(
      {"all_nan",
       [](const fs::path& p) { one_channel(p, std::vector<double>(3000, std::nan("")), 100.0); },
       Outcome::FileFails,
       "/imu/gyro_x",
       {"no valid (non-NaN) sample"}});
  c.push_back({"plus_inf",
               [v](const fs::path& p) {
                 auto w = v;
                 w[1234] = kInf;
                 one_channel(p, w, 100.0);
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"infinite"}});
  c.push_back({"minus_inf",
               [v](const fs::path& p) {
                 auto w = v;
                 w[0] = -kInf;
                 one_channel(p, w, 100.0);
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"infinite"}});
  // Attributes of the wrong type or value.
  c.push_back({"units_number",
               [v](const fs::path& p) {
                 one_channel(p, v, 100.0, [](H5Fixture& f) { f.attr("/imu", "units", 3.0); });
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"attribute 'units' must be a string"}});
  c.push_back({"scale_string",
               [v](const fs::path& p) {
                 one_channel(p, v, 100.0,
                             [](H5Fixture& f) { f.attr("/imu/gyro_x", "scale", "0.1"); });
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"attribute 'scale' must be a number"}});
  c.push_back({"scale_zero",
               [v](const fs::path& p) {
                 one_channel(p, v, 100.0, [](H5Fixture& f) { f.attr("/imu", "scale", 0.0); });
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"scale must be finite and non-zero"}});
  c.push_back({"offset_nan",
               [v](const fs::path& p) {
                 one_channel(p, v, 100.0,
                             [](H5Fixture& f) { f.attr("/imu", "offset", std::nan("")); });
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"offset finite"}});
  c.push_back({"data_type_number",
               [v](const fs::path& p) {
                 one_channel(p, v, 100.0, [](H5Fixture& f) { f.attr("/imu", "data_type", 1.0); });
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"attribute 'data_type' must be a string"}});
  c.push_back({"data_type_unknown",
               [v](const fs::path& p) {
                 one_channel(p, v, 100.0,
                             [](H5Fixture& f) { f.attr("/imu", "data_type", "frequency"); });
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"data_type 'frequency' is neither"}});
  c.push_back({"device_id_number",
               [v](const fs::path& p) {
                 one_channel(p, v, 100.0, [](H5Fixture& f) { f.attr("/", "device_id", 42.0); });
               },
               Outcome::FileFails,
               "/",
               {"attribute 'device_id' must be a string"}});
  // A dataset that claims more samples than any machine holds: a chunked dataset of 2^40
  // samples whose chunks were never written is a file of a few kilobytes.
  c.push_back(
      {"huge_extent",
       [](const fs::path& p) {
         H5Fixture f(p);
         f.group("/imu");
         const hsize_t n = hsize_t{1} << 40, chunk = 4096;
         const hid_t space = H5Screate_simple(1, &n, nullptr);
         const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
         H5Pset_chunk(dcpl, 1, &chunk);
         const hid_t ds = H5Dcreate2(f.id(), "/imu/gyro_x", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                     dcpl, H5P_DEFAULT);
         H5Dclose(ds);
         H5Pclose(dcpl);
         H5Sclose(space);
         f.attr("/imu", "sample_rate_hz", 100.0);
       },
       Outcome::FileFails,
       "/imu/gyro_x",
       {"1099511627776 samples need about 32768 GiB to analyse", "more than the memory limit of"}});
  // Odd but analysable: each is analysed (status 0 for its part) and its results file written.
  c.push_back({"partly_nan",
               [v](const fs::path& p) {
                 auto w = v;
                 for (std::size_t i = 100; i < 3000; i += 97)
                   w[i] = std::nan("");
                 one_channel(p, w, 100.0);
               },
               Outcome::Ok,
               "",
               {}});
  c.push_back({"constant",
               [](const fs::path& p) { one_channel(p, std::vector<double>(3000, 2.5), 100.0); },
               Outcome::Ok,
               "",
               {}});
  c.push_back({"int16_without_scale",
               [](const fs::path& p) {
                 H5Fixture f(p);
                 std::vector<double> counts(3000);
                 std::mt19937 rng(3);
                 for (auto& x : counts)
                   x = static_cast<double>(static_cast<int>(rng() % 2001) - 1000);
                 f.dataset("/adc/counts", counts, H5T_STD_I16LE);
                 f.attr("/adc", "sample_rate_hz", 50.0);
               },
               Outcome::Ok,
               "",
               {}});
  c.push_back({"uint64_big_endian",
               [](const fs::path& p) {
                 H5Fixture f(p);
                 std::vector<double> counts(3000);
                 for (std::size_t i = 0; i < counts.size(); ++i)
                   counts[i] = static_cast<double>((i * 7919) % 65536) * 1e9;
                 f.dataset("/adc/counts", counts, H5T_STD_U64BE);
                 f.attr("/adc", "sample_rate_hz", 50.0);
               },
               Outcome::Ok,
               "",
               {}});
  c.push_back({"rate_as_integer",
               [v](const fs::path& p) {
                 H5Fixture f(p);
                 f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
                 f.attr_int("/imu", "sample_rate_hz", 100);
               },
               Outcome::Ok,
               "",
               {}});
  // Sample rates beyond what double precision can carry through tau^2 fail by name; rates
  // far from the usual but inside the range (a clock compared daily, a 10 GHz digitizer) are
  // analysed.
  for (const double rate : {1e-300, 1e-10, 2e12, 1e300})
    c.push_back({"rate_" + std::to_string(static_cast<int>(std::log10(rate))),
                 [v, rate](const fs::path& p) { one_channel(p, v, rate); },
                 Outcome::FileFails,
                 "/imu/gyro_x",
                 {"is outside 1e-09 .. 1e+12 Hz"}});
  c.push_back({"rate_daily",
               [v](const fs::path& p) { one_channel(p, v, 1.0 / 86400); },
               Outcome::Ok,
               "",
               {}});
  c.push_back(
      {"rate_10GHz", [v](const fs::path& p) { one_channel(p, v, 1e10); }, Outcome::Ok, "", {}});
  c.push_back({"values_enormous",
               [v](const fs::path& p) {
                 auto w = v;
                 for (auto& x : w)
                   x *= 1e300;
                 one_channel(p, w, 100.0);
               },
               Outcome::FileFails,
               "/imu/gyro_x",
               {"overflow double precision"}});
  c.push_back({"values_tiny",
               [v](const fs::path& p) {
                 auto w = v;
                 for (auto& x : w)
                   x *= 1e-300;
                 one_channel(p, w, 100.0);
               },
               Outcome::Ok,
               "",
               {}});
  // One bad channel beside a good one: the file is analysed, the channel fails.
  c.push_back({"mixed",
               [v](const fs::path& p) {
                 H5Fixture f(p);
                 f.dataset("/imu/gyro_x", v, H5T_IEEE_F64LE);
                 auto w = v;
                 w[17] = kInf;
                 f.dataset("/imu/gyro_y", w, H5T_IEEE_F64LE);
                 f.attr("/imu", "sample_rate_hz", 100.0);
               },
               Outcome::ChannelFails,
               "/imu/gyro_y",
               {"infinite"}});
  return c;
}

// The lines of `text` that start with `prefix`.
std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

TEST(BadInputs, EachFailsAloneWithItsReasonAndTheLotGoesOn) {
  const fs::path dir = test::fresh_dir("bad_inputs");
  const fs::path in = dir / "in";
  fs::create_directories(in);
  good_unit(in / "good_a.h5", 1);
  good_unit(in / "good_b.h5", 2);
  const auto all = cases(in);
  std::map<fs::path, std::uint64_t> hashes;
  std::string args;
  for (const Case& c : all) {
    c.make(in / (c.stem + ".h5"));
    args += ' ';
    args += (in / (c.stem + ".h5")).string();
  }
  for (const auto& e : fs::directory_iterator(in))
    hashes[e.path()] = file_hash(e.path());

  const fs::path out = dir / "out";
  std::string text;
  const int rc =
      run_command(binary() + " analyze -q --taus octave -o " + out.string() + " " +
                      (in / "good_a.h5").string() + args + " " + (in / "good_b.h5").string(),
                  &text);
  EXPECT_EQ(rc, 1) << text;  // some inputs failed, the others were analysed

  // The good units, before and after every bad one, are analysed.
  for (const char* g : {"good_a", "good_b"}) {
    ASSERT_TRUE(fs::exists(out / (std::string(g) + ".allan.h5"))) << g << "\n" << text;
    EXPECT_EQ(io::read_results(out / (std::string(g) + ".allan.h5")).channels.at(0).status,
              io::ChannelStatus::ok());
  }
  const auto rows = io::read_lot_summary(out / "lot_summary.h5");
  for (const Case& c : all) {
    SCOPED_TRACE(c.stem);
    const fs::path file = in / (c.stem + ".h5");
    const fs::path results = out / (c.stem + ".allan.h5");
    if (c.outcome != Outcome::Ok) {
      const std::string where = file.string() + (c.dataset.empty() ? "" : ":" + c.dataset) + ": ";
      const auto lines = lines_starting(text, "allanlot: error: " + where);
      bool named = false;
      for (const auto& line : lines)
        for (const auto& r : c.reasons)
          named = named || line.find(r) != std::string::npos;
      EXPECT_TRUE(named) << "no message 'allanlot: error: " << where << "<reason>' in:\n" << text;
    }
    switch (c.outcome) {
    case Outcome::FileFails: {
      EXPECT_FALSE(fs::exists(results));
      bool listed = false;
      for (const auto& r : rows)
        listed = listed || (r.source_file == file.string() &&
                            io::to_string(r.status).rfind("failed: ", 0) == 0);
      EXPECT_TRUE(listed) << "no failed row in the lot summary";
      break;
    }
    case Outcome::ChannelFails:
    case Outcome::Ok: {
      ASSERT_TRUE(fs::exists(results)) << text;
      const auto r = io::read_results(results);
      for (const auto& ch : r.channels) {
        if (c.outcome == Outcome::ChannelFails && ch.path == c.dataset) {
          EXPECT_EQ(io::to_string(ch.status).rfind("failed: ", 0), 0u) << io::to_string(ch.status);
        } else {
          EXPECT_EQ(io::to_string(ch.status), "ok") << ch.path;
          for (const auto& [name, s] : ch.stats)
            for (std::size_t i = 0; i < s.size(); ++i)
              EXPECT_TRUE(std::isfinite(s.dev[i]) && s.dev[i] >= 0) << name << " row " << i;
        }
      }
      break;
    }
    }
  }
  for (const auto& [p, h] : hashes)
    EXPECT_EQ(file_hash(p), h) << p << " was modified";
  // No temporary file, probe or anything else is left behind, and nothing is written beside
  // the inputs.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
  EXPECT_EQ(std::distance(fs::directory_iterator(in), fs::directory_iterator()),
            static_cast<long>(hashes.size()));
}

}  // namespace
}  // namespace allanlot

namespace allanlot {
namespace {

// Every regular file below `dir`, with its bytes.
std::map<fs::path, std::string> tree(const fs::path& dir) {
  std::map<fs::path, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) m[e.path()] = test::file_bytes(e.path());
  return m;
}

// device_id is text from the input file: whatever it holds, the results go to OUTDIR under a
// name of [A-Za-z0-9._-] not starting with '.', and two ids that reduce to the same name make
// the second input fail rather than overwrite the first.
TEST(BadInputs, DeviceIdsNeverLeaveTheOutputDirectory) {
  const fs::path dir = test::fresh_dir("bad_device_ids");
  const fs::path in = dir / "lot" / "in";
  fs::create_directories(in);
  const std::vector<std::pair<std::string, std::string>> ids = {
      {"dotdot", "../../../outside"},
      {"absolute", "/tmp/allanlot-escape"},
      {"dot", "."},
      {"dots", ".."},
      {"hidden", ".hidden"},
      {"backslash", "..\\..\\win"},
      {"slash", "a/b"},
      {"collides_with_slash", "a_b"},
      {"non_utf8", "\xff\xfe\xc3\x28"},
      {"spaces", "  "}};
  for (std::size_t i = 0; i < ids.size(); ++i)
    one_channel(in / (ids[i].first + ".h5"), noise(2000, static_cast<unsigned>(i)), 100.0,
                [&](H5Fixture& f) { f.attr("/", "device_id", ids[i].second); });
  const auto before = tree(dir);
  std::string args;
  for (const auto& [stem, id] : ids)
    args += " " + (in / (stem + ".h5")).string();
  const fs::path out = dir / "lot" / "out";
  std::string text;
  EXPECT_EQ(
      run_command(binary() + " analyze -q --taus octave --no-psd -o " + out.string() + args, &text),
      1)
      << text;
  // a_b comes after a/b: it is the one that fails.
  EXPECT_NE(text.find("allanlot: error: " + (in / "collides_with_slash.h5").string() +
                      ": device_id 'a_b' is also the device_id of " + (in / "slash.h5").string()),
            std::string::npos)
      << text;
  // Nothing new anywhere but in OUTDIR, and nothing changed.
  for (const auto& [p, bytes] : tree(dir)) {
    if (p.string().rfind(out.string() + "/", 0) == 0) continue;
    ASSERT_TRUE(before.count(p)) << p << " was written outside OUTDIR";
    EXPECT_EQ(before.at(p), bytes) << p << " was modified";
  }
  EXPECT_FALSE(fs::exists("/tmp/allanlot-escape.allan.h5"));
  std::size_t n_results = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    EXPECT_NE(name[0], '.') << name;
    EXPECT_EQ(name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                     "0123456789._-"),
              std::string::npos)
        << name;
    if (name.ends_with(".allan.h5")) {
      ++n_results;
      // The id itself is kept as it was, in the results and the summary.
      EXPECT_NO_THROW(io::read_results(e.path())) << name;
    }
  }
  EXPECT_EQ(n_results, ids.size() - 1);
  EXPECT_TRUE(fs::exists(out / "_._.._.._outside.allan.h5"));
  EXPECT_EQ(io::read_results(out / "_._.._.._outside.allan.h5").device_id, "../../../outside");
}

// Names that are not UTF-8 (file, group, dataset, device id): the unit is analysed; group names
// keep their bytes (HDF5 names are bytes, and the input is read by them), every string allanlot
// writes is UTF-8 as its type declares, with the other bytes as \xNN (io/utf8.hpp), so that
// h5py, pandas and spreadsheets read the results and summaries.
TEST(BadInputs, NonUtf8NamesAreAnalysedAndKeptAsBytes) {
  const fs::path dir = test::fresh_dir("bad_non_utf8");
  const fs::path file = dir / "unit_\xff\xfe.h5";
  {
    H5Fixture f(file);
    f.dataset("/imu_\xe9/gyro_\xc3\x28", noise(3000, 5), H5T_IEEE_F64LE);
    f.attr("/imu_\xe9", "sample_rate_hz", 100.0);
    f.attr("/imu_\xe9", "units", "deg/\xb0s");
    f.dataset("/imu_\xe9/bad_\xff", std::vector<double>(1, 1.0), H5T_IEEE_F64LE);
  }
  const std::string bytes = test::file_bytes(file);
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -q --taus octave -o " + (dir / "out").string() + " '" +
                            file.string() + "'",
                        &text),
            1)
      << text;
  EXPECT_NE(text.find("allanlot: error: " + file.string() + ":/imu_\xe9/bad_\xff: need at least"),
            std::string::npos)
      << text;
  EXPECT_EQ(test::file_bytes(file), bytes);
  const auto r = io::read_results(dir / "out" / "unit___.allan.h5");
  EXPECT_EQ(r.device_id, "unit_\\xFF\\xFE");
  ASSERT_EQ(r.channels.size(), 2u);
  bool found = false;
  for (const auto& ch : r.channels)
    if (ch.path == "/imu_\xe9/gyro_\xc3\x28") {
      found = true;
      EXPECT_EQ(io::to_string(ch.status), "ok");
      EXPECT_EQ(ch.units, "deg/\\xB0s");
    }
  EXPECT_TRUE(found);
  const auto rows = io::read_lot_summary(dir / "out" / "lot_summary.h5");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NE(test::file_bytes(dir / "out" / "lot_summary.csv").find("/imu_\\xE9/gyro_\\xC3("),
            std::string::npos);
  EXPECT_EQ(rows[0].channel, "/imu_\\xE9/bad_\\xFF");
}

// Model and spec files with unknown keys (or otherwise wrong) are usage errors (status 2)
// naming the file and the key path, found before anything is written.
TEST(BadInputs, UnknownKeysInModelAndSpecFilesAreUsageErrors) {
  const fs::path dir = test::fresh_dir("bad_json");
  good_unit(dir / "u.h5", 3);
  {
    std::ofstream(dir / "model.json")
        << R"({"units": "deg/s", "sample_rate_hz": 100, "terms": {"N": 0.01, "ARW": 1}})";
    std::ofstream(dir / "spec.json")
        << R"j({"channels": {"gyro_*": {"N": {"max": 1, "unit": "deg/h/sqrt(Hz)", "typ": 1}}}})j";
    std::ofstream(dir / "spec_top.json")
        << R"j({"channels": {"gyro_*": {"N": {"max": 1, "unit": "deg/h/sqrt(Hz)"}}}, "colour": 1})j";
  }
  std::string text;
  EXPECT_EQ(run_command(binary() + " simulate --model " + (dir / "model.json").string() +
                            " --duration 10 -o " + (dir / "sim.h5").string(),
                        &text),
            2);
  EXPECT_NE(text.find((dir / "model.json").string() + ": terms.ARW: unknown key"),
            std::string::npos)
      << text;
  EXPECT_FALSE(fs::exists(dir / "sim.h5"));
  EXPECT_EQ(run_command(binary() + " simulate --model " + (dir / "model.json").string() +
                            " --lot 2 --duration 10 -o " + (dir / "simlot").string(),
                        &text),
            2);
  EXPECT_FALSE(fs::exists(dir / "simlot" / "unit_0001.h5"));
  const std::pair<const char*, const char*> specs[] = {{"spec.json", "channels.gyro_*.N.typ"},
                                                       {"spec_top.json", "colour"}};
  for (const auto& [name, where] : specs) {
    EXPECT_EQ(run_command(binary() + " analyze -q --spec " + (dir / name).string() + " -o " +
                              (dir / "out").string() + " " + (dir / "u.h5").string(),
                          &text),
              2);
    EXPECT_NE(text.find((dir / name).string() + ": " + where + ": unknown key"), std::string::npos)
        << text;
    EXPECT_FALSE(fs::exists(dir / "out" / "u.allan.h5"));
  }
  ASSERT_EQ(run_command(binary() + " analyze -q -o " + (dir / "out").string() + " " +
                            (dir / "u.h5").string(),
                        &text),
            0)
      << text;
  EXPECT_EQ(run_command(binary() + " summarize -q --spec " + (dir / "spec.json").string() + " " +
                            (dir / "out").string(),
                        &text),
            2);
  EXPECT_NE(text.find("channels.gyro_*.N.typ: unknown key"), std::string::npos) << text;
}

// Manifests: missing entries, an empty manifest, one that is binary junk, CRLF line ends, a
// directory listed as a recording. Each bad entry fails alone, named; the good ones are
// analysed.
TEST(BadInputs, ManifestEntriesFailAloneAndEmptyManifestsAreNamed) {
  const fs::path dir = test::fresh_dir("bad_manifests");
  good_unit(dir / "u1.h5", 1);
  good_unit(dir / "u2.h5", 2);
  fs::create_directories(dir / "adir");
  std::ofstream(dir / "lot.txt", std::ios::binary) << "u1.h5\r\n# comment\r\n\r\nmissing.h5\r\n"
                                                   << "adir\n  u2.h5\t\n";
  std::ofstream(dir / "empty.txt", std::ios::binary) << "# nothing here\n\n";
  std::ofstream(dir / "junk.txt", std::ios::binary) << std::string("\x00\x01\xff\n\x89HDF", 9);
  std::string text;
  EXPECT_EQ(run_command(binary() + " analyze -q --taus octave --no-psd -o " +
                            (dir / "out").string() + " @" + (dir / "lot.txt").string() + " @" +
                            (dir / "empty.txt").string() + " @" + (dir / "junk.txt").string() +
                            " @" + (dir / "absent.txt").string(),
                        &text),
            1)
      << text;
  EXPECT_TRUE(fs::exists(dir / "out" / "u1.allan.h5"));
  EXPECT_TRUE(fs::exists(dir / "out" / "u2.allan.h5"));
  for (const std::string& expected :
       {(dir / "missing.h5").string() + ": no such file",
        (dir / "adir").string() + ": is a directory",
        (dir / "empty.txt").string() + ": manifest lists no recording",
        (dir / "absent.txt").string() + ": cannot open manifest"})
    EXPECT_NE(text.find("allanlot: error: " + expected), std::string::npos) << expected << "\n"
                                                                            << text;
  // The junk line is a path that does not exist, named as it is.
  EXPECT_NE(text.find(": no such file"), std::string::npos) << text;
  // Only an empty manifest: nothing could be analysed, status 2, and it is named.
  EXPECT_EQ(run_command(binary() + " analyze -q -o " + (dir / "out2").string() + " @" +
                            (dir / "empty.txt").string(),
                        &text),
            2);
  EXPECT_NE(text.find("manifest lists no recording"), std::string::npos) << text;
}

}  // namespace
}  // namespace allanlot
