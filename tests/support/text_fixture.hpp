// Test-only text recordings: a CSV written the way an IMU logger writes one (a time column in
// milliseconds since the epoch, units in the header), with rows left out on purpose.
#pragma once

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace allanlot::test {

struct CsvSpec {
  std::size_t rows = 20000;
  double rate_hz = 400.0;
  std::size_t dropped = 137;  // rows left out, never the first or the last
  unsigned seed = 7;
  double jitter_ms = 0.0;  // uniform scatter of the time stamps
};

/// Writes `timestamp [ms],gx [deg/s],gy [deg/s],gz [deg/s],ax (m/s^2),ay (m/s^2),az (m/s^2)`.
inline void write_imu_csv(const std::filesystem::path& path, const CsvSpec& spec = {}) {
  std::mt19937_64 rng(spec.seed);
  std::set<std::size_t> drop;
  std::uniform_int_distribution<std::size_t> pick(1, spec.rows - 2);
  while (drop.size() < spec.dropped)
    drop.insert(pick(rng));
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-spec.jitter_ms, spec.jitter_ms);
  std::ofstream f(path);
  f << "timestamp [ms],gx [deg/s],gy [deg/s],gz [deg/s],ax (m/s^2),ay (m/s^2),az (m/s^2)\n";
  const double t0 = 1.7e12, step_ms = 1000.0 / spec.rate_hz;
  char buf[64];
  for (std::size_t i = 0; i < spec.rows; ++i) {
    if (drop.count(i)) continue;
    std::snprintf(buf, sizeof buf, "%.3f", t0 + step_ms * static_cast<double>(i) + u(rng));
    f << buf;
    for (int c = 0; c < 6; ++c) {
      std::snprintf(buf, sizeof buf, ",%.9g", (c < 3 ? 0.01 : 9.8 * (c == 5)) + g(rng));
      f << buf;
    }
    f << "\n";
  }
}

/// A CSV as a test rig logs it: integer epoch-nanosecond stamps with Gaussian jitter, units in
/// the header, a temperature column that is not a sensor channel, rows dropped.
struct RigSpec {
  std::size_t rows = 100000;
  double rate_hz = 100.0;
  std::size_t dropped = 12;  // rows left out, never the first or the last
  double jitter_ns = 20000;  // rms of the stamps about their nominal times
  long long t0_ns = 1764300000000000000LL;
  unsigned seed = 11;
  char sep = ',';
};

/// Writes `timestamp_ns,gyro_x [deg/s],gyro_y [deg/s],accel_x (g),accel_z (g),temp [degC]`.
inline void write_rig_csv(const std::filesystem::path& path, const RigSpec& spec = {}) {
  std::mt19937_64 rng(spec.seed);
  std::set<std::size_t> drop;
  std::uniform_int_distribution<std::size_t> pick(1, spec.rows - 2);
  while (drop.size() < spec.dropped)
    drop.insert(pick(rng));
  std::normal_distribution<double> g(0.0, 1.0);
  std::ofstream f(path);
  const char s = spec.sep;
  f << "timestamp_ns" << s << "gyro_x [deg/s]" << s << "gyro_y [deg/s]" << s << "accel_x (g)" << s
    << "accel_z (g)" << s << "temp [degC]\n";
  const double step_ns = 1e9 / spec.rate_hz;
  char buf[64];
  for (std::size_t i = 0; i < spec.rows; ++i) {
    const double jitter = spec.jitter_ns * g(rng);
    if (drop.count(i)) continue;
    f << spec.t0_ns + std::llround(step_ns * static_cast<double>(i) + jitter);
    for (const double v : {0.01 * g(rng), 0.01 * g(rng), 1e-3 * g(rng), -1 + 1e-3 * g(rng)}) {
      std::snprintf(buf, sizeof buf, "%.9g", v);
      f << s << buf;
    }
    std::snprintf(buf, sizeof buf, "%.2f", 31.5 + 1e-5 * static_cast<double>(i));
    f << s << buf << "\n";
  }
}

/// The lines of a text file, without their line ends.
inline std::vector<std::string> read_lines(const std::filesystem::path& path) {
  std::vector<std::string> lines;
  std::ifstream in(path);
  for (std::string l; std::getline(in, l);)
    lines.push_back(l);
  return lines;
}

/// Writes `lines`, each ended by '\n'.
inline void write_lines(const std::filesystem::path& path, const std::vector<std::string>& lines) {
  std::ofstream out(path);
  for (const auto& l : lines)
    out << l << "\n";
}

/// `gzip -c SRC > DST`; false when gzip failed.
inline bool gzip_copy(const std::filesystem::path& src, const std::filesystem::path& dst) {
  const std::string cmd = "gzip -c '" + src.string() + "' > '" + dst.string() + "'";
  return std::system(cmd.c_str()) == 0;
}

}  // namespace allanlot::test
