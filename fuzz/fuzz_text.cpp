// libFuzzer target: text recordings (io/text_recording.cpp, io/line_reader.cpp). The input is
// written as a file whose name the first byte chooses (.csv, .tsv, .dat, or .csv.gz, which
// zlib reads as plain text when it is not gzip) and read with or without the options of a
// single-column file. Reading must throw nothing but io::Error (a usage error included);
// what it returns must be whole: every channel as long as the others, a finite positive
// sample rate when the command line gave it, and paths that start with '/'.
#include "io/error.hpp"
#include "io/text_recording.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

std::filesystem::path workdir() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    auto d = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
             ("allanlot-fuzz-text." + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace allanlot;
  if (size == 0) return 0;
  static const char* const kNames[] = {"f.csv", "f.tsv", "f.dat", "f.csv.gz"};
  const std::filesystem::path file = workdir() / kNames[data[0] % 4];
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  io::InputOptions opt;
  if (data[0] & 4) {
    opt.data_type = kernels::DataType::Phase;
    opt.sample_rate_hz = 10.0;
  }
  try {
    const io::TextRecording rec = io::read_text_recording(file.string(), opt);
    if (rec.channels.empty()) std::abort();
    if (!(rec.sample_rate_hz > 0) || !std::isfinite(rec.sample_rate_hz)) {
      // Only a time column can give an unusable rate (its steps far below a second's range);
      // io::RecordingReader names it as a problem. Anything else is a bug.
      if (opt.sample_rate_hz > 0) std::abort();
    }
    for (const io::TextChannel& ch : rec.channels) {
      if (ch.path.empty() || ch.path[0] != '/') std::abort();
      if (ch.samples.size() != rec.channels[0].samples.size()) std::abort();
    }
  } catch (const io::Error&) {
    // Named problems (malformed lines, usage errors, bad gzip) are the expected outcome.
  }
  return 0;
}
