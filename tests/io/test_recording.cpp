// Channel discovery (docs/formats.md "Input recordings"), chunked reads of every storage type, and
// the writer that `simulate` uses.
#include "io/error.hpp"
#include "io/recording.hpp"
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sys/stat.h>

namespace allanlot {
namespace {

using test::H5Fixture;

const io::ChannelInfo* find(const io::RecordingInfo& info, const std::string& path) {
  for (const auto& c : info.channels)
    if (c.path == path) return &c;
  return nullptr;
}

std::string problem(const io::RecordingInfo& info, const std::string& path) {
  for (const auto& p : info.problems)
    if (p.path == path) return p.reason;
  return "";
}

// The one rule of channel globs: the path or the name.
TEST(Recording, ChannelGlobsMatchThePathOrTheName) {
  EXPECT_TRUE(io::channel_glob_matches("", "/imu/temp"));
  EXPECT_TRUE(io::channel_glob_matches("gyro_*", "/imu/gyro_x"));
  EXPECT_TRUE(io::channel_glob_matches("/imu/*", "/imu/gyro_x"));
  EXPECT_TRUE(io::channel_glob_matches("gyro_[xy]", "/gyro_y"));
  EXPECT_FALSE(io::channel_glob_matches("gyro_[xy]", "/gyro_z"));
  EXPECT_FALSE(io::channel_glob_matches("imu", "/imu/gyro_x"));
  EXPECT_FALSE(io::channel_glob_matches("accel_*", "/imu/gyro_x"));
}

TEST(Recording, DiscoversChannelsWithAncestorLookup) {
  const auto dir = test::fresh_dir("discover");
  const auto file = dir / "unit7.h5";
  {
    H5Fixture f(file);
    f.dataset("/imu/gyro_x", {1, 2, 3, 4}, H5T_IEEE_F64LE);
    f.dataset("/imu/accel_z", {1, 2, 3, 4}, H5T_IEEE_F32LE);
    f.dataset("/imu/time", {0, 1, 2, 3}, H5T_IEEE_F64LE);
    f.dataset("/imu/raw/counts", {100, -200, 300, 400}, H5T_STD_I16LE);
    f.dataset("/clock/phase", {1, 2, 3, 4, 5}, H5T_STD_I32LE);
    f.dataset("/other/no_rate", {1, 2, 3}, H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 1000.0);
    f.attr("/imu", "units", "deg/s");
    f.attr("/imu/accel_z", "units", "m/s^2");
    f.attr("/imu/raw", "units", "counts-as-g");
    f.attr("/imu/raw/counts", "scale", 0.5);
    f.attr("/imu/raw/counts", "offset", 10.0);
    f.attr("/clock/phase", "sample_rate_hz", 1.0);
    f.attr("/clock", "data_type", "phase");
    f.attr("/", "device_id", "SN-0042");
  }
  io::RecordingReader r(file.string());
  const auto& info = r.info();
  EXPECT_EQ(info.device_id, "SN-0042");
  EXPECT_TRUE(info.problems.empty());
  ASSERT_EQ(info.channels.size(), 4u);  // time and the dataset without a rate are not channels
  const auto* gx = find(info, "/imu/gyro_x");
  ASSERT_NE(gx, nullptr);
  EXPECT_EQ(gx->units, "deg/s");
  EXPECT_EQ(gx->sample_rate_hz, 1000.0);
  EXPECT_EQ(gx->storage_type, "float64");
  EXPECT_EQ(gx->n_samples, 4);
  const auto* az = find(info, "/imu/accel_z");
  ASSERT_NE(az, nullptr);
  EXPECT_EQ(az->units, "m/s^2");  // the dataset's own attribute wins over the ancestor's
  EXPECT_EQ(az->storage_type, "float32");
  const auto* counts = find(info, "/imu/raw/counts");
  ASSERT_NE(counts, nullptr);
  EXPECT_EQ(counts->units, "counts-as-g");
  EXPECT_EQ(counts->storage_type, "int16");
  EXPECT_EQ(test::as_vector(r.read(*counts)),
            (std::vector<double>{60, -90, 160, 210}));  // raw * 0.5 + 10
  const auto* ph = find(info, "/clock/phase");
  ASSERT_NE(ph, nullptr);
  EXPECT_EQ(ph->data_type, kernels::DataType::Phase);
  EXPECT_EQ(ph->storage_type, "int32");
  EXPECT_EQ(test::as_vector(r.read(*ph)), (std::vector<double>{1, 2, 3, 4, 5}));
}

TEST(Recording, ChunkedReadEqualsWholeRead) {
  const auto dir = test::fresh_dir("chunked");
  const auto file = dir / "a.h5";
  std::vector<double> v(10007);
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = std::sin(0.01 * static_cast<double>(i));
  v[17] = std::nan("");
  {
    H5Fixture f(file);
    f.dataset("/d/x", v, H5T_IEEE_F64LE);
    f.attr("/d/x", "sample_rate_hz", 10.0);
  }
  io::RecordingReader r(file.string());
  ASSERT_EQ(r.info().channels.size(), 1u);
  const auto whole = r.read(r.info().channels[0], 1 << 20);
  const auto chunked = r.read(r.info().channels[0], 1000);
  ASSERT_EQ(whole.size(), v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::isnan(v[i])) {
      EXPECT_TRUE(std::isnan(whole[i]) && std::isnan(chunked[i]));
    } else {
      EXPECT_EQ(whole[i], v[i]);
      EXPECT_EQ(chunked[i], v[i]);
    }
  }
  EXPECT_EQ(r.info().device_id, "a");  // no device_id attribute: the file's stem
}

// A recording truncated after it was opened (still being copied, a full disk) reads as zeros
// past its new end without an HDF5 error: the reader must say so, naming file and channel
// (else the tail would be analysed as zeros).
TEST(Recording, TruncatedWhileItIsReadIsAnError) {
  const auto file = test::fresh_dir("truncated_while_read") / "a.h5";
  {
    H5Fixture f(file);
    f.dataset("/d/x", std::vector<double>(100000, 1.5), H5T_IEEE_F64LE);
    f.attr("/d/x", "sample_rate_hz", 10.0);
  }
  io::RecordingReader r(file.string());
  ASSERT_EQ(r.info().channels.size(), 1u);
  EXPECT_NO_THROW(r.read(r.info().channels[0]));
  std::filesystem::resize_file(file, std::filesystem::file_size(file) / 2);
  try {
    r.read(r.info().channels[0]);
    ADD_FAILURE() << "a truncated recording was read";
  } catch (const io::Error& e) {
    EXPECT_EQ(e.dataset(), "/d/x");
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find("truncated while it was read"), std::string::npos) << e.what();
  }
}

