#include "io/report_data.hpp"

#include "io/schema.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace allanlot::io {

namespace {

std::vector<double> deviations(const std::vector<double>& avar) {
  std::vector<double> v = avar;
  for (double& x : v)
    x = x >= 0 ? std::sqrt(x) : std::nan("");
  return v;
}

std::string attribute_number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

DiagnosisView diagnosis_view(const DiagnosisRecord& r) {
  DiagnosisView d;
  d.channel = r.channel;
  d.tau = r.tau;
  d.measured = deviations(r.avar_measured);
  d.model_before = deviations(r.avar_model_before);
  d.model_after = deviations(r.avar_model_after);
  d.band_lo = deviations(r.mc_after_lo);
  d.band_hi = deviations(r.mc_after_hi);
  d.band_before_lo = deviations(r.mc_before_lo);
  d.band_before_hi = deviations(r.mc_before_hi);
  d.edf = r.edf;
  d.effects_named = r.effect;
  d.iteration_gap_before = r.gap_before;
  d.iteration_gap_after = r.gap_after;
  d.iteration_delta_ic = r.delta_ic;
  d.iteration_parameters = r.parameters_json;
  for (const auto& [k, v] : r.number_attributes) {
    d.attributes.emplace_back(k, attribute_number(v));
    if (k == "gap_before") d.gap_before = v;
    if (k == "gap_after") d.gap_after = v;
    if (k == "gap_noise_p95") d.gap_noise_p95 = v;
    if (k == "gap_within_noise" && (v == 0.0 || v == 1.0)) d.within_noise = static_cast<int>(v);
    if (k == "mc_replicas" && v >= 0.0 && v <= 1e9) d.replicas = static_cast<int>(v);
  }
  for (const auto& [k, v] : r.string_attributes)
    d.attributes.emplace_back(k, v);
  std::sort(d.attributes.begin(), d.attributes.end());
  if (std::isnan(d.gap_before) && !d.iteration_gap_before.empty())
    d.gap_before = d.iteration_gap_before.front();
  if (std::isnan(d.gap_after) && !d.iteration_gap_after.empty())
    d.gap_after = d.iteration_gap_after.back();
  // Curves of another length than tau cannot be drawn against it.
  const std::string object = r.channel + "/diagnosis";
  for (auto* v : {&d.measured, &d.model_before, &d.model_after, &d.band_lo, &d.band_hi,
                  &d.band_before_lo, &d.band_before_hi, &d.edf})
    if (!v->empty() && v->size() != d.tau.size()) {
      d.notes.push_back(object + ": a curve has " + std::to_string(v->size()) + " values for " +
                        std::to_string(d.tau.size()) + " taus; not drawn");
      v->clear();
    }
  return d;
}

ReportExtras report_extras(const RecordingResult& r) {
  ReportExtras x;
  x.device_id = r.device_id;
  for (const ChannelResult& ch : r.channels) {
    if (ch.psd_fit && !ch.psd_fit->terms.empty()) x.psd_fits.emplace_back(ch.path, *ch.psd_fit);
    if (ch.diagnosis) x.diagnoses.push_back(diagnosis_view(*ch.diagnosis));
  }
  return x;
}

ReportExtras read_report_extras(const std::filesystem::path& file) {
  // Every diagnosis group, also those of a diagnose output that is not a results file (no
  // channel groups), so not only those read_results finds under channels.
  const std::vector<DiagnosisRecord> diagnoses = read_diagnoses(file);
  ReportExtras x = report_extras(read_results(file));
  x.diagnoses.clear();
  for (const DiagnosisRecord& d : diagnoses)
    x.diagnoses.push_back(diagnosis_view(d));
  return x;
}

int SummaryColumns::find(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

SummaryColumns read_summary_columns(const std::filesystem::path& h5_path) {
  const std::vector<SummaryRow> rows = read_lot_summary(h5_path);
  SummaryColumns cols;
  cols.rows = rows.size();
  for (auto& [name, text] : schema::summary_text(rows)) {
    cols.names.push_back(std::move(name));
    cols.values.push_back(std::move(text));
  }
  return cols;
}

}  // namespace allanlot::io
