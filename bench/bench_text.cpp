// Text recording parser throughput (the aim: at least 50 MB/s of CSV on one core): a CSV
// in an IMU logger's shape (a time column in ms since the epoch, six channels with units in
// the header, 400 Hz) and a single-column phase file, plain and gzipped, read whole by
// io::read_text_recording into the channels' doubles. The files are written once into
// ${TMPDIR:-/tmp} outside the timed loop. bytes_per_second counts the uncompressed text;
// the counter peak_over_doubles is the growth of the peak resident memory during one read
// divided by the bytes of the doubles it returns (1.0: nothing but the result held).
// Argument: rows. Run: build/bench/bench_text --benchmark_repetitions=3
// --benchmark_report_aggregates_only=true (or through bench/run-all).
#include "io/text_recording.hpp"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const char* t = std::getenv("TMPDIR");
  const fs::path d =
      fs::path(t ? t : "/tmp") / ("allanlot-bench-text." + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// Writes `rows` rows; returns the file's size in bytes.
std::uintmax_t write_csv(const fs::path& p, std::int64_t rows) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::FILE* f = std::fopen(p.c_str(), "w");
  std::fputs("timestamp [ms],gx [deg/s],gy [deg/s],gz [deg/s],ax [m/s^2],ay [m/s^2],az [m/s^2]\n",
             f);
  for (std::int64_t i = 0; i < rows; ++i)
    std::fprintf(f, "%.1f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", 1.7e12 + 2.5 * static_cast<double>(i),
                 0.01 * g(rng), 0.01 * g(rng), 0.01 * g(rng), 0.02 * g(rng), 0.02 * g(rng),
                 9.80665 + 0.02 * g(rng));
  std::fclose(f);
  return fs::file_size(p);
}

std::uintmax_t write_column(const fs::path& p, std::int64_t rows) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::FILE* f = std::fopen(p.c_str(), "w");
  std::fputs("# phase, s\n", f);
  double x = 0;
  for (std::int64_t i = 0; i < rows; ++i) {
    x += 1e-9 * g(rng);
    std::fprintf(f, "%.15e\n", x);
  }
  std::fclose(f);
  return fs::file_size(p);
}

// Peak resident memory (VmHWM) in bytes; reset_peak() starts a new peak (Linux clear_refs 5).
std::int64_t peak_rss() {
  std::ifstream s("/proc/self/status");
  for (std::string line; std::getline(s, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stoll(line.substr(6)) * 1024;
  return 0;
}
void reset_peak() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

void run(benchmark::State& state, const fs::path& file, std::uintmax_t text_bytes,
         const allanlot::io::InputOptions& opt) {
  double ratio = 0;
  for (auto _ : state) {
    reset_peak();
    const std::int64_t before = peak_rss();
    const auto rec = allanlot::io::read_text_recording(file.string(), opt);
    std::int64_t doubles = 0;
    for (const auto& ch : rec.channels)
      doubles += static_cast<std::int64_t>(ch.samples.size() * sizeof(double));
    ratio = static_cast<double>(peak_rss() - before) / static_cast<double>(doubles);
    benchmark::DoNotOptimize(rec.channels.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text_bytes));
  state.counters["peak_over_doubles"] = ratio;
}

void BM_ReadCsv(benchmark::State& state, bool gz) {
  const fs::path dir = temp_dir();
  const fs::path csv = dir / "unit.csv";
  const std::uintmax_t bytes = write_csv(csv, state.range(0));
  fs::path file = csv;
  if (gz) {
    const std::string cmd = "gzip -1 -kf '" + csv.string() + "'";
    if (std::system(cmd.c_str()) != 0) state.SkipWithError("gzip failed");
    file = dir / "unit.csv.gz";
  }
  run(state, file, bytes, {});
  fs::remove_all(dir);
}

void BM_ReadSingleColumn(benchmark::State& state) {
  const fs::path dir = temp_dir();
  const fs::path file = dir / "phase.dat";
  const std::uintmax_t bytes = write_column(file, state.range(0));
  allanlot::io::InputOptions opt;
  opt.data_type = allanlot::kernels::DataType::Phase;
  opt.sample_rate_hz = 1.0;
  run(state, file, bytes, opt);
  fs::remove_all(dir);
}

}  // namespace

// 20 minutes of the 400 Hz log (480 000 rows, about 40 MB) and 4 M phase points (about 90 MB).
BENCHMARK_CAPTURE(BM_ReadCsv, plain, false)->Arg(480000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadCsv, gzip, true)->Arg(480000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadSingleColumn)->Arg(4000000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