// A dataset that declares more samples than it stores (never written) would read as zeros,
// after allocating all it declares: refused first, naming file and channel.
TEST(Recording, DeclaredButUnwrittenSamplesAreRefused) {
  const auto file = test::fresh_dir("declared_unwritten") / "a.h5";
  {
    H5Fixture f(file);
    f.dataset("/d/x", {}, H5T_IEEE_F32LE, {300000000});
    f.attr("/d/x", "sample_rate_hz", 10.0);
  }
  EXPECT_LT(std::filesystem::file_size(file), 10000u);
  io::RecordingReader r(file.string());
  ASSERT_EQ(r.info().channels.size(), 1u);
  try {
    r.read(r.info().channels[0]);
    ADD_FAILURE() << "an unwritten dataset was read";
  } catch (const io::Error& e) {
    EXPECT_EQ(e.dataset(), "/d/x");
    EXPECT_NE(e.reason().find("declares 300000000 samples but stores only 0"), std::string::npos)
        << e.what();
  }
}

TEST(Recording, BadAttributesAndShapesAreNamedProblems) {
  const auto dir = test::fresh_dir("badattr");
  const auto file = dir / "bad.h5";
  {
    H5Fixture f(file);
    f.dataset("/a/zero_rate", {1, 2, 3}, H5T_IEEE_F64LE);
    f.attr("/a/zero_rate", "sample_rate_hz", 0.0);
    f.dataset("/a/nan_rate", {1, 2, 3}, H5T_IEEE_F64LE);
    f.attr("/a/nan_rate", "sample_rate_hz", std::nan(""));
    f.dataset("/a/string_rate", {1, 2, 3}, H5T_IEEE_F64LE);
    f.attr("/a/string_rate", "sample_rate_hz", "fast");
    f.dataset("/a/two_d", {1, 2, 3, 4}, H5T_IEEE_F64LE, {2, 2});
    f.attr("/a/two_d", "sample_rate_hz", 1.0);
    f.string_dataset("/a/labels", {"x", "y"});
    f.attr("/a/labels", "sample_rate_hz", 1.0);
    f.dataset("/a/odd_type", {1, 2, 3}, H5T_IEEE_F64LE);
    f.attr("/a/odd_type", "sample_rate_hz", 1.0);
    f.attr("/a/odd_type", "data_type", "velocity");
  }
  io::RecordingReader r(file.string());
  EXPECT_TRUE(r.info().channels.empty());
  EXPECT_NE(problem(r.info(), "/a/zero_rate").find("sample_rate_hz = 0"), std::string::npos);
  EXPECT_NE(problem(r.info(), "/a/nan_rate").find("sample_rate_hz"), std::string::npos);
  EXPECT_NE(problem(r.info(), "/a/string_rate").find("must be a number"), std::string::npos);
  EXPECT_NE(problem(r.info(), "/a/two_d").find("2 dimensions"), std::string::npos);
  EXPECT_NE(problem(r.info(), "/a/labels").find("string"), std::string::npos);
  EXPECT_NE(problem(r.info(), "/a/odd_type").find("velocity"), std::string::npos);
}

