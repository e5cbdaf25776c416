#include "src/pipeline/channel_quality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace allanlot::pipeline {

std::optional<std::pair<double, double>> storage_limits(const io::ChannelInfo& channel) {
  const std::string& t = channel.storage_type;
  const bool is_unsigned = t.starts_with("uint");
  if (!is_unsigned && !t.starts_with("int")) return std::nullopt;
  const std::string digits = t.substr(is_unsigned ? 4 : 3);
  if (digits != "8" && digits != "16" && digits != "32" && digits != "64") return std::nullopt;
  const int bits = std::stoi(digits);
  // 2^bits as a double is exact; the limits are exact integers up to 32 bits, and beyond they
  // round as HDF5's conversion of the stored limit to double does.
  const double span = std::ldexp(1.0, bits);
  double lo = is_unsigned ? 0.0 : -span / 2;
  double hi = is_unsigned ? span - 1 : span / 2 - 1;
  if (channel.scale != 1.0 || channel.offset != 0.0) {
    lo = lo * channel.scale + channel.offset;
    hi = hi * channel.scale + channel.offset;
  }
  return std::pair{std::min(lo, hi), std::max(lo, hi)};
}

kernels::QualityReport screen_channel(const io::ChannelInfo& channel,
                                      std::span<const double> samples, int threads) {
  kernels::QualityInput in;
  in.samples = samples;
  in.time = channel.time_stamps;
  if (const auto limits = storage_limits(channel)) {
    in.storage_min = limits->first;
    in.storage_max = limits->second;
  }
  kernels::QualityOptions opt;
  opt.threads = threads;
  return kernels::screen_quality(in, opt);
}

}  // namespace allanlot::pipeline
