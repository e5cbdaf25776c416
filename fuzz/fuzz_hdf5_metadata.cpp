// libFuzzer target: hostile bytes in a recording's HDF5 metadata, read under the isolation of
// io/isolation.hpp as every input recording is. The input is a list of patches (offset, up to
// 16 bytes) applied to a small recording in the layout `allanlot simulate` writes (variable-
// length string attributes in the global heap, a contiguous and a chunked, compressed channel);
// the patched file is discovered and each channel read, all in the child. The HDF5 library may
// crash, loop or allocate on such bytes (its own parser is HDF5's to fuzz); what is under test
// is that nothing of it reaches the process: every outcome is a return or an io::Error naming
// the file. A crash, a hang or a sanitizer report of this process is a finding. (A child that
// asks the allocator for more than -rss_limit_mb still meets libFuzzer's malloc hook, which
// leaves an "oom-" file in artifacts/ and ends the child, not the run.)
#include "io/error.hpp"
#include "io/isolation.hpp"
#include "io/recording.hpp"

#include <fuzzer/FuzzedDataProvider.h>
#include <sanitizer/common_interface_defs.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

std::filesystem::path temp_path(const std::string& name) {
  const char* tmp = std::getenv("TMPDIR");
  return std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
         ("allanlot-fuzz-hdf5-metadata." + std::to_string(::getpid()) + "." + name);
}

// The recording every input patches, written once.
const std::string& template_bytes() {
  static const std::string bytes = [] {
    const std::filesystem::path p = temp_path("template.h5");
    std::vector<double> v(300);
    for (std::size_t i = 0; i < v.size(); ++i)
      v[i] = static_cast<double>(i % 17) * 0.01;
    {
      allanlot::io::RecordingWriter w(p.string(), "unit-7", 100.0);
      w.add_channel({"gyro_x", "deg/s", v}, {"rate", 0.0});
      w.set_deflate(4);
      w.add_channel({"accel_z", "m/s^2", v}, {"", 100.0});
      w.add_root_attribute("operator", "station 3");
      w.commit();
    }
    std::ifstream in(p, std::ios::binary);
    std::string b{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::filesystem::remove(p);
    return b;
  }();
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string bytes = template_bytes();
  FuzzedDataProvider in(data, size);
  while (in.remaining_bytes() > 0) {
    const auto at = in.ConsumeIntegralInRange<std::size_t>(0, bytes.size() - 1);
    const std::string patch = in.ConsumeBytesAsString(in.ConsumeIntegralInRange(1, 16));
    for (std::size_t i = 0; i < patch.size() && at + i < bytes.size(); ++i)
      bytes[at + i] = patch[i];
  }
  const std::string path = temp_path("input.h5").string();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  // Bounds below libFuzzer's -timeout and -rss_limit_mb, so that a child the bounds end is an
  // io::Error here, not a finding of libFuzzer's.
  allanlot::io::IsolationLimits limits;
  limits.cpu = std::chrono::seconds(3);
  limits.wall = std::chrono::seconds(5);
  limits.extra_address_space = std::uint64_t{512} << 20;
  try {
    allanlot::io::run_isolated(
        path,
        [&] {
          // In the child, a sanitizer's report on the library's own code (it copies overlapping
          // ranges on some damaged files) ends the child like any crash; libFuzzer's death
          // callback, inherited from this process, would file it as a crash of its own.
          __sanitizer_set_death_callback(nullptr);
          const allanlot::io::RecordingReader reader(path);
          for (const allanlot::io::ChannelInfo& ch : reader.info().channels)
            reader.read(ch);
        },
        limits);
  } catch (const allanlot::io::Error& e) {
    if (e.file() != path) std::abort();  // every error names the file
  }
  return 0;
}
