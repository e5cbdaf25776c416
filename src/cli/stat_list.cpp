#include "src/cli/stat_list.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <sstream>

namespace allanlot::cli {

std::vector<kernels::Stat> parse_stats(const std::string& list) {
  std::vector<kernels::Stat> out;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    if (name == "all") {
      // Every single-recording statistic of this build (docs/cli.md); those that cannot run
      // on a gapped channel are skipped there with a note, as when named one by one.
      for (const auto k : kernels::all_stats())
        if (std::find(out.begin(), out.end(), k) == out.end()) out.push_back(k);
      continue;
    }
    const auto s = kernels::parse_stat(name);
    if (!s) {
      std::string known;
      for (const auto k : kernels::all_stats())
        known += (known.empty() ? "" : ", ") + std::string(kernels::stat_name(k));
      throw CLI::ValidationError("--stats",
                                 "unknown statistic '" + name + "' (known: " + known + ", or all)");
    }
    bool dup = false;
    for (const auto k : out)
      dup = dup || k == *s;
    if (!dup) out.push_back(*s);
  }
  if (out.empty()) throw CLI::ValidationError("--stats", "empty list");
  return out;
}

std::string default_stats() {
  std::vector<const kernels::StatInfo*> chosen;
  for (const kernels::Stat s : kernels::all_stats())
    if (kernels::stat_info(s).default_rank > 0) chosen.push_back(&kernels::stat_info(s));
  std::sort(chosen.begin(), chosen.end(),
            [](const auto* a, const auto* b) { return a->default_rank < b->default_rank; });
  std::string s;
  for (const auto* info : chosen)
    s += (s.empty() ? "" : ",") + std::string(info->name);
  return s;
}

}  // namespace allanlot::cli