TEST(Recording, UnreadableFilesThrowWithTheFileName) {
  const auto dir = test::fresh_dir("unreadable");
  const auto junk = dir / "junk.h5";
  { std::ofstream(junk) << "this is not HDF5"; }
  const auto empty = dir / "empty.h5";
  { std::ofstream(empty).flush(); }
  for (const auto& p : {junk, empty, dir / "missing.h5", dir}) {
    try {
      io::RecordingReader r(p.string());
      ADD_FAILURE() << "no error for " << p;
    } catch (const io::Error& e) {
      EXPECT_EQ(e.file(), p.string());
      EXPECT_FALSE(e.reason().empty());
    }
  }
  // A truncated HDF5 file: a valid recording cut in half.
  const auto good = dir / "good.h5";
  {
    H5Fixture f(good);
    f.dataset("/imu/x", std::vector<double>(50000, 1.0), H5T_IEEE_F64LE);
    f.attr("/imu", "sample_rate_hz", 100.0);
  }
  const std::string bytes = test::file_bytes(good);
  const auto cut = dir / "cut.h5";
  std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size() / 2));
  try {
    io::RecordingReader r(cut.string());
    ASSERT_EQ(r.info().channels.size(), 1u);
    r.read(r.info().channels[0]);
    ADD_FAILURE() << "truncated file read without error";
  } catch (const io::Error& e) {
    EXPECT_EQ(e.file(), cut.string());
  }
}

TEST(Recording, WriterProducesTheSimulateLayoutAtomically) {
  const auto dir = test::fresh_dir("writer");
  const auto file = dir / "sim.h5";
  const std::vector<double> x = {1.5, 2.5, 3.5};
  {
    io::RecordingWriter w(file.string(), "unit-1", 250.0);
    w.add_channel({"gyro_x", "deg/s", x});
    EXPECT_FALSE(std::filesystem::exists(file));  // not visible before commit
    w.commit();
  }
  io::RecordingReader r(file.string());
  ASSERT_EQ(r.info().channels.size(), 1u);
  EXPECT_EQ(r.info().device_id, "unit-1");
  EXPECT_EQ(r.info().channels[0].path, "/imu/gyro_x");
  EXPECT_EQ(r.info().channels[0].units, "deg/s");
  EXPECT_EQ(r.info().channels[0].sample_rate_hz, 250.0);
  EXPECT_EQ(test::as_vector(r.read(r.info().channels[0])), x);
  {
    io::RecordingWriter w((dir / "abandoned.h5").string(), "u", 1.0);
    w.add_channel({"gyro_x", "deg/s", x});
  }  // destroyed without commit: nothing left behind
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "sim.h5");
}

