// libFuzzer target: channel discovery and attribute handling of io/hdf5_source.cpp. The input
// does not feed the HDF5 library's own file parser (that is HDF5's to fuzz, and its crashes on
// corrupt files are not ours to fix); it is a recipe: the fuzzer chooses the groups, datasets
// (type, byte order, rank, extent, values) and attributes (name, type, shape, value, where) of
// a well-formed HDF5 file, which RecordingReader then discovers and reads. Anything but
// io::Error escaping, a crash or a sanitizer report is a finding, and so is a channel that
// breaks ChannelInfo's promises (a rate within the supported range, non-zero finite scale) or a
// sanitized device id that could leave OUTDIR.
#include "io/error.hpp"
#include "io/isolation.hpp"
#include "io/recording.hpp"

#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

const std::string& file_path() {
  static const std::string path = [] {
    const char* tmp = std::getenv("TMPDIR");
    return (std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
            ("allanlot-fuzz-recording." + std::to_string(::getpid()) + ".h5"))
        .string();
  }();
  return path;
}

const char* const kNames[] = {"imu", "gyro_x", "accel_z",  "time", "timestamps",
                              "raw", "a b",    "\xff\xfe", "..",   "x"};
const char* const kAttrs[] = {"sample_rate_hz", "units",     "scale",          "offset",
                              "data_type",      "device_id", "sample_rate_hz", "other"};
const char* const kStrings[] = {"",     "rate", "phase", "deg/s",    "../../etc/passwd",
                                "/abs", ".",    "..",    "\xc3\x28", "velocity"};
constexpr double kNumbers[] = {0.0,
                               -1.0,
                               100.0,
                               1e-300,
                               1e300,
                               std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::infinity(),
                               1.0};

hid_t pick_type(FuzzedDataProvider& in) {
  const hid_t types[] = {H5T_IEEE_F64LE, H5T_IEEE_F32BE, H5T_STD_I8LE,  H5T_STD_U16BE,
                         H5T_STD_I32LE,  H5T_STD_U64LE,  H5T_STD_I64BE, H5T_IEEE_F64BE};
  return in.PickValueInArray(types);
}

// A path of 1-3 components below the root.
std::string pick_path(FuzzedDataProvider& in) {
  std::string p;
  for (int k = in.ConsumeIntegralInRange(1, 3); k > 0; --k)
    p += std::string("/") + in.PickValueInArray(kNames);
  return p;
}

