// The data-quality screen of one channel (docs/quality.md) as the pipeline runs it: the storage
// type's limits in physical units from the channel's description, and the screen of
// kernels/quality on the samples as read.
#pragma once

#include "io/recording.hpp"
#include "kernels/quality/quality.hpp"

#include <optional>
#include <span>
#include <string>
#include <utility>

namespace allanlot::pipeline {

/// The smallest and largest value an integer storage type ("int8" ... "int64", "uint8" ...
/// "uint64", as io::ChannelInfo::storage_type names it) can hold, converted to physical units as
/// the reader converts samples (raw * scale + offset when either differs from 1 and 0), in
/// increasing order; nullopt for floating or unknown storage.
std::optional<std::pair<double, double>> storage_limits(const io::ChannelInfo& channel);

/// Screens the samples of `channel` (before any statistic, NaN = missing sample).
kernels::QualityReport screen_channel(const io::ChannelInfo& channel,
                                      std::span<const double> samples, int threads);

}  // namespace allanlot::pipeline