// A recording whose /gyro_x keeps its 100 float64 samples in the external file `target`.
void external_recording(const std::filesystem::path& file, const std::string& target) {
  const hid_t f = H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t n = 100;
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_external(dcpl, target.c_str(), 0, n * sizeof(double));
  const hid_t ds = H5Dcreate2(f, "gyro_x", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  const double rate = 10.0;
  const hid_t aspace = H5Screate(H5S_SCALAR);
  const hid_t a =
      H5Acreate2(ds, "sample_rate_hz", H5T_IEEE_F64LE, aspace, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_DOUBLE, &rate);
  H5Aclose(a);
  H5Sclose(aspace);
  H5Dclose(ds);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Fclose(f);
}

// External raw storage (H5Pset_external) is read only from a regular file beside the recording:
// a FIFO would hang the read, /etc/shadow or /dev/urandom would be read as samples.
TEST(Recording, ExternalRawDataOnlyFromARegularFileBesideTheRecording) {
  const auto dir = test::fresh_dir("external_storage");
  {
    std::vector<double> v(100);
    for (std::size_t i = 0; i < v.size(); ++i)
      v[i] = static_cast<double>(i);
    std::ofstream(dir / "samples.raw", std::ios::binary)
        .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(800));
  }
  ASSERT_EQ(::mkfifo((dir / "pipe.raw").c_str(), 0600), 0);
  std::filesystem::create_symlink("/dev/urandom", dir / "link.raw");
  external_recording(dir / "good.h5", (dir / "samples.raw").string());
  {
    const io::RecordingReader r((dir / "good.h5").string());
    ASSERT_EQ(r.info().channels.size(), 1u);
    const auto x = r.read(r.info().channels[0]);
    EXPECT_EQ(x[99], 99.0);
  }
  const std::pair<const char*, const char*> bad[] = {{"fifo.h5", "pipe.raw"},
                                                     {"device.h5", "/dev/urandom"},
                                                     {"shadow.h5", "/etc/shadow"},
                                                     {"up.h5", "../samples.raw"},
                                                     {"link.h5", "link.raw"},
                                                     {"missing.h5", "missing.raw"},
                                                     {"elsewhere.h5", "/proc/self/environ"}};
  for (const auto& [name, target] : bad) {
    // Names of files in `dir` as the library resolves them (from the working directory).
    const std::string t = std::string(target).ends_with(".raw") && target[0] != '.'
                              ? (dir / target).string()
                              : std::string(target);
    external_recording(dir / name, t);
    const io::RecordingReader r((dir / name).string());
    EXPECT_TRUE(r.info().channels.empty()) << name;
    EXPECT_NE(problem(r.info(), "/gyro_x").find("external file"), std::string::npos)
        << name << ": " << problem(r.info(), "/gyro_x");
  }
}

