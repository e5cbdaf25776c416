#pragma once
// The statistics `analyze --stats` takes (docs/cli.md): the list parsed against the statistics'
// table (kernels/allan/stats.hpp), and the default list in its documented order.

#include "kernels/allan/stats.hpp"

#include <string>
#include <vector>

namespace allanlot::cli {

/// The statistics of a comma-separated list ("all" for every one), each once, in the order
/// given; CLI::ValidationError naming --stats for an unknown name or an empty list.
std::vector<kernels::Stat> parse_stats(const std::string& list);

/// The default statistics of docs/cli.md, comma-separated (kernels::StatInfo::default_rank).
std::string default_stats();

}  // namespace allanlot::cli
