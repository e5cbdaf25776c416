#include "io/results.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <sstream>

namespace allanlot::io {

using h5::check;
using h5::Handle;

namespace {

void write_stat(hid_t allan, const std::string& name, const kernels::StatResult& s,
                const std::string& file, const std::string& object) {
  Handle gcpl = h5::group_create_plist(file, object);
  Handle g = check(H5Gcreate2(allan, name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose,
                   file, object, "H5Gcreate2");
  h5::write_dataset(g.get(), "m", s.m, file, object);
  h5::write_dataset(g.get(), "tau", s.tau_s, file, object);
  h5::write_dataset(g.get(), "dev", s.dev, file, object);
  h5::write_dataset(g.get(), "n", s.n, file, object);
  if (s.confidence > 0.0) {
    h5::write_dataset(g.get(), "edf", s.edf, file, object);
    h5::write_dataset(g.get(), "dev_lo", s.dev_lo, file, object);
    h5::write_dataset(g.get(), "dev_hi", s.dev_hi, file, object);
    h5::write_dataset(g.get(), "alpha", s.alpha, file, object);
    h5::write_attribute(g.get(), "confidence", s.confidence, file, object);
  }
}

void write_fit(hid_t channel_group, const std::string& name, const FitRecord& fit,
               const std::string& file, const std::string& object) {
  Handle gcpl = h5::group_create_plist(file, object);
  Handle g = check(H5Gcreate2(channel_group, name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT),
                   H5Gclose, file, object, "H5Gcreate2");
  std::vector<std::string> term, unit, unit_ds, unit_alt;
  std::vector<double> value, sigma, upper, value_ds, sigma_ds, upper_ds, value_alt;
  std::vector<std::uint8_t> detected;
  for (const TermRecord& t : fit.terms) {
    term.push_back(t.term);
    value.push_back(t.value);
    sigma.push_back(t.sigma);
    upper.push_back(t.upper);
    detected.push_back(t.detected ? 1 : 0);
    unit.push_back(t.unit);
    value_ds.push_back(t.value_datasheet);
    sigma_ds.push_back(t.sigma_datasheet);
    upper_ds.push_back(t.upper_datasheet);
    unit_ds.push_back(t.unit_datasheet);
    value_alt.push_back(t.value_datasheet_alt);
    unit_alt.push_back(t.unit_datasheet_alt);
  }
  h5::write_dataset(g.get(), "term", term, file, object);
  h5::write_dataset(g.get(), "value", value, file, object);
  h5::write_dataset(g.get(), "sigma", sigma, file, object);
  h5::write_dataset(g.get(), "upper", upper, file, object);
  h5::write_dataset(g.get(), "detected", detected, file, object);
  h5::write_dataset(g.get(), "unit", unit, file, object);
  h5::write_dataset(g.get(), "value_datasheet", value_ds, file, object);
  h5::write_dataset(g.get(), "sigma_datasheet", sigma_ds, file, object);
  h5::write_dataset(g.get(), "upper_datasheet", upper_ds, file, object);
  h5::write_dataset(g.get(), "unit_datasheet", unit_ds, file, object);
  h5::write_dataset(g.get(), "value_datasheet_alt", value_alt, file, object);
  h5::write_dataset(g.get(), "unit_datasheet_alt", unit_alt, file, object);
  if (!fit.tau.empty() || fit.f.empty()) {
    h5::write_dataset(g.get(), "tau", fit.tau, file, object);
    h5::write_dataset(g.get(), "adev_model", fit.adev_model, file, object);
  }
  if (!fit.f.empty()) {
    h5::write_dataset(g.get(), "f", fit.f, file, object);
    h5::write_dataset(g.get(), "psd_model", fit.psd_model, file, object);
  }
  if (fit.agree >= 0) {
    h5::write_dataset(g.get(), "z_vs_fit", fit.z_vs_fit, file, object);
    h5::write_attribute(g.get(), "agrees_with_fit", static_cast<std::int64_t>(fit.agree), file,
                        object);
    h5::write_attribute(g.get(), "max_abs_z", fit.max_abs_z, file, object);
    h5::write_attribute(g.get(), "worst_term", fit.worst_term, file, object);
  }
  h5::write_attribute(g.get(), "method", fit.method, file, object);
  h5::write_attribute(g.get(), "status", fit.status, file, object);
  h5::write_attribute(g.get(), "rank", static_cast<std::int64_t>(fit.rank), file, object);
  h5::write_attribute(g.get(), "chi2_dof", fit.chi2_dof, file, object);
  if (fit.readouts.empty()) return;
  const std::string ro = object + "/readouts";
  Handle rcpl = h5::group_create_plist(file, ro);
  Handle r = check(H5Gcreate2(g.get(), "readouts", H5P_DEFAULT, rcpl.get(), H5P_DEFAULT), H5Gclose,
                   file, ro, "H5Gcreate2");
  std::vector<std::string> rname, runit;
  std::vector<double> rvalue, rsigma, rtau, rmodel, rvalue_ds, rsigma_ds;
  std::vector<std::uint8_t> rvalid;
  for (const ReadoutRecord& x : fit.readouts) {
    rname.push_back(x.name);
    rvalid.push_back(x.valid ? 1 : 0);
    rvalue.push_back(x.value);
    rsigma.push_back(x.sigma);
    rtau.push_back(x.tau_s);
    rmodel.push_back(x.model);
    rvalue_ds.push_back(x.value_datasheet);
    rsigma_ds.push_back(x.sigma_datasheet);
    runit.push_back(x.unit_datasheet);
  }
  h5::write_dataset(r.get(), "name", rname, file, ro);
  h5::write_dataset(r.get(), "valid", rvalid, file, ro);
  h5::write_dataset(r.get(), "value", rvalue, file, ro);
  h5::write_dataset(r.get(), "sigma", rsigma, file, ro);
  h5::write_dataset(r.get(), "tau", rtau, file, ro);
  h5::write_dataset(r.get(), "model", rmodel, file, ro);
  h5::write_dataset(r.get(), "value_datasheet", rvalue_ds, file, ro);
  h5::write_dataset(r.get(), "sigma_datasheet", rsigma_ds, file, ro);
  h5::write_dataset(r.get(), "unit_datasheet", runit, file, ro);
}

void write_psd(hid_t channel_group, const PsdRecord& psd, const std::string& file,
               const std::string& object) {
  Handle gcpl = h5::group_create_plist(file, object);
  Handle g = check(H5Gcreate2(channel_group, "psd", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose,
                   file, object, "H5Gcreate2");
  h5::write_dataset(g.get(), "f", psd.f, file, object);
  h5::write_dataset(g.get(), "psd", psd.psd, file, object);
  h5::write_dataset(g.get(), "edf", psd.edf, file, object);
  h5::write_dataset(g.get(), "n_avg", psd.n_avg, file, object);
  h5::write_attribute(g.get(), "method", psd.method, file, object);
  h5::write_attribute(g.get(), "convention", psd.convention, file, object);
}

void write_crosscheck(hid_t channel_group, const CrosscheckRecord& c, const std::string& file,
                      const std::string& object) {
  Handle gcpl = h5::group_create_plist(file, object);
  Handle g = check(H5Gcreate2(channel_group, "crosscheck", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT),
                   H5Gclose, file, object, "H5Gcreate2");
  h5::write_dataset(g.get(), "tau", c.tau, file, object);
  h5::write_dataset(g.get(), "avar_time", c.avar_time, file, object);
  h5::write_dataset(g.get(), "avar_psd", c.avar_psd, file, object);
  h5::write_dataset(g.get(), "ratio", c.ratio, file, object);
  h5::write_dataset(g.get(), "valid", c.valid, file, object);
  h5::write_attribute(g.get(), "max_abs_log10_ratio", c.max_abs_log10_ratio, file, object);
  h5::write_attribute(g.get(), "valid_tau_range", c.valid_tau_range, file, object);
  h5::write_attribute(g.get(), "worst_tau", c.worst_tau, file, object);
}

FitRecord read_fit(hid_t g, const std::string& file, const std::string& object) {
  FitRecord fit;
  const auto term = h5::read_strings(g, "term", file, object);
  const auto value = h5::read_doubles(g, "value", file, object);
  const auto sigma = h5::read_doubles(g, "sigma", file, object);
  const auto upper = h5::read_doubles(g, "upper", file, object);
  const auto detected = h5::read_int64s(g, "detected", file, object);
  const auto unit = h5::read_strings(g, "unit", file, object);
  const auto value_ds = h5::read_doubles(g, "value_datasheet", file, object);
  const auto sigma_ds = h5::read_doubles(g, "sigma_datasheet", file, object);
  const auto upper_ds = h5::read_doubles(g, "upper_datasheet", file, object);
  const auto unit_ds = h5::read_strings(g, "unit_datasheet", file, object);
  const auto value_alt = h5::read_doubles(g, "value_datasheet_alt", file, object);
  const auto unit_alt = h5::read_strings(g, "unit_datasheet_alt", file, object);
  for (std::size_t i = 0; i < term.size(); ++i)
    fit.terms.push_back({term[i], value.at(i), sigma.at(i), upper.at(i), detected.at(i) != 0,
                         unit.at(i), value_ds.at(i), sigma_ds.at(i), upper_ds.at(i), unit_ds.at(i),
                         value_alt.at(i), unit_alt.at(i)});
  if (H5Lexists(g, "tau", H5P_DEFAULT) > 0) {
    fit.tau = h5::read_doubles(g, "tau", file, object);
    fit.adev_model = h5::read_doubles(g, "adev_model", file, object);
  }
  if (H5Lexists(g, "f", H5P_DEFAULT) > 0) {
    fit.f = h5::read_doubles(g, "f", file, object);
    fit.psd_model = h5::read_doubles(g, "psd_model", file, object);
  }
  if (H5Lexists(g, "z_vs_fit", H5P_DEFAULT) > 0) {
    fit.z_vs_fit = h5::read_doubles(g, "z_vs_fit", file, object);
    double agree = -1;
    h5::read_attribute(g, "agrees_with_fit", agree, file, object);
    fit.agree = static_cast<int>(agree);
    h5::read_attribute(g, "max_abs_z", fit.max_abs_z, file, object);
    h5::read_attribute(g, "worst_term", fit.worst_term, file, object);
  }
  h5::read_attribute(g, "method", fit.method, file, object);
  h5::read_attribute(g, "status", fit.status, file, object);
  double rank = 0;
  h5::read_attribute(g, "rank", rank, file, object);
  fit.rank = static_cast<int>(rank);
  h5::read_attribute(g, "chi2_dof", fit.chi2_dof, file, object);
  return fit;
}

std::string read_string_attr(hid_t obj, const std::string& name, const std::string& file,
                             const std::string& object) {
  std::string v;
  h5::read_attribute(obj, name, v, file, object);
  return v;
}

double read_double_attr(hid_t obj, const std::string& name, const std::string& file,
                        const std::string& object) {
  double v = 0.0;
  h5::read_attribute(obj, name, v, file, object);
  return v;
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
      h5::write_attribute(root.get(), "device_id", r.device_id, file, "/");
      h5::write_attribute(root.get(), "source_file", r.source_file, file, "/");
      h5::write_attribute(root.get(), "tool_version", r.tool_version, file, "/");
      h5::write_attribute(root.get(), "created_utc", r.created_utc, file, "/");
      h5::write_attribute(root.get(), "command_line", r.command_line, file, "/");
      for (const auto& [k, v] : r.attributes)
        h5::write_attribute(root.get(), k, v, file, "/");
      for (const ChannelResult& ch : r.channels) {
        Handle g = h5::ensure_groups(f.get(), ch.path, file);
        h5::write_attribute(g.get(), "units", ch.units, file, ch.path);
        h5::write_attribute(g.get(), "sample_rate_hz", ch.sample_rate_hz, file, ch.path);
        h5::write_attribute(g.get(), "n_samples", ch.n_samples, file, ch.path);
        h5::write_attribute(g.get(), "n_gaps", ch.n_gaps, file, ch.path);
        h5::write_attribute(g.get(), "data_type", ch.data_type, file, ch.path);
        h5::write_attribute(g.get(), "status", ch.status, file, ch.path);
        if (!ch.notes.empty()) h5::write_attribute(g.get(), "notes", ch.notes, file, ch.path);
        if (ch.fit) write_fit(g.get(), "fit", *ch.fit, file, ch.path + "/fit");
        if (ch.psd_fit) write_fit(g.get(), "psd_fit", *ch.psd_fit, file, ch.path + "/psd_fit");
        if (ch.psd) write_psd(g.get(), *ch.psd, file, ch.path + "/psd");
        if (ch.crosscheck) write_crosscheck(g.get(), *ch.crosscheck, file, ch.path + "/crosscheck");
        if (ch.stats.empty()) continue;
        Handle gcpl = h5::group_create_plist(file, ch.path + "/allan");
        Handle allan = check(H5Gcreate2(g.get(), "allan", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT),
                             H5Gclose, file, ch.path + "/allan", "H5Gcreate2");
        for (const auto& [name, s] : ch.stats)
          write_stat(allan.get(), name, s, file, ch.path + "/allan/" + name);
      }
    }
    h5::write_memory_file(f, atomic.temp_path().string(), file);
  }
  atomic.commit();
}

// A channel group's own attributes (both readers); its groups are read by the caller.
ChannelResult read_channel_attributes(hid_t g, const std::string& file, const std::string& gp) {
  ChannelResult ch;
  ch.path = gp;
  ch.units = read_string_attr(g, "units", file, gp);
  ch.sample_rate_hz = read_double_attr(g, "sample_rate_hz", file, gp);
  ch.n_samples = static_cast<std::int64_t>(read_double_attr(g, "n_samples", file, gp));
  ch.n_gaps = static_cast<std::int64_t>(read_double_attr(g, "n_gaps", file, gp));
  ch.data_type = read_string_attr(g, "data_type", file, gp);
  ch.status = read_string_attr(g, "status", file, gp);
  ch.notes = read_string_attr(g, "notes", file, gp);
  return ch;
}

// A results file opened for reading, with its root attributes read into `r` (both readers).
struct OpenResults {
  Handle file, root;
};

OpenResults open_results(const std::string& file, RecordingResult& r) {
  h5::quiet_library();
  if (H5Fis_hdf5(file.c_str()) <= 0) throw Error(file, "", "not an HDF5 results file");
  OpenResults o;
  o.file = check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, file, "", "H5Fopen");
  o.root = check(H5Gopen2(o.file.get(), "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
  r.device_id = read_string_attr(o.root.get(), "device_id", file, "/");
  r.source_file = read_string_attr(o.root.get(), "source_file", file, "/");
  r.tool_version = read_string_attr(o.root.get(), "tool_version", file, "/");
  r.created_utc = read_string_attr(o.root.get(), "created_utc", file, "/");
  r.command_line = read_string_attr(o.root.get(), "command_line", file, "/");
  return o;
}

RecordingResult read_results(const std::filesystem::path& path) {
  const std::string file = path.string();
  RecordingResult r;
  OpenResults o = open_results(file, r);
  Handle& f = o.file;

  struct Found {
    std::vector<std::string> groups;
  } found;
  auto visit = [](hid_t obj, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    if (info->type != H5O_TYPE_GROUP || !name || name[0] == '.') return 0;
    // Channel groups carry `status` and `data_type` (fit/ carries a status of its own).
    if (H5Aexists_by_name(obj, name, "status", H5P_DEFAULT) > 0 &&
        H5Aexists_by_name(obj, name, "data_type", H5P_DEFAULT) > 0)
      static_cast<Found*>(data)->groups.push_back(std::string("/") + name);
    return 0;
  };
  if (H5Ovisit2(f.get(), H5_INDEX_NAME, H5_ITER_INC, visit, &found, H5O_INFO_BASIC) < 0)
    throw Error(file, "", "cannot walk the results file");
  for (const std::string& gp : found.groups) {
    Handle g = check(H5Gopen2(f.get(), gp.c_str(), H5P_DEFAULT), H5Gclose, file, gp, "H5Gopen2");
    ChannelResult ch = read_channel_attributes(g.get(), file, gp);
    if (H5Lexists(g.get(), "allan", H5P_DEFAULT) > 0) {
      for (const kernels::Stat s : kernels::all_stats()) {
        const std::string name(kernels::stat_name(s));
        const std::string sp = gp + "/allan/" + name;
        if (H5Lexists(g.get(), ("allan/" + name).c_str(), H5P_DEFAULT) <= 0) continue;
        Handle sg = check(H5Gopen2(g.get(), ("allan/" + name).c_str(), H5P_DEFAULT), H5Gclose, file,
                          sp, "H5Gopen2");
        kernels::StatResult st;
        st.m = h5::read_int64s(sg.get(), "m", file, sp);
        st.tau_s = h5::read_doubles(sg.get(), "tau", file, sp);
        st.dev = h5::read_doubles(sg.get(), "dev", file, sp);
        st.n = h5::read_int64s(sg.get(), "n", file, sp);
        if (H5Lexists(sg.get(), "edf", H5P_DEFAULT) > 0) {
          st.edf = h5::read_doubles(sg.get(), "edf", file, sp);
          st.dev_lo = h5::read_doubles(sg.get(), "dev_lo", file, sp);
          st.dev_hi = h5::read_doubles(sg.get(), "dev_hi", file, sp);
          const auto a = h5::read_int64s(sg.get(), "alpha", file, sp);
          st.alpha.assign(a.begin(), a.end());
          h5::read_attribute(sg.get(), "confidence", st.confidence, file, sp);
        }
        ch.stats.emplace_back(name, std::move(st));
      }
    }
    if (H5Lexists(g.get(), "fit", H5P_DEFAULT) > 0) {
      Handle fg =
          check(H5Gopen2(g.get(), "fit", H5P_DEFAULT), H5Gclose, file, gp + "/fit", "H5Gopen2");
      ch.fit = read_fit(fg.get(), file, gp + "/fit");
    }
    if (H5Lexists(g.get(), "psd_fit", H5P_DEFAULT) > 0) {
      Handle fg = check(H5Gopen2(g.get(), "psd_fit", H5P_DEFAULT), H5Gclose, file, gp + "/psd_fit",
                        "H5Gopen2");
      ch.psd_fit = read_fit(fg.get(), file, gp + "/psd_fit");
    }
    if (H5Lexists(g.get(), "psd", H5P_DEFAULT) > 0) {
      const std::string pp = gp + "/psd";
      Handle pg = check(H5Gopen2(g.get(), "psd", H5P_DEFAULT), H5Gclose, file, pp, "H5Gopen2");
      PsdRecord psd;
      psd.f = h5::read_doubles(pg.get(), "f", file, pp);
      psd.psd = h5::read_doubles(pg.get(), "psd", file, pp);
      psd.edf = h5::read_doubles(pg.get(), "edf", file, pp);
      psd.n_avg = h5::read_int64s(pg.get(), "n_avg", file, pp);
      h5::read_attribute(pg.get(), "method", psd.method, file, pp);
      h5::read_attribute(pg.get(), "convention", psd.convention, file, pp);
      ch.psd = std::move(psd);
    }
    if (H5Lexists(g.get(), "crosscheck", H5P_DEFAULT) > 0) {
      const std::string cp = gp + "/crosscheck";
      Handle cg =
          check(H5Gopen2(g.get(), "crosscheck", H5P_DEFAULT), H5Gclose, file, cp, "H5Gopen2");
      CrosscheckRecord c;
      c.tau = h5::read_doubles(cg.get(), "tau", file, cp);
      c.avar_time = h5::read_doubles(cg.get(), "avar_time", file, cp);
      c.avar_psd = h5::read_doubles(cg.get(), "avar_psd", file, cp);
      c.ratio = h5::read_doubles(cg.get(), "ratio", file, cp);
      const auto valid = h5::read_int64s(cg.get(), "valid", file, cp);
      c.valid.assign(valid.begin(), valid.end());
      h5::read_attribute(cg.get(), "max_abs_log10_ratio", c.max_abs_log10_ratio, file, cp);
      if (H5Aexists(cg.get(), "worst_tau") > 0)
        h5::read_attribute(cg.get(), "worst_tau", c.worst_tau, file, cp);
      ch.crosscheck = std::move(c);
    }
    r.channels.push_back(std::move(ch));
  }
  return r;
}

namespace {

constexpr const char* kTermNames[5] = {"R", "K", "B", "N", "Q"};

// The fit/ terms in datasheet units and the attributes summary_rows uses; the per-tau model
// curve, the read-outs and the channel-unit values are left unread.
FitRecord read_fit_summary(hid_t g, const std::string& file, const std::string& object) {
  FitRecord fit;
  const auto term = h5::read_strings(g, "term", file, object);
  const auto detected = h5::read_int64s(g, "detected", file, object);
  const auto value_ds = h5::read_doubles(g, "value_datasheet", file, object);
  const auto sigma_ds = h5::read_doubles(g, "sigma_datasheet", file, object);
  const auto unit_ds = h5::read_strings(g, "unit_datasheet", file, object);
  const auto upper_ds = H5Lexists(g, "upper_datasheet", H5P_DEFAULT) > 0
                            ? h5::read_doubles(g, "upper_datasheet", file, object)
                            : std::vector<double>(term.size(), std::nan(""));
  for (std::size_t i = 0; i < term.size(); ++i) {
    TermRecord t;
    t.term = term[i];
    t.detected = detected.at(i) != 0;
    t.value_datasheet = value_ds.at(i);
    t.sigma_datasheet = sigma_ds.at(i);
    t.upper_datasheet = upper_ds.at(i);
    t.unit_datasheet = unit_ds.at(i);
    fit.terms.push_back(std::move(t));
  }
  h5::read_attribute(g, "chi2_dof", fit.chi2_dof, file, object);
  return fit;
}

// Depth-first, in name order (the order H5Ovisit gives read_results), collects the channel
// groups under `g` (`path` its name): groups with `status` and `data_type` attributes. A
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
    if (H5Aexists(o.get(), "status") > 0 && H5Aexists(o.get(), "data_type") > 0)
      out.push_back(child);
    else
      find_channel_groups(o.get(), child, file, out);
  }
}

}  // namespace

RecordingResult read_summary_results(const std::filesystem::path& path) {
  const std::string file = path.string();
  RecordingResult r;
  OpenResults o = open_results(file, r);
  Handle& f = o.file;
  Handle& root = o.root;
  std::vector<std::string> groups;
  find_channel_groups(root.get(), "", file, groups);
  for (const std::string& gp : groups) {
    Handle g = check(H5Gopen2(f.get(), gp.c_str(), H5P_DEFAULT), H5Gclose, file, gp, "H5Gopen2");
    ChannelResult ch = read_channel_attributes(g.get(), file, gp);
    if (H5Lexists(g.get(), "fit", H5P_DEFAULT) > 0) {
      Handle fg =
          check(H5Gopen2(g.get(), "fit", H5P_DEFAULT), H5Gclose, file, gp + "/fit", "H5Gopen2");
      ch.fit = read_fit_summary(fg.get(), file, gp + "/fit");
    }
    if (H5Lexists(g.get(), "psd_fit", H5P_DEFAULT) > 0) {
      const std::string pp = gp + "/psd_fit";
      Handle pg = check(H5Gopen2(g.get(), "psd_fit", H5P_DEFAULT), H5Gclose, file, pp, "H5Gopen2");
      FitRecord pf;
      double agree = -1;
      h5::read_attribute(pg.get(), "agrees_with_fit", agree, file, pp);
      pf.agree = static_cast<int>(agree);
      h5::read_attribute(pg.get(), "max_abs_z", pf.max_abs_z, file, pp);
      ch.psd_fit = std::move(pf);
    }
    if (H5Lexists(g.get(), "crosscheck", H5P_DEFAULT) > 0) {
      const std::string cp = gp + "/crosscheck";
      Handle cg =
          check(H5Gopen2(g.get(), "crosscheck", H5P_DEFAULT), H5Gclose, file, cp, "H5Gopen2");
      CrosscheckRecord c;
      h5::read_attribute(cg.get(), "max_abs_log10_ratio", c.max_abs_log10_ratio, file, cp);
      h5::read_attribute(cg.get(), "worst_tau", c.worst_tau, file, cp);
      ch.crosscheck = std::move(c);
    }
    r.channels.push_back(std::move(ch));
  }
  return r;
}

std::vector<SummaryRow> summary_rows(const RecordingResult& r) {
  std::vector<SummaryRow> rows;
  for (const ChannelResult& ch : r.channels) {
    SummaryRow row{r.device_id, ch.path, ch.units, ch.n_samples, ch.status, r.source_file};
    if (ch.fit) {
      for (const TermRecord& t : ch.fit->terms)
        for (std::size_t i = 0; i < row.value.size(); ++i) {
          if (t.term != kTermNames[i]) continue;
          row.value[i] = t.value_datasheet;
          row.sigma[i] = t.sigma_datasheet;
          row.unit[i] = t.unit_datasheet;
          row.detected[i] = t.detected ? 1 : 0;
          row.upper[i] = t.upper_datasheet;
        }
      row.chi2_dof = ch.fit->chi2_dof;
    }
    if (ch.crosscheck) {
      row.max_abs_log10_ratio = ch.crosscheck->max_abs_log10_ratio;
      row.crosscheck_worst_tau = ch.crosscheck->worst_tau;
    }
    if (ch.psd_fit && ch.psd_fit->agree >= 0) {
      row.fits_agree = static_cast<std::int8_t>(ch.psd_fit->agree);
      row.fits_max_abs_z = ch.psd_fit->max_abs_z;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

namespace {

// Numbers in the CSV with 7 significant digits (a datasheet needs 2 or 3, the uncertainty
// another); empty where there is no value.
std::string csv_number(double v) {
  if (std::isnan(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.7g", v);
  return buf;
}

// In-memory layout of one /summary record: variable-length UTF-8 strings, numbers, and per
// term of eq. (3) its datasheet value, sigma, unit and detection flag.
struct SummaryRecord {
  const char* device_id;
  const char* channel;
  const char* units;
  std::int64_t n_samples;
  const char* status;
  const char* source_file;
  double value[5];
  double sigma[5];
  const char* unit[5];
  std::uint8_t detected[5];
  double chi2_dof;
  double max_abs_log10_ratio;
  double crosscheck_worst_tau;
  std::int8_t fits_agree;
  double fits_max_abs_z;
  double upper[5];
  const char* spec_status;
  const char* spec_detail;
  std::uint8_t outlier;
  const char* outlier_terms;
  const char* spec_term_status[5];
};

// A variable-length UTF-8 string type (every string column of the summary files).
Handle vlen_string_type(const std::string& file, const std::string& object) {
  Handle str = check(H5Tcopy(H5T_C_S1), H5Tclose, file, object, "H5Tcopy");
  H5Tset_size(str.get(), H5T_VARIABLE);
  H5Tset_cset(str.get(), H5T_CSET_UTF8);
  return str;
}

Handle summary_type(const std::string& file) {
  Handle str = vlen_string_type(file, "/summary");
  Handle t = check(H5Tcreate(H5T_COMPOUND, sizeof(SummaryRecord)), H5Tclose, file, "/summary",
                   "H5Tcreate");
  H5Tinsert(t.get(), "device_id", offsetof(SummaryRecord, device_id), str.get());
  H5Tinsert(t.get(), "channel", offsetof(SummaryRecord, channel), str.get());
  H5Tinsert(t.get(), "units", offsetof(SummaryRecord, units), str.get());
  H5Tinsert(t.get(), "n_samples", offsetof(SummaryRecord, n_samples), H5T_NATIVE_INT64);
  H5Tinsert(t.get(), "status", offsetof(SummaryRecord, status), str.get());
  H5Tinsert(t.get(), "source_file", offsetof(SummaryRecord, source_file), str.get());
  for (std::size_t i = 0; i < 5; ++i) {
    const std::string n = kTermNames[i];
    H5Tinsert(t.get(), n.c_str(), offsetof(SummaryRecord, value) + i * sizeof(double),
              H5T_NATIVE_DOUBLE);
    H5Tinsert(t.get(), (n + "_sigma").c_str(), offsetof(SummaryRecord, sigma) + i * sizeof(double),
              H5T_NATIVE_DOUBLE);
    H5Tinsert(t.get(), (n + "_unit").c_str(),
              offsetof(SummaryRecord, unit) + i * sizeof(const char*), str.get());
    H5Tinsert(t.get(), (n + "_detected").c_str(), offsetof(SummaryRecord, detected) + i,
              H5T_NATIVE_UINT8);
  }
  H5Tinsert(t.get(), "chi2_dof", offsetof(SummaryRecord, chi2_dof), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "max_abs_log10_ratio", offsetof(SummaryRecord, max_abs_log10_ratio),
            H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "crosscheck_worst_tau", offsetof(SummaryRecord, crosscheck_worst_tau),
            H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "fits_agree", offsetof(SummaryRecord, fits_agree), H5T_NATIVE_INT8);
  H5Tinsert(t.get(), "fits_max_abs_z", offsetof(SummaryRecord, fits_max_abs_z), H5T_NATIVE_DOUBLE);
  // Columns added after the first release go last, so that readers by position keep working.
  for (std::size_t i = 0; i < 5; ++i)
    H5Tinsert(t.get(), (std::string(kTermNames[i]) + "_upper").c_str(),
              offsetof(SummaryRecord, upper) + i * sizeof(double), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "spec_status", offsetof(SummaryRecord, spec_status), str.get());
  H5Tinsert(t.get(), "spec_detail", offsetof(SummaryRecord, spec_detail), str.get());
  H5Tinsert(t.get(), "outlier", offsetof(SummaryRecord, outlier), H5T_NATIVE_UINT8);
  H5Tinsert(t.get(), "outlier_terms", offsetof(SummaryRecord, outlier_terms), str.get());
  for (std::size_t i = 0; i < 5; ++i)
    H5Tinsert(t.get(), (std::string(kTermNames[i]) + "_spec_status").c_str(),
              offsetof(SummaryRecord, spec_term_status) + i * sizeof(const char*), str.get());
  return t;
}

// In-memory layout of one /statistics record.
struct StatisticsRecord {
  const char* channel;
  const char* term;
  const char* unit;
  std::int64_t n;
  std::int64_t n_detected;
  std::int64_t n_outliers;
  double median, spread, p5, p25, p75, p95, min, max;
};

Handle statistics_type(const std::string& file) {
  Handle str = vlen_string_type(file, "/statistics");
  Handle t = check(H5Tcreate(H5T_COMPOUND, sizeof(StatisticsRecord)), H5Tclose, file, "/statistics",
                   "H5Tcreate");
  H5Tinsert(t.get(), "channel", offsetof(StatisticsRecord, channel), str.get());
  H5Tinsert(t.get(), "term", offsetof(StatisticsRecord, term), str.get());
  H5Tinsert(t.get(), "unit", offsetof(StatisticsRecord, unit), str.get());
  H5Tinsert(t.get(), "n", offsetof(StatisticsRecord, n), H5T_NATIVE_INT64);
  H5Tinsert(t.get(), "n_detected", offsetof(StatisticsRecord, n_detected), H5T_NATIVE_INT64);
  H5Tinsert(t.get(), "n_outliers", offsetof(StatisticsRecord, n_outliers), H5T_NATIVE_INT64);
  H5Tinsert(t.get(), "median", offsetof(StatisticsRecord, median), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "spread", offsetof(StatisticsRecord, spread), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "p5", offsetof(StatisticsRecord, p5), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "p25", offsetof(StatisticsRecord, p25), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "p75", offsetof(StatisticsRecord, p75), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "p95", offsetof(StatisticsRecord, p95), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "min", offsetof(StatisticsRecord, min), H5T_NATIVE_DOUBLE);
  H5Tinsert(t.get(), "max", offsetof(StatisticsRecord, max), H5T_NATIVE_DOUBLE);
  return t;
}

// Writes `recs` (n records of `type`) as the 1-D compound dataset `name` of file `f`.
void write_compound(hid_t f, const char* name, hid_t type, const void* recs, hsize_t n,
                    const std::string& file) {
  const std::string object = std::string("/") + name;
  Handle space =
      check(H5Screate_simple(1, &n, nullptr), H5Sclose, file, object, "H5Screate_simple");
  Handle dcpl = h5::dataset_create_plist(file, object);
  Handle ds = check(H5Dcreate2(f, name, type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                    H5Dclose, file, object, "H5Dcreate2");
  if (n > 0)
    check(H5Dwrite(ds.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, recs), file, object, "H5Dwrite");
  if (ds.close() < 0) throw Error(file, object, "H5Dclose failed");
}

std::string statistics_csv(const std::vector<StatisticsRow>& statistics) {
  std::ostringstream csv;
  csv << "channel,term,unit,n,n_detected,n_outliers,median,spread,p5,p25,p75,p95,min,max\n";
  for (const StatisticsRow& s : statistics)
    csv << csv_field(s.channel) << ',' << csv_field(s.term) << ',' << csv_field(s.unit) << ','
        << s.n << ',' << s.n_detected << ',' << s.n_outliers << ',' << csv_number(s.median) << ','
        << csv_number(s.spread) << ',' << csv_number(s.p5) << ',' << csv_number(s.p25) << ','
        << csv_number(s.p75) << ',' << csv_number(s.p95) << ',' << csv_number(s.min) << ','
        << csv_number(s.max) << '\n';
  return csv.str();
}

}  // namespace

void write_lot_summary(const std::filesystem::path& outdir, const std::vector<SummaryRow>& rows,
                       const std::vector<StatisticsRow>& statistics,
                       const std::vector<std::pair<std::string, std::string>>& attributes) {
  h5::quiet_library();
  std::ostringstream csv;
  csv << "device_id,channel,units,n_samples,status,source_file";
  for (const char* t : kTermNames)
    csv << ',' << t << ',' << t << "_sigma," << t << "_unit," << t << "_detected";
  csv << ",chi2_dof,max_abs_log10_ratio,crosscheck_worst_tau,fits_agree,fits_max_abs_z";
  for (const char* t : kTermNames)
    csv << ',' << t << "_upper";
  csv << ",spec_status,spec_detail,outlier,outlier_terms";
  for (const char* t : kTermNames)
    csv << ',' << t << "_spec_status";
  csv << '\n';
  for (const SummaryRow& r : rows) {
    csv << csv_field(r.device_id) << ',' << csv_field(r.channel) << ',' << csv_field(r.units) << ','
        << r.n_samples << ',' << csv_field(r.status) << ',' << csv_field(r.source_file);
    for (std::size_t i = 0; i < 5; ++i)
      csv << ',' << csv_number(r.value[i]) << ',' << csv_number(r.sigma[i]) << ','
          << csv_field(r.unit[i]) << ','
          << (std::isnan(r.value[i]) ? ""
              : r.detected[i]        ? "1"
                                     : "0");
    csv << ',' << csv_number(r.chi2_dof) << ',' << csv_number(r.max_abs_log10_ratio) << ','
        << csv_number(r.crosscheck_worst_tau) << ','
        << (r.fits_agree < 0 ? "" : std::to_string(r.fits_agree)) << ','
        << csv_number(r.fits_max_abs_z);
    for (const double u : r.upper)
      csv << ',' << csv_number(u);
    csv << ',' << csv_field(r.spec_status) << ',' << csv_field(r.spec_detail) << ','
        << static_cast<int>(r.outlier) << ',' << csv_field(r.outlier_terms);
    for (const std::string& t : r.spec_term_status)
      csv << ',' << csv_field(t);
    csv << '\n';
  }
  write_text_atomic(outdir / "lot_summary.csv", csv.str());
  write_text_atomic(outdir / "lot_statistics.csv", statistics_csv(statistics));

  const std::filesystem::path h5path = outdir / "lot_summary.h5";
  const std::string file = h5path.string();
  AtomicFile atomic(h5path);
  {
    Handle f = h5::create_memory_file(file);
    std::vector<SummaryRecord> recs;
    recs.reserve(rows.size());
    for (const SummaryRow& r : rows) {
      SummaryRecord rec{};
      rec.device_id = r.device_id.c_str();
      rec.channel = r.channel.c_str();
      rec.units = r.units.c_str();
      rec.n_samples = r.n_samples;
      rec.status = r.status.c_str();
      rec.source_file = r.source_file.c_str();
      for (std::size_t i = 0; i < 5; ++i) {
        rec.value[i] = r.value[i];
        rec.sigma[i] = r.sigma[i];
        rec.unit[i] = r.unit[i].c_str();
        rec.detected[i] = r.detected[i];
      }
      rec.chi2_dof = r.chi2_dof;
      rec.max_abs_log10_ratio = r.max_abs_log10_ratio;
      rec.crosscheck_worst_tau = r.crosscheck_worst_tau;
      rec.fits_agree = r.fits_agree;
      rec.fits_max_abs_z = r.fits_max_abs_z;
      for (std::size_t i = 0; i < 5; ++i)
        rec.upper[i] = r.upper[i];
      rec.spec_status = r.spec_status.c_str();
      rec.spec_detail = r.spec_detail.c_str();
      rec.outlier = r.outlier;
      rec.outlier_terms = r.outlier_terms.c_str();
      for (std::size_t i = 0; i < 5; ++i)
        rec.spec_term_status[i] = r.spec_term_status[i].c_str();
      recs.push_back(rec);
    }
    Handle type = summary_type(file);
    write_compound(f.get(), "summary", type.get(), recs.data(), recs.size(), file);
    std::vector<StatisticsRecord> srecs;
    srecs.reserve(statistics.size());
    for (const StatisticsRow& s : statistics)
      srecs.push_back({s.channel.c_str(), s.term.c_str(), s.unit.c_str(), s.n, s.n_detected,
                       s.n_outliers, s.median, s.spread, s.p5, s.p25, s.p75, s.p95, s.min, s.max});
    Handle stype = statistics_type(file);
    write_compound(f.get(), "statistics", stype.get(), srecs.data(), srecs.size(), file);
    if (!attributes.empty()) {
      Handle root = check(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
      for (const auto& [name, value] : attributes)
        h5::write_attribute(root.get(), name, value, file, "/");
    }
    h5::write_memory_file(f, atomic.temp_path().string(), file);
  }
  atomic.commit();
}

std::vector<SummaryRow> read_lot_summary(const std::filesystem::path& h5_path) {
  h5::quiet_library();
  const std::string file = h5_path.string();
  Handle f =
      check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, file, "", "H5Fopen");
  Handle ds =
      check(H5Dopen2(f.get(), "summary", H5P_DEFAULT), H5Dclose, file, "/summary", "H5Dopen2");
  Handle space = check(H5Dget_space(ds.get()), H5Sclose, file, "/summary", "H5Dget_space");
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  std::vector<SummaryRecord> recs(static_cast<std::size_t>(n));
  Handle type = summary_type(file);
  // Files written before a column existed leave it at its initial value (H5Dread converts
  // only the members the file has).
  for (SummaryRecord& r : recs) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    r = SummaryRecord{};  // strings nullptr: read back as ""; outlier 0
    r.chi2_dof = r.max_abs_log10_ratio = r.crosscheck_worst_tau = r.fits_max_abs_z = nan;
    r.fits_agree = -1;
    for (std::size_t i = 0; i < 5; ++i)
      r.value[i] = r.sigma[i] = r.upper[i] = nan;
  }
  // Read only the members the file has: a memory type with members the file lacks makes
  // H5Dread fail, so the older files' reading type is the intersection, same offsets.
  Handle ftype = check(H5Dget_type(ds.get()), H5Tclose, file, "/summary", "H5Dget_type");
  Handle rtype = check(H5Tcreate(H5T_COMPOUND, sizeof(SummaryRecord)), H5Tclose, file, "/summary",
                       "H5Tcreate");
  const int n_members = H5Tget_nmembers(type.get());
  for (int i = 0; i < n_members; ++i) {
    char* name = H5Tget_member_name(type.get(), static_cast<unsigned>(i));
    if (!name) continue;
    const int fi = H5Tget_member_index(ftype.get(), name);
    if (fi >= 0) {
      Handle mt = check(H5Tget_member_type(type.get(), static_cast<unsigned>(i)), H5Tclose, file,
                        "/summary", "H5Tget_member_type");
      // HDF5 does not convert between character sets: read a string in the file's own (an
      // older writer may have used ASCII); the bytes are the same for ASCII text.
      if (H5Tget_class(mt.get()) == H5T_STRING) {
        Handle fm = check(H5Tget_member_type(ftype.get(), static_cast<unsigned>(fi)), H5Tclose,
                          file, "/summary", "H5Tget_member_type");
        if (H5Tget_class(fm.get()) == H5T_STRING) H5Tset_cset(mt.get(), H5Tget_cset(fm.get()));
      }
      H5Tinsert(rtype.get(), name, H5Tget_member_offset(type.get(), static_cast<unsigned>(i)),
                mt.get());
    }
    H5free_memory(name);
  }
  if (n > 0)
    check(H5Dread(ds.get(), rtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, recs.data()), file,
          "/summary", "H5Dread");
  const auto str = [](const char* p) { return std::string(p ? p : ""); };
  std::vector<SummaryRow> rows;
  for (const SummaryRecord& r : recs) {
    SummaryRow row{str(r.device_id), str(r.channel), str(r.units),
                   r.n_samples,      str(r.status),  str(r.source_file)};
    for (std::size_t i = 0; i < 5; ++i) {
      row.value[i] = r.value[i];
      row.sigma[i] = r.sigma[i];
      row.unit[i] = str(r.unit[i]);
      row.detected[i] = r.detected[i];
    }
    row.chi2_dof = r.chi2_dof;
    row.max_abs_log10_ratio = r.max_abs_log10_ratio;
    row.crosscheck_worst_tau = r.crosscheck_worst_tau;
    row.fits_agree = r.fits_agree;
    row.fits_max_abs_z = r.fits_max_abs_z;
    for (std::size_t i = 0; i < 5; ++i)
      row.upper[i] = r.upper[i];
    row.spec_status = str(r.spec_status);
    row.spec_detail = str(r.spec_detail);
    row.outlier = r.outlier;
    row.outlier_terms = str(r.outlier_terms);
    for (std::size_t i = 0; i < 5; ++i)
      row.spec_term_status[i] = str(r.spec_term_status[i]);
    rows.push_back(std::move(row));
  }
  if (n > 0) H5Dvlen_reclaim(rtype.get(), space.get(), H5P_DEFAULT, recs.data());
  return rows;
}

std::vector<StatisticsRow> read_lot_statistics(const std::filesystem::path& h5_path) {
  h5::quiet_library();
  const std::string file = h5_path.string();
  Handle f =
      check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, file, "", "H5Fopen");
  if (H5Lexists(f.get(), "statistics", H5P_DEFAULT) <= 0) return {};
  Handle ds = check(H5Dopen2(f.get(), "statistics", H5P_DEFAULT), H5Dclose, file, "/statistics",
                    "H5Dopen2");
  Handle space = check(H5Dget_space(ds.get()), H5Sclose, file, "/statistics", "H5Dget_space");
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  std::vector<StatisticsRecord> recs(static_cast<std::size_t>(n), StatisticsRecord{});
  Handle type = statistics_type(file);
  if (n > 0)
    check(H5Dread(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, recs.data()), file,
          "/statistics", "H5Dread");
  const auto str = [](const char* p) { return std::string(p ? p : ""); };
  std::vector<StatisticsRow> out;
  for (const StatisticsRecord& r : recs)
    out.push_back({str(r.channel), str(r.term), str(r.unit), r.n, r.n_detected, r.n_outliers,
                   r.median, r.spread, r.p5, r.p25, r.p75, r.p95, r.min, r.max});
  if (n > 0) H5Dvlen_reclaim(type.get(), space.get(), H5P_DEFAULT, recs.data());
  return out;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

}  // namespace allanlot::io
