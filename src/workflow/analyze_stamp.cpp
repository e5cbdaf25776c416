#include "src/workflow/analyze_stamp.hpp"

#include "io/recording.hpp"

#include <allanlot/version.hpp>

#include <cstdio>

namespace allanlot::workflow {
namespace {

// A number as the stamp writes it: every digit a double has, so that a stamp names its value.
std::string number(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

// The input options that change what is read, only when given: the stamp of a run without
// them stays that of earlier versions, whose results remain current.
std::string input_stamp(const io::InputOptions& in) {
  std::string s;
  if (in.data_type)
    s += in.data_type == kernels::DataType::Rate ? ";data_type=rate" : ";data_type=phase";
  if (in.sample_rate_hz > 0) s += ";sample_rate=" + number(in.sample_rate_hz);
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

std::string edit_stamp(const pipeline::EditOptions& opt) {
  std::string s;
  if (opt.drift != kernels::DriftModel::None)
    s += ";drift=" + std::string(kernels::to_string(opt.drift));
  if (opt.outlier_sigmas > 0) s += ";outliers=" + number(opt.outlier_sigmas);
  for (const kernels::TimeRange& r : opt.exclude)
    s += ";exclude=" + number(r.t0_s) + ":" + number(r.t1_s);
  if (opt.dynamic.enabled())
    s += ";dynamic=" + number(opt.dynamic.window) + ":" + number(opt.dynamic.step) +
         (opt.dynamic.in_seconds ? "s" : "");
  return s;
}

std::string options_stamp(const AnalyzeOptions& opt) {
  return "stats=" + join_stats(opt.stats) + ";taus=" + kernels::to_string(opt.grid) +
         ";confidence=" + number(opt.confidence) + ";channels=" + opt.channels.text() +
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

}  // namespace allanlot::workflow
