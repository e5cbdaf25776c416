#include "src/cli/analyze_edit.hpp"

#include <cmath>
#include <stdexcept>

namespace allanlot::cli {
namespace {

double parse_seconds(const std::string& text, const std::string& whole) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v))
    throw CLI::ValidationError("--exclude", "'" + whole +
                                                "': expected T0:T1, seconds from the first "
                                                "sample, with T0 <= T1 (e.g. 0:600)");
  return v;
}

kernels::TimeRange parse_range(const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) parse_seconds("", text);
  const kernels::TimeRange r{parse_seconds(text.substr(0, colon), text),
                             parse_seconds(text.substr(colon + 1), text)};
  if (r.t0_s > r.t1_s) parse_seconds("", text);
  return r;
}

double parse_outliers(const std::string& text) {
  if (text == "off") return 0;
  if (text == "mad") return kernels::kDefaultOutlierSigmas;
  if (text.rfind("mad:", 0) == 0) {
    std::size_t used = 0;
    double k = 0;
    try {
      k = std::stod(text.substr(4), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used > 0 && used == text.size() - 4 && std::isfinite(k) && k > 0) return k;
  }
  throw CLI::ValidationError("--outliers", "'" + text +
                                               "': expected off, mad (5 robust sigmas) or "
                                               "mad:K (K > 0 robust sigmas)");
}

}  // namespace

void add_edit_options(CLI::App* sub, EditArgs& a) {
  sub->add_option("--drift", a.drift,
                  "Frequency drift fitted and removed before the statistics: none, linear "
                  "(a line to rate data, a parabola to phase data), quadratic (the same), log "
                  "(y = a ln(bt+1) + c) or diffusion (y = a + b sqrt(t+c)); rate data for the "
                  "last two")
      ->check(CLI::IsMember({"none", "linear", "quadratic", "log", "diffusion"}))
      ->capture_default_str();
  sub->add_option("--outliers", a.outliers,
                  "Remove outliers of the frequency: off, mad (beyond 5 robust sigmas of the "
                  "median, sigma = 1.4826 MAD) or mad:K")
      ->capture_default_str();
  sub->add_option("--exclude", a.exclude,
                  "Exclude the samples from T0 to T1 s after the first sample (T0:T1, "
                  "repeatable); the gap policy then fills or skips them")
      ->allow_extra_args(false);
  sub->add_option("--dynamic", a.dynamic,
                  "Dynamic Allan deviation: OADEV of a sliding window, WINDOW[:STEP] in samples "
                  "or with the suffix s in seconds (default step: a quarter of the window)");
}

pipeline::EditOptions checked_edit_options(const EditArgs& a) {
  pipeline::EditOptions opt;
  opt.drift = kernels::parse_drift_model(a.drift);  // IsMember has checked it
  opt.outlier_sigmas = parse_outliers(a.outliers);
  for (const std::string& r : a.exclude)
    opt.exclude.push_back(parse_range(r));
  if (!a.dynamic.empty()) {
    try {
      opt.dynamic = kernels::parse_dynamic_spec(a.dynamic);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--dynamic", e.what());
    }
  }
  return opt;
}

}  // namespace allanlot::cli
