// Results files (docs/formats.md "Results file layout"): the composition of the groups; what
// each group holds is io/schema.hpp's.
#include "io/results.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/isolation.hpp"
#include "io/schema_h5.hpp"
#include "io/seal.hpp"

namespace allanlot::io {

using h5::check;
using h5::Handle;
using schema::Depth;

namespace {

void write_fit(hid_t channel_group, const char* name, const FitRecord& fit, const std::string& file,
               const std::string& object) {
  Handle g = schema::create_group(channel_group, name, file, object);
  schema::write_columns(g.get(), fit.terms, schema::term_columns(), file, object);
  schema::write_fields(g.get(), fit, schema::fit_fields(), file, object);
  if (!fit.effects.empty()) {
    const std::string eo = object + "/" + schema::kEffects;
    Handle e = schema::create_group(g.get(), schema::kEffects, file, eo);
    schema::write_columns(e.get(), fit.effects, schema::effect_columns(), file, eo);
  }
  if (fit.readouts.empty()) return;
  const std::string ro = object + "/" + schema::kReadouts;
  Handle r = schema::create_group(g.get(), schema::kReadouts, file, ro);
  schema::write_columns(r.get(), fit.readouts, schema::readout_columns(), file, ro);
}

FitRecord read_fit(hid_t channel_group, const char* name, Depth depth, const std::string& file,
                   const std::string& object) {
  Handle g = schema::open_group(channel_group, name, file, object);
  FitRecord fit;
  fit.terms = schema::read_columns(g.get(), schema::term_columns(), depth, file, object);
  schema::read_fields(g.get(), fit, schema::fit_fields(), depth, file, object);
  // The read-outs are in the lot summary too: read at either depth (three rows).
  if (schema::has_link(g.get(), schema::kReadouts)) {
    const std::string ro = object + "/" + schema::kReadouts;
    Handle r = schema::open_group(g.get(), schema::kReadouts, file, ro);
    fit.readouts = schema::read_columns(r.get(), schema::readout_columns(), depth, file, ro);
  }
  if (schema::has_link(g.get(), schema::kEffects)) {
    const std::string eo = object + "/" + schema::kEffects;
    Handle e = schema::open_group(g.get(), schema::kEffects, file, eo);
    fit.effects = schema::read_columns(e.get(), schema::effect_columns(), depth, file, eo);
  }
  return fit;
}

// A group written from one table (psd/, crosscheck/, allan/<stat>/).
template <class Rec>
void write_group(hid_t parent, const char* name, const Rec& rec,
                 std::span<const schema::Field<Rec>> fields, const std::string& file,
                 const std::string& object) {
  Handle g = schema::create_group(parent, name, file, object);
  schema::write_fields(g.get(), rec, fields, file, object);
}

template <class Rec>
Rec read_group(hid_t parent, const char* name, std::span<const schema::Field<Rec>> fields,
               Depth depth, const std::string& file, const std::string& object) {
  Handle g = schema::open_group(parent, name, file, object);
  Rec rec;
  schema::read_fields(g.get(), rec, fields, depth, file, object);
  return rec;
}

void write_channel(hid_t f, const ChannelResult& ch, const std::string& file) {
  const std::string& gp = ch.path;
  Handle g = h5::ensure_groups(f, gp, file);
  schema::write_fields(g.get(), ch, schema::channel_fields(), file, gp);
  if (ch.quality)
    write_group(g.get(), schema::kQuality, *ch.quality, schema::quality_fields(), file,
                gp + "/quality");
  if (ch.fit) write_fit(g.get(), schema::kFit, *ch.fit, file, gp + "/fit");
  if (ch.psd_fit) write_fit(g.get(), schema::kPsdFit, *ch.psd_fit, file, gp + "/psd_fit");
  if (ch.psd) write_group(g.get(), schema::kPsd, *ch.psd, schema::psd_fields(), file, gp + "/psd");
  if (ch.crosscheck)
    write_group(g.get(), schema::kCrosscheck, *ch.crosscheck, schema::crosscheck_fields(), file,
                gp + "/crosscheck");
  if (!ch.stats.empty()) {
    Handle allan = schema::create_group(g.get(), schema::kAllan, file, gp + "/allan");
    for (const auto& [name, s] : ch.stats)
      write_group(allan.get(), name.c_str(), s, schema::stat_fields(), file, gp + "/allan/" + name);
  }
  if (ch.diagnosis) schema::write_diagnosis_group(g.get(), *ch.diagnosis, file);
  if (ch.powerlaw) {
    const std::string po = gp + "/" + schema::kPowerLaw;
    Handle p = schema::create_group(g.get(), schema::kPowerLaw, file, po);
    schema::write_columns(p.get(), ch.powerlaw->levels, schema::powerlaw_columns(), file, po);
    schema::write_fields(p.get(), *ch.powerlaw, schema::powerlaw_fields(), file, po);
  }

  schema::write_editing_groups(g.get(), ch, file);
}

// One channel group. The summary depth never opens allan/, psd/ or a diagnosis,
// and reads of fit/, psd_fit/ and crosscheck/ only the fields marked `summary`: a lot of
// thousands of units is summarized quickly.
ChannelResult read_channel(hid_t f, const std::string& gp, Depth depth, const std::string& file) {
  Handle g = check(H5Gopen2(f, gp.c_str(), H5P_DEFAULT), H5Gclose, file, gp, "H5Gopen2");
  ChannelResult ch;
  ch.path = gp;
  schema::read_fields(g.get(), ch, schema::channel_fields(), depth, file, gp);
  const bool full = depth == Depth::Full;
  if (schema::has_link(g.get(), schema::kQuality))
    ch.quality = read_group(g.get(), schema::kQuality, schema::quality_fields(), depth, file,
                            gp + "/quality");
  if (schema::has_link(g.get(), schema::kFit))
    ch.fit = read_fit(g.get(), schema::kFit, depth, file, gp + "/fit");
  if (schema::has_link(g.get(), schema::kPsdFit))
    ch.psd_fit = read_fit(g.get(), schema::kPsdFit, depth, file, gp + "/psd_fit");
  if (full && schema::has_link(g.get(), schema::kPsd))
    ch.psd = read_group(g.get(), schema::kPsd, schema::psd_fields(), depth, file, gp + "/psd");
  if (schema::has_link(g.get(), schema::kCrosscheck))
    ch.crosscheck = read_group(g.get(), schema::kCrosscheck, schema::crosscheck_fields(), depth,
                               file, gp + "/crosscheck");
  if (full && schema::has_link(g.get(), schema::kAllan)) {
    // In the order of kernels::all_stats, whatever the order in the file.
    Handle allan = schema::open_group(g.get(), schema::kAllan, file, gp + "/allan");
    for (const kernels::Stat s : kernels::all_stats()) {
      const std::string name(kernels::stat_name(s));
      if (!schema::has_link(allan.get(), name.c_str())) continue;
      ch.stats.emplace_back(name, read_group(allan.get(), name.c_str(), schema::stat_fields(),
                                             depth, file, gp + "/allan/" + name));
    }
  }
  if (schema::has_link(g.get(), schema::kPowerLaw)) {
    const std::string po = gp + "/" + schema::kPowerLaw;
    Handle p = schema::open_group(g.get(), schema::kPowerLaw, file, po);
    ch.powerlaw.emplace();
    ch.powerlaw->levels =
        schema::read_columns(p.get(), schema::powerlaw_columns(), depth, file, po);
    schema::read_fields(p.get(), *ch.powerlaw, schema::powerlaw_fields(), depth, file, po);
  }
  if (full && schema::has_link(g.get(), schema::kDiagnosis)) {
    Handle dg = schema::open_group(g.get(), schema::kDiagnosis, file, gp + "/diagnosis");
    ch.diagnosis = schema::read_diagnosis_group(dg.get(), gp, file);
  }
  schema::read_editing_groups(g.get(), ch, depth, file);
  return ch;
}

bool is_channel_group(hid_t g) {
  // Channel groups carry `status` and `data_type` (fit/ carries a status of its own).
  return H5Aexists(g, "status") > 0 && H5Aexists(g, "data_type") > 0;
}

// Depth-first, in name order, collects the channel groups under `g` (`path` its name). A
// channel group's own subgroups (allan/, psd/, ...) are results, never channels, and are not
// entered: this is what keeps the walk from touching the statistics' datasets.
void find_channel_groups(hid_t g, const std::string& path, const std::string& file,
                         std::vector<std::string>& out) {
  H5G_info_t info{};
  check(H5Gget_info(g, &info), file, path.empty() ? "/" : path, "H5Gget_info");
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len <= 0) throw Error(file, path, "H5Lget_name_by_idx failed");
    std::string name(static_cast<std::size_t>(len), '\0');
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    if (name.starts_with(".")) continue;
    const std::string child = path + "/" + name;
    Handle o = check(H5Oopen(g, name.c_str(), H5P_DEFAULT), H5Oclose, file, child, "H5Oopen");
    if (H5Iget_type(o.get()) != H5I_GROUP) continue;
    if (is_channel_group(o.get()))
      out.push_back(child);
    else
      find_channel_groups(o.get(), child, file, out);
  }
}

