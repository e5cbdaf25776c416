// The quality screen's false-flag rate (docs/quality.md "False flags"): 100 clean channels drawn
// by the project's simulator (kernels/simulate) at a tactical MEMS IMU's levels, in floating and
// in integer storage, raise no flag. The margins (the largest spike distance against the
// threshold of 10 sigmas, the longest run against the stuck length) are printed for the docs.
#include "kernels/quality/quality.hpp"
#include "kernels/simulate/simulate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace allanlot {
namespace {

using kernels::ChannelSpec;

constexpr std::size_t kSamples = 131'072;  // 131 s at 1 kHz
constexpr int kPerKind = 20;

struct Kind {
  const char* name;
  ChannelSpec spec;
  double lsb = 0;  // 0: floating storage; else rounded to it, stored as int16
};

// ADIS16488-class gyro (ARW 0.3 deg/sqrt(h), bias instability 6.25 deg/h, docs/formats.md's
// model) and accelerometer (VRW 0.029 m/s/sqrt(h), 0.1 mg), plus quantization noise (Q) and a
// random walk ten times the datasheet's, in deg/s and m/s^2 at 1 kHz.
std::vector<Kind> kinds() {
  ChannelSpec gyro;
  gyro.rate_hz = 1000;
  gyro.terms.N = 0.005;
  gyro.terms.B = 0.0017361;
  gyro.terms.K = 4.6e-7;
  gyro.sinusoids.push_back({0.002, 0.5, 0});
  gyro.markovs.push_back({0.001, 20});
  ChannelSpec accel;
  accel.rate_hz = 1000;
  accel.terms.N = 0.029 / 60;
  accel.terms.B = 0.1e-3 * 9.80665;
  accel.terms.K = 1e-5;
  accel.offset = 9.80665;
  ChannelSpec gyro_q = gyro;
  gyro_q.terms.Q = 5e-5;
  ChannelSpec walk = gyro;
  walk.terms.K = 4.6e-6;
  walk.terms.R = 1e-4;
  // 16-bit gyro at 0.02 deg/s per step (noise ~8 steps); 14-bit accelerometer at 3.33 mg per
  // step (ADIS16405-like: noise ~0.5 step, the stuck test's hardest case).
  return {{"gyro", gyro},
          {"accel", accel},
          {"gyro+Q int16", gyro_q, 0.02},
          {"accel int16", accel, 3.33e-3 * 9.80665},
          {"gyro random walk", walk}};
}

TEST(QualityClean, HundredSimulatedChannelsRaiseNoFlag) {
  kernels::SimulationPlan plan(kSamples);
  std::vector<double> x(kSamples);
  int flagged = 0, channels = 0;
  double worst_spike = 0, worst_run_ratio = 0;
  for (const Kind& k : kinds())
    for (int i = 0; i < kPerKind; ++i) {
      plan.run(k.spec, 20261123, static_cast<std::uint64_t>(100 * channels + i), x, 1);
      kernels::QualityInput in;
      if (k.lsb > 0) {
        for (double& v : x)
          v = std::round(v / k.lsb) * k.lsb;
        in.storage_min = -32768 * k.lsb;
        in.storage_max = 32767 * k.lsb;
      }
      in.samples = x;
      const kernels::QualityReport r = kernels::screen_quality(in);
      ++channels;
      if (!r.flags.empty()) ++flagged;
      EXPECT_EQ(r.flags, "") << k.name << " #" << i << ": spikes " << r.n_spikes << " (max "
                             << r.max_spike_sigmas << " sigma), longest run " << r.longest_run
                             << " of " << r.stuck_run << ", saturated " << r.n_saturated_runs;
      worst_spike = std::max(worst_spike, r.max_spike_sigmas);
      worst_run_ratio = std::max(worst_run_ratio, static_cast<double>(r.longest_run) /
                                                      static_cast<double>(r.stuck_run));
    }
  std::printf("quality screen on %d clean simulated channels: %d flagged; largest spike %.2f "
              "robust sigmas (threshold 10); longest run %.2f of the stuck length\n",
              channels, flagged, worst_spike, worst_run_ratio);
  EXPECT_EQ(channels, 100);
}

}  // namespace
}  // namespace allanlot
