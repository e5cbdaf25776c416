#include "src/cli/analyze_stamp.hpp"

#include "io/recording.hpp"
#include "src/cli/analyze_edit.hpp"

#include <allanlot/version.hpp>

#include <cstdio>

namespace allanlot::cli {
namespace {

// The input options that change what is read, only when given: the stamp of a run without
// them stays that of earlier versions, whose results remain current.
std::string input_stamp(const io::InputOptions& in) {
  std::string s;
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.17g", in.sample_rate_hz);
  if (in.data_type)
    s += in.data_type == kernels::DataType::Rate ? ";data_type=rate" : ";data_type=phase";
  if (in.sample_rate_hz > 0) s += std::string(";sample_rate=") + rate;
  if (in.column > 0) s += ";column=" + std::to_string(in.column);
  if (!in.time_column.empty()) s += ";time_column=" + in.time_column;
  if (!in.time_unit.empty()) s += ";time_unit=" + in.time_unit;
  if (!in.units.empty()) s += ";units=" + io::units_text(in.units);
  for (const std::string& t : in.topics)
    s += ";topic=" + t;
  if (in.receive_time) s += ";receive_time";
  return s;
}

// The gap policy, named in the stamp only when it is not the default: results files written
// by a default run without the option in their stamp stay current for resume.
std::string gaps_stamp(const kernels::GapPolicy& gaps) {
  return gaps == kernels::GapPolicy{} ? "" : ";gaps=" + kernels::to_string(gaps);
}

}  // namespace

std::string options_stamp(const AnalyzeOptions& opt) {
  char conf[32];
  std::snprintf(conf, sizeof conf, "%.17g", opt.confidence);
  return "stats=" + join_stats(opt.stats) + ";taus=" + kernels::to_string(opt.grid) +
         ";confidence=" + conf + ";channels=" + opt.channels.text() +
         ";fit=" + (opt.fit ? "1" : "0") + ";lowpass=" + opt.lowpass +
         (opt.model_poor_fits == "auto" ? "" : ";model_poor_fits=" + opt.model_poor_fits) +
         (opt.noise_model == "auto" ? "" : ";model=" + opt.noise_model) +
         ";psd=" + (opt.psd ? "1" : "0") + gaps_stamp(opt.gaps) + ";version=" + kVersion +
         input_stamp(opt.input) + edit_stamp(opt.edit);
}

std::string join_stats(const std::vector<kernels::Stat>& stats) {
  std::string s;
  for (std::size_t i = 0; i < stats.size(); ++i) {
    if (i) s += ',';
    s += kernels::stat_name(stats[i]);
  }
  return s;
}

}  // namespace allanlot::cli