RecordingResult read(const std::filesystem::path& path, Depth depth) {
  const std::string file = path.string();
  // A file without a seal (an earlier version's) is read once in a child process first: its
  // bytes were never checked, and damaged ones can crash the HDF5 library (io/isolation.hpp).
  if (!in_isolated_child() && !require_intact(path)) run_isolated(file, [&] { read(path, depth); });
  Handle f = h5::open_sealed(path, "results file");
  Handle root = check(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
  schema::check_version(root.get(), file);
  RecordingResult r;
  schema::read_fields(root.get(), r, schema::root_fields(), depth, file, "/");
  // The analysis options that say how to print the results again (export's Stable32 tables:
  // which MTIE run, which file a table is of; a hat's clocks and pairs, in pair order); the
  // others are for people reading the file.
  for (const char* key : {"statistic", "taus", "clocks", "pairs"})
    if (std::string v; h5::read_attribute(root.get(), key, v, file, "/"))
      r.attributes.emplace_back(key, std::move(v));
  std::vector<std::string> groups;
  find_channel_groups(root.get(), "", file, groups);
  for (const std::string& gp : groups)
    r.channels.push_back(read_channel(f.get(), gp, depth, file));
  return r;
}

}  // namespace

void write_results(const std::filesystem::path& path, const RecordingResult& r) {
  h5::quiet_library();
  const std::string file = path.string();
  AtomicFile atomic(path);
  {
    Handle f = h5::create_memory_file(file);
    {
      Handle root = check(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
      schema::write_fields(root.get(), r, schema::root_fields(), file, "/");
      for (const auto& [k, v] : r.attributes)
        h5::write_attribute(root.get(), k, v, file, "/");
      schema::write_version(root.get(), file);
      for (const ChannelResult& ch : r.channels)
        write_channel(f.get(), ch, file);
    }
    h5::write_memory_file(f, atomic, file);
  }
  atomic.commit();
}

RecordingResult read_results(const std::filesystem::path& path) {
  return read(path, Depth::Full);
}

RecordingResult read_summary_results(const std::filesystem::path& path) {
  return read(path, Depth::Summary);
}

std::string fit_status_text(const FitRecord& f) {
  std::string text = to_string(f.status);
  if (f.status == kernels::FitStatus::PoorFit) {
    char buf[48];
    std::snprintf(buf, sizeof buf, " (chi2/dof = %.3g)", f.chi2_dof);
    text += buf;
  }
  if (!f.model.empty())
    text += "; modelled: " + f.model +
            (f.model_within_noise == 1 ? " (within noise)" : " (NOT within noise)");
  return text;
}

namespace {

// fit/readouts into the row's read-out columns.
void add_readouts(SummaryRow& row, const FitRecord& fit) {
  for (const ReadoutRecord& x : fit.readouts) {
    const char* term = x.name == "N_1s" ? "N" : x.name == "bias_instability" ? "B" : "K";
    if (x.valid) {
      if (!row.readouts_valid.empty()) row.readouts_valid += ' ';
      row.readouts_valid += term;
    }
    if (x.name == "N_1s") {
      row.readout_n = x.value_datasheet;
      row.readout_n_sigma = x.sigma_datasheet;
      row.readout_n_unit = x.unit_datasheet;
      row.readout_n_alt = x.value_datasheet_alt;
      row.readout_n_alt_sigma = x.sigma_datasheet_alt;
      row.readout_n_alt_unit = x.unit_datasheet_alt;
    } else if (x.name == "bias_instability") {
      row.readout_b = x.value_datasheet;
      row.readout_b_sigma = x.sigma_datasheet;
      row.readout_b_unit = x.unit_datasheet;
      row.readout_b_tau = x.tau_s;
    } else if (x.name == "K_3s") {
      row.readout_k = x.value_datasheet;
      row.readout_k_sigma = x.sigma_datasheet;
      row.readout_k_unit = x.unit_datasheet;
      row.readout_k_tau = x.tau_s;
    }
  }
}

}  // namespace

std::vector<SummaryRow> summary_rows(const RecordingResult& r) {
  std::vector<SummaryRow> rows;
  for (const ChannelResult& ch : r.channels) {
    SummaryRow row{r.device_id, ch.path, ch.units, ch.n_samples, ch.status, r.source_file};
    if (ch.fit) {
      for (const TermRecord& t : ch.fit->terms)
        for (std::size_t i = 0; i < row.value.size(); ++i) {
          if (t.term != schema::kTermNames[i]) continue;
          row.value[i] = t.value_datasheet;
          row.sigma[i] = t.sigma_datasheet;
          row.unit[i] = t.unit_datasheet;
          row.detected[i] = t.detected ? 1 : 0;
          row.upper[i] = t.upper_datasheet;
        }
      row.chi2_dof = ch.fit->chi2_dof;
      row.fit_status = fit_status_text(*ch.fit);
      if (kernels::has_terms(ch.fit->status))
        row.fit_within_noise =
            ch.fit->status == kernels::FitStatus::Ok || ch.fit->model_within_noise == 1 ? 1 : 0;
      row.lowpass = ch.fit->lowpass;
      row.lowpass_cutoff_hz = ch.fit->lowpass_cutoff_hz;
      row.lowpass_taps = ch.fit->lowpass_taps;
      row.first_tau_fitted = ch.fit->first_tau_fitted;
      row.chi2_dof_all_taus = ch.fit->chi2_dof_all_taus;
      add_readouts(row, *ch.fit);
    }
    if (ch.powerlaw)
      for (const PowerLawLevelRecord& l : ch.powerlaw->levels)
        if (l.alpha >= -2 && l.alpha <= 2) {
          const auto i = static_cast<std::size_t>(2 - l.alpha);
          row.h[i] = l.h;
          row.h_sigma[i] = l.h_sigma;
          row.h_upper[i] = l.h_upper;
          row.h_detected[i] = l.detected ? 1 : 0;
        }
    if (ch.crosscheck) {
      row.max_abs_log10_ratio = ch.crosscheck->max_abs_log10_ratio;
      row.crosscheck_worst_tau = ch.crosscheck->worst_tau;
    }
    if (ch.psd_fit && ch.psd_fit->agree >= 0) {
      row.fits_agree = static_cast<std::int8_t>(ch.psd_fit->agree);
      row.fits_max_abs_z = ch.psd_fit->max_abs_z;
    }
    if (ch.quality) {
      const kernels::QualityReport& q = *ch.quality;
      row.quality = q.flags.empty() ? "ok" : q.flags;
      row.n_missing = q.n_missing;
      row.n_gap_runs = q.n_gap_runs;
      row.n_time_errors = q.n_duplicate_times + q.n_decreasing_times;
      row.n_saturated = q.n_saturated_samples;
      row.longest_run = q.longest_run;
      row.n_stuck = q.n_stuck_runs;
      row.n_spikes = q.n_spikes;
      row.max_spike_sigmas = q.max_spike_sigmas;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace allanlot::io
