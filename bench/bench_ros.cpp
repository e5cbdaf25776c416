// ROS 1 bag reading throughput (docs/performance.md: at least 200 MB/s on one core): a bag of
// sensor_msgs/Imu messages at 200 Hz in uncompressed chunks of 768 KiB (rosbag's default
// chunk threshold), read whole by io::RecordingReader into six channels. The bag is written
// once into ${TMPDIR:-/tmp} outside the timed loop, by the minimal writer below (format 2.0
// records as rosbag writes them, without the index, which the reader does not use).
// bytes_per_second counts the bag's bytes per second of CPU time. Argument: messages (2.9 M
// is 1 GB). `bench_ros --write-bag FILE MESSAGES` only writes a bag (for the end-to-end run of
// docs/performance.md). Run: build/bench/bench_ros --benchmark_repetitions=3
// --benchmark_report_aggregates_only=true.
#include "io/recording.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;

void put32(std::vector<char>& b, std::uint32_t v) {
  b.insert(b.end(), reinterpret_cast<const char*>(&v), reinterpret_cast<const char*>(&v) + 4);
}

void field(std::vector<char>& h, const std::string& name, const void* value, std::size_t n) {
  put32(h, static_cast<std::uint32_t>(name.size() + 1 + n));
  h.insert(h.end(), name.begin(), name.end());
  h.push_back('=');
  h.insert(h.end(), static_cast<const char*>(value), static_cast<const char*>(value) + n);
}

void record(std::vector<char>& out, const std::vector<char>& header,
            const std::vector<char>& data) {
  put32(out, static_cast<std::uint32_t>(header.size()));
  out.insert(out.end(), header.begin(), header.end());
  put32(out, static_cast<std::uint32_t>(data.size()));
  out.insert(out.end(), data.begin(), data.end());
}

std::vector<char> connection() {
  std::vector<char> h, d;
  const char op = 7;
  const std::uint32_t conn = 0;
  const std::string topic = "/imu", type = "sensor_msgs/Imu";
  field(h, "op", &op, 1);
  field(h, "conn", &conn, 4);
  field(h, "topic", topic.data(), topic.size());
  field(d, "topic", topic.data(), topic.size());
  field(d, "type", type.data(), type.size());
  std::vector<char> out;
  record(out, h, d);
  return out;
}

// One Imu message at sample i (ROS 1 serialization) as a message data record.
void message(std::vector<char>& out, std::int64_t i, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 0.01);
  const std::int64_t ns = 1700000000000000000 + i * 5000000;
  const auto sec = static_cast<std::uint32_t>(ns / 1000000000);
  const auto nsec = static_cast<std::uint32_t>(ns % 1000000000);
  std::vector<char> h, d;
  const char op = 2;
  const std::uint32_t conn = 0;
  const std::uint64_t time = sec | (std::uint64_t{nsec} << 32);
  field(h, "op", &op, 1);
  field(h, "conn", &conn, 4);
  field(h, "time", &time, 8);
  put32(d, static_cast<std::uint32_t>(i));
  put32(d, sec);
  put32(d, nsec);
  put32(d, 8);
  d.insert(d.end(), {'i', 'm', 'u', '_', 'l', 'i', 'n', 'k'});
  double v[37] = {0, 0, 0, 1};
  for (int k = 0; k < 3; ++k) {
    v[13 + k] = g(rng);
    v[25 + k] = g(rng) + (k == 2 ? 9.81 : 0);
  }
  d.insert(d.end(), reinterpret_cast<const char*>(v), reinterpret_cast<const char*>(v) + sizeof v);
  record(out, h, d);
}

// Writes `messages` messages; returns the bag's size in bytes.
std::uintmax_t write_bag(const fs::path& p, std::int64_t messages) {
  std::FILE* f = std::fopen(p.c_str(), "wb");
  std::fputs("#ROSBAG V2.0\n", f);
  std::vector<char> head;
  std::vector<char> out;
  const char op3 = 3;
  field(head, "op", &op3, 1);
  record(out, head, std::vector<char>(4096 - 13 - 8 - head.size(), ' '));
  std::fwrite(out.data(), 1, out.size(), f);
  std::mt19937_64 rng(7);
  const std::vector<char> conn = connection();
  for (std::int64_t i = 0; i < messages;) {
    std::vector<char> chunk = conn;
    while (chunk.size() < 768 * 1024 && i < messages)
      message(chunk, i++, rng);
    std::vector<char> h, rec;
    const char op = 5;
    const std::string none = "none";
    const auto size = static_cast<std::uint32_t>(chunk.size());
    field(h, "op", &op, 1);
    field(h, "compression", none.data(), none.size());
    field(h, "size", &size, 4);
    record(rec, h, chunk);
    std::fwrite(rec.data(), 1, rec.size(), f);
  }
  std::fclose(f);
  return fs::file_size(p);
}

void BM_ReadBag(benchmark::State& state) {
  const char* t = std::getenv("TMPDIR");
  const fs::path bag =
      fs::path(t ? t : "/tmp") / ("allanlot-bench-ros." + std::to_string(::getpid()) + ".bag");
  const std::uintmax_t bytes = write_bag(bag, state.range(0));
  for (auto _ : state) {
    const allanlot::io::RecordingReader r(bag.string());
    benchmark::DoNotOptimize(r.info().channels.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
  fs::remove(bag);
}
BENCHMARK(BM_ReadBag)->Arg(290000)->Arg(2900000)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::strcmp(argv[1], "--write-bag") == 0) {
    const std::uintmax_t bytes = write_bag(argv[2], std::atoll(argv[3]));
    std::printf("%s: %s messages, %ju bytes\n", argv[2], argv[3], bytes);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
