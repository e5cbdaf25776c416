#include "src/workflow/diagnosis_json.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace allanlot::workflow {
namespace {

Json bands_json(const std::vector<kernels::Band>& bands) {
  Json a = Json::array();
  for (const auto& b : bands)
    a.push_back({{"tau_lo_s", b.tau_lo_s},
                 {"tau_hi_s", b.tau_hi_s},
                 {"sign", b.sign},
                 {"max_abs_z", b.max_abs_z}});
  return a;
}

Json value_or_null(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

Json params_json(const std::vector<kernels::Parameter>& ps) {
  Json o = Json::object();
  for (const auto& p : ps)
    o[p.name] = p.value;
  return o;
}

Json sigmas_json(const std::vector<kernels::Parameter>& ps) {
  Json o = Json::object();
  for (const auto& p : ps)
    o[p.name] = value_or_null(p.sigma);
  return o;
}

// The parameters that are limits rather than estimates: "<" (an upper limit, at the lower end
// of the search) or ">" (a lower limit).
Json bounds_json(const std::vector<kernels::Parameter>& ps) {
  Json o = Json::object();
  for (const auto& p : ps)
    if (p.bound != 0) o[p.name] = p.bound < 0 ? "<" : ">";
  return o;
}

}  // namespace

Json diagnosis_json(const std::string& channel, const kernels::Diagnosis& d) {
  Json j;
  j["channel"] = channel;
  j["effects_named"] = Json::array();
  Json params = Json::object(), sigmas = Json::object(), bounds = Json::object();
  for (std::size_t i = 0; i < d.effects_named.size(); ++i) {
    std::string key(kernels::effect_name(d.effects_named[i]));
    // A second effect of the same kind (two sinusoids) gets its ordinal.
    for (int k = 2; params.contains(key); ++k)
      key = std::string(kernels::effect_name(d.effects_named[i])) + "_" + std::to_string(k);
    j["effects_named"].push_back(std::string(kernels::effect_name(d.effects_named[i])));
    params[key] = params_json(d.effect_parameters[i]);
    sigmas[key] = sigmas_json(d.effect_parameters[i]);
    if (Json b = bounds_json(d.effect_parameters[i]); !b.empty()) bounds[key] = std::move(b);
  }
  j["parameters"] = params;
  j["gap_before"] = d.before.gap;
  j["gap_after"] = d.after.gap;
  Json its = Json::array();
  for (const auto& it : d.iterations) {
    Json cands = Json::array();
    for (const auto& c : it.candidates)
      cands.push_back({{"effect", std::string(kernels::effect_name(c.effect))},
                       {"evaluated", c.evaluated},
                       {"delta_ic", c.evaluated ? Json(c.delta_ic) : Json(nullptr)},
                       {"note", c.note}});
    its.push_back({{"effect", std::string(kernels::effect_name(it.effect))},
                   {"parameters", params_json(it.parameters)},
                   {"sigmas", sigmas_json(it.parameters)},
                   {"delta_ic", it.delta_ic},
                   {"gap_before", it.gap_before},
                   {"gap_after", it.gap_after},
                   {"bands_before", bands_json(it.bands_before)},
                   {"bands_after", bands_json(it.bands_after)},
                   {"coefficients", params_json(it.coefficients)},
                   {"candidates", cands}});
  }
  j["iterations"] = its;
  j["parameter_sigmas"] = sigmas;
  j["parameter_bounds"] = bounds;
  j["gap_within_noise"] = d.gap_within_noise;
  j["gap_noise_median"] = d.mc_after.gap_median;
  j["gap_noise_p95"] = d.mc_after.gap_p95;
  j["bands_before"] = bands_json(d.before.bands);
  j["bands_after"] = bands_json(d.after.bands);
  j["coefficients_wrong"] = d.coefficients_wrong;
  Json rev = Json::array();
  for (const auto& r : d.revisions)
    rev.push_back({{"coefficient", r.name},
                   {"given", r.given},
                   {"estimated", r.estimated},
                   {"sigma", value_or_null(r.sigma)}});
  j["coefficients"] = rev;
  j["n_taus"] = d.tau_s.size();
  j["n_eff"] = d.n_eff;
  j["z_threshold"] = d.z_threshold;
  j["psd_line"] = {{"searched", d.line.searched},         {"found", d.line.found},
                   {"frequency_hz", d.line.frequency_hz}, {"peak_ratio", d.line.peak_ratio},
                   {"threshold", d.line.threshold},       {"wide_hz", d.line.wide_hz}};
  if (const auto& nb = d.line.narrowband; nb.found)
    j["psd_line"]["narrowband"] = {{"frequency_hz", nb.frequency_hz},
                                   {"frequency_sigma", nb.frequency_sigma},
                                   {"q", nb.q},
                                   {"q_sigma", nb.q_sigma},
                                   {"sigma", nb.sigma},
                                   {"sigma_sigma", nb.sigma_sigma}};
  j["step_witness"] = {{"searched", d.step.searched},   {"found", d.step.found},
                       {"time_s", d.step.time_s},       {"size", d.step.size},
                       {"statistic", d.step.statistic}, {"scale_m", d.step.scale_m},
                       {"p_value", d.step.p_value},     {"false_alarm", d.step.false_alarm}};
  j["trend_witness"] = {{"searched", d.trend.searched},
                        {"found", d.trend.found},
                        {"slope", d.trend.slope},
                        {"sigma", d.trend.sigma},
                        {"z", d.trend.z},
                        {"p_value", d.trend.p_value},
                        {"false_alarm", d.trend.false_alarm}};
  j["notes"] = d.notes;
  return j;
}

Json parameters_json(const std::vector<kernels::Parameter>& ps) {
  return {{"parameters", params_json(ps)}, {"sigmas", sigmas_json(ps)}};
}

}  // namespace allanlot::workflow
