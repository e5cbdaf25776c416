// `allanlot watch` following an HDF5 recording that a writer extends in SWMR mode (HDF5's single
// writer, multiple readers): the writer here appends a simulated channel in batches while the
// command watches; a unit far inside its B limit is decided pass at the first look.
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace allanlot {
namespace {

namespace fs = std::filesystem;

// The recording layout (docs/formats.md): /imu with sample_rate_hz, /imu/gyro_x with units,
// created empty and extensible, then opened to SWMR readers.
struct SwmrWriter {
  hid_t file = -1, group = -1, dataset = -1;
  hsize_t written = 0;

  explicit SwmrWriter(const std::string& path) {
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    H5Pclose(fapl);
    group = H5Gcreate2(file, "imu", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const double rate = 1.0;
    const hid_t scalar = H5Screate(H5S_SCALAR);
    const hid_t a =
        H5Acreate2(group, "sample_rate_hz", H5T_IEEE_F64LE, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, &rate);
    H5Aclose(a);
    const hsize_t dims = 0, maxdims = H5S_UNLIMITED, chunk = 1000;
    const hid_t space = H5Screate_simple(1, &dims, &maxdims);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, &chunk);
    dataset = H5Dcreate2(group, "gyro_x", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    H5Pclose(dcpl);
    H5Sclose(space);
    const std::string units = "deg/s";
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, units.size() + 1);
    const hid_t u = H5Acreate2(dataset, "units", t, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(u, t, units.c_str());
    H5Aclose(u);
    H5Tclose(t);
    H5Sclose(scalar);
    H5Fstart_swmr_write(file);
  }

  void append(const double* y, hsize_t n) {
    const hsize_t size = written + n;
    H5Dset_extent(dataset, &size);
    const hid_t fspace = H5Dget_space(dataset);
    H5Sselect_hyperslab(fspace, H5S_SELECT_SET, &written, nullptr, &n, nullptr);
    const hid_t mspace = H5Screate_simple(1, &n, nullptr);
    H5Dwrite(dataset, H5T_NATIVE_DOUBLE, mspace, fspace, H5P_DEFAULT, y);
    H5Sclose(mspace);
    H5Sclose(fspace);
    H5Dflush(dataset);
    written = size;
  }

  ~SwmrWriter() {
    H5Dclose(dataset);
    H5Gclose(group);
    H5Fclose(file);
  }
};

TEST(WatchSwmr, FollowsADatasetExtendedBySwmrWriter) {
  const fs::path dir = fs::path(ALLANLOT_TEST_TMP) / "watch_swmr";
  fs::create_directories(dir);
  const std::string spec = (dir / "spec.json").string();
  std::ofstream(spec) << R"({"channels": {"gyro_*": {"B": {"max": 0.001, "unit": "deg/s"}}}})";
  kernels::ChannelSpec s;
  s.rate_hz = 1.0;
  s.terms = {0, 0.0001, 0.0004, 0.001, 0};
  std::vector<double> y(12000);
  kernels::simulate_channel(s, 5, 0, y, 1);
  const std::string h5 = (dir / "unit.h5").string();
  auto writer = std::make_unique<SwmrWriter>(h5);
  // 3000 samples (50 min of data) every 100 ms; the writer holds the file open throughout.
  std::thread feed([&] {
    for (std::size_t i = 0; i < y.size(); i += 3000) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      writer->append(y.data() + i, 3000);
    }
  });
  const std::string log = (dir / "watch.log").string();
  const int rc = std::system((std::string(ALLANLOT_BINARY) + " watch " + h5 + " --spec " + spec +
                              " --interval 3000 --max-duration 12000 --poll 0.02 "
                              "--idle-timeout 20 --threads 1 > " +
                              log + " 2>&1")
                                 .c_str());
  feed.join();
  writer.reset();
  std::stringstream out;
  out << std::ifstream(log).rdbuf();
  EXPECT_EQ(WEXITSTATUS(rc), 0) << out.str();
  EXPECT_NE(out.str().find("look 1 at 3000 s"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("unit passes"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace allanlot