void make_groups(hid_t file, const std::string& path) {
  for (std::size_t pos = path.find('/', 1); pos != std::string::npos;
       pos = path.find('/', pos + 1)) {
    const std::string g = path.substr(0, pos);
    if (H5Lexists(file, g.c_str(), H5P_DEFAULT) <= 0) {
      const hid_t id = H5Gcreate2(file, g.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      if (id >= 0) H5Gclose(id);
    }
  }
}

void add_dataset(hid_t file, FuzzedDataProvider& in) {
  const std::string path = pick_path(in);
  make_groups(file, path);
  const int rank = in.ConsumeIntegralInRange(0, 3);
  hsize_t dims[3] = {1, 1, 1};
  hsize_t total = 1;
  for (int d = 0; d < rank; ++d) {
    dims[d] = in.ConsumeIntegralInRange<hsize_t>(0, rank == 1 ? 600 : 8);
    total *= dims[d];
  }
  const bool is_string = in.ConsumeIntegralInRange(0, 7) == 0;
  const hid_t space = in.ConsumeIntegralInRange(0, 15) == 0 ? H5Screate(H5S_NULL)
                      : rank == 0                           ? H5Screate(H5S_SCALAR)
                                                            : H5Screate_simple(rank, dims, nullptr);
  hid_t type = is_string ? H5Tcopy(H5T_C_S1) : H5Tcopy(pick_type(in));
  if (is_string) H5Tset_size(type, 4);
  const hid_t ds =
      H5Dcreate2(file, path.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds >= 0 && !is_string && H5Sget_simple_extent_type(space) != H5S_NULL) {
    std::vector<double> v(total);
    for (auto& x : v)
      x = in.ConsumeBool() ? in.PickValueInArray(kNumbers) : in.ConsumeFloatingPoint<double>();
    // Out-of-range values for integer storage are clipped by HDF5's conversion: that is the
    // file's content, whatever it is.
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  }
  if (ds >= 0) H5Dclose(ds);
  H5Tclose(type);
  H5Sclose(space);
}

void add_attribute(hid_t file, FuzzedDataProvider& in) {
  // On the root, on an existing group or dataset, or (rarely) nowhere that exists.
  std::string where = in.ConsumeBool() ? "/" : pick_path(in);
  if (H5Lexists(file, where.c_str(), H5P_DEFAULT) <= 0) where = "/";
  const hid_t obj = H5Oopen(file, where.c_str(), H5P_DEFAULT);
  if (obj < 0) return;
  const std::string name = in.PickValueInArray(kAttrs);
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  const int kind = in.ConsumeIntegralInRange(0, 5);
  const hsize_t n = in.ConsumeIntegralInRange<hsize_t>(0, 3);
  const hid_t space = kind == 5          ? H5Screate(H5S_NULL)
                      : in.ConsumeBool() ? H5Screate(H5S_SCALAR)
                                         : H5Screate_simple(1, &n, nullptr);
  const hsize_t points = static_cast<hsize_t>(std::max<hssize_t>(
      H5Sget_simple_extent_type(space) == H5S_NULL ? 0 : H5Sget_simple_extent_npoints(space), 0));
  hid_t type = -1;
  if (kind <= 1 || kind == 5) {  // numbers
    type = H5Tcopy(kind == 0 ? H5T_IEEE_F64LE : pick_type(in));
    const hid_t a = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<double> v(std::max<hsize_t>(points, 1));
    for (auto& x : v)
      x = in.ConsumeBool() ? in.PickValueInArray(kNumbers) : in.ConsumeFloatingPoint<double>();
    if (a >= 0) {
      if (points > 0) H5Awrite(a, H5T_NATIVE_DOUBLE, v.data());
      H5Aclose(a);
    }
  } else if (kind == 2 || kind == 3) {  // variable- or fixed-length strings, any character set
    type = H5Tcopy(H5T_C_S1);
    const std::string s = in.ConsumeBool() ? std::string(in.PickValueInArray(kStrings))
                                           : in.ConsumeRandomLengthString(64);
    if (kind == 2) {
      H5Tset_size(type, H5T_VARIABLE);
    } else {
      H5Tset_size(type, std::max<std::size_t>(s.size(), 1));
      H5Tset_strpad(type, in.ConsumeBool() ? H5T_STR_NULLTERM : H5T_STR_NULLPAD);
    }
    if (in.ConsumeBool()) H5Tset_cset(type, H5T_CSET_UTF8);
    const hid_t a = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
      if (points > 0) {
        if (kind == 2) {
          std::vector<const char*> ptrs(points, s.c_str());
          H5Awrite(a, type, ptrs.data());
        } else {
          const std::size_t w = H5Tget_size(type);
          std::string buf(w * points, '\0');
          for (hsize_t i = 0; i < points; ++i)
            buf.replace(i * w, std::min(w, s.size()), s.substr(0, w));
          H5Awrite(a, type, buf.data());
        }
      }
      H5Aclose(a);
    }
  } else {  // a compound {double}: neither a number nor a string
    type = H5Tcreate(H5T_COMPOUND, sizeof(double));
    H5Tinsert(type, "v", 0, H5T_NATIVE_DOUBLE);
    const hid_t a = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
      const std::vector<double> zeros(std::max<hsize_t>(points, 1), 0.0);
      if (points > 0) H5Awrite(a, type, zeros.data());
      H5Aclose(a);
    }
  }
  H5Tclose(type);
  H5Sclose(space);
  H5Oclose(obj);
}

}  // namespace

// The files are well formed: allanlot's own discovery code is under test, read in this process
// so that its crashes reach the fuzzer (io/isolation.hpp would turn them into a child's error).
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  allanlot::io::read_in_process();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace allanlot;
  FuzzedDataProvider in(data, size);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  {
    const hid_t file = H5Fcreate(file_path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0) std::abort();
    for (int k = in.ConsumeIntegralInRange(0, 12); k > 0 && in.remaining_bytes() > 0; --k) {
      if (in.ConsumeBool())
        add_dataset(file, in);
      else
        add_attribute(file, in);
    }
    H5Fclose(file);
  }
  try {
    io::RecordingReader reader(file_path());
    const io::RecordingInfo& info = reader.info();
    const std::string id = io::sanitize_device_id(info.device_id);
    if (id.empty() || id[0] == '.' || id.find('/') != std::string::npos) std::abort();
    for (const io::ChannelInfo& ch : info.channels) {
      if (!(ch.sample_rate_hz >= io::kMinSampleRateHz && ch.sample_rate_hz <= io::kMaxSampleRateHz))
        std::abort();
      if (!(std::isfinite(ch.scale) && ch.scale != 0 && std::isfinite(ch.offset))) std::abort();
      if (ch.n_samples < 0) std::abort();
      try {
        const auto v = reader.read(ch, in.ConsumeIntegralInRange<std::size_t>(0, 700));
        if (v.size() != static_cast<std::size_t>(ch.n_samples)) std::abort();
      } catch (const io::Error&) {
      }
    }
  } catch (const io::Error&) {
  }
  return 0;
}