// A recording whose /imu/gyro_x is a virtual dataset mapping `source`:/d, 100 doubles; with
// `source` "." the source is /d of the same file.
void virtual_recording(const std::filesystem::path& file, const std::string& source) {
  const hsize_t n = 100;
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const std::vector<double> v(n, 1.0);
  const auto write_d = [&](hid_t f) {
    const hid_t d =
        H5Dcreate2(f, "d", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(d);
  };
  if (source != ".") {
    const hid_t s =
        H5Fcreate((file.parent_path() / source).c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    write_d(s);
    H5Fclose(s);
  }
  const hid_t f = H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (source == ".") write_d(f);
  const hid_t g = H5Gcreate2(f, "imu", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const double rate = 10.0;
  const hid_t aspace = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(g, "sample_rate_hz", H5T_IEEE_F64LE, aspace, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_DOUBLE, &rate);
  H5Aclose(a);
  H5Sclose(aspace);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_virtual(dcpl, space, source.c_str(), "/d", space);
  const hid_t ds = H5Dcreate2(g, "gyro_x", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Dclose(ds);
  H5Pclose(dcpl);
  H5Gclose(g);
  H5Sclose(space);
  H5Fclose(f);
}

// A virtual dataset (HDF5 VDS) is refused by name, with its first source: its sources are HDF5
// files nothing has checked, and a missing one reads as zeros without an error.
TEST(Recording, AVirtualDatasetIsRefusedByName) {
  const auto dir = test::fresh_dir("virtual_dataset");
  for (const std::string source : {"source.h5", "."}) {
    const auto file = dir / (source == "." ? "same.h5" : "vds.h5");
    virtual_recording(file, source);
    const io::RecordingReader r(file.string());
    EXPECT_TRUE(r.info().channels.empty()) << source;
    EXPECT_EQ(problem(r.info(), "/imu/gyro_x"),
              "a virtual dataset (HDF5 VDS) of 1 source(s), the first '" + source +
                  ":/d': not read, as its sources are HDF5 files nothing has checked and a "
                  "missing one reads as zeros without an error; copy it into a regular dataset "
                  "(h5repack -l /imu/gyro_x:CONTI) to analyse it");
  }
}

void put_attribute(hid_t obj, const char* name, double value) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(obj, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_DOUBLE, &value);
  H5Aclose(a);
  H5Sclose(space);
}

void put_attribute(hid_t obj, const char* name, const std::string& value) {
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, value.size() + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(obj, name, t, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, t, value.c_str());
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(t);
}

// 2000 nested groups: the channel at the bottom is discovered with the attributes of its
// ancestors (sample_rate_hz on the root, units half-way), each lookup opening the chain from the
// root once (linear in the depth: bench figures in docs/reliability.md).
TEST(Recording, DeeplyNestedGroupsAreWalkedOnce) {
  const auto dir = test::fresh_dir("deep_groups");
  const auto file = dir / "deep.h5";
  constexpr int kDepth = 2000;
  std::string channel;
  {
    const hid_t f = H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    put_attribute(f, "sample_rate_hz", 50.0);
    hid_t g = H5Gopen2(f, "/", H5P_DEFAULT);
    for (int i = 0; i < kDepth; ++i) {
      const hid_t next = H5Gcreate2(g, "g", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      H5Gclose(g);
      g = next;
      channel += "/g";
      if (i == kDepth / 2) put_attribute(g, "units", std::string("deg/s"));
    }
    const std::vector<double> v(64, 1.0);
    const hsize_t n = v.size();
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t ds =
        H5Dcreate2(g, "x", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(ds);
    H5Sclose(space);
    H5Gclose(g);
    H5Fclose(f);
    channel += "/x";
  }
  const io::RecordingReader r(file.string());
  const io::ChannelInfo* ch = find(r.info(), channel);
  ASSERT_NE(ch, nullptr);
  EXPECT_EQ(ch->sample_rate_hz, 50.0);
  EXPECT_EQ(ch->units, "deg/s");
  EXPECT_EQ(ch->n_samples, 64);
}

TEST(Recording, DeviceIdsAreSanitized) {
  EXPECT_EQ(io::sanitize_device_id("SN-00.42_a"), "SN-00.42_a");
  EXPECT_EQ(io::sanitize_device_id("../../etc/passwd"), "_._.._etc_passwd");
  EXPECT_EQ(io::sanitize_device_id(".."), "_.");
  EXPECT_EQ(io::sanitize_device_id(""), "_");
  EXPECT_EQ(io::sanitize_device_id("a b/c\\d"), "a_b_c_d");
  EXPECT_EQ(io::sanitize_device_id("\xc3\xa9t\xff"), "\xc3\xa9t_");  // é kept, 0xff not
}

}  // namespace
}  // namespace allanlot
