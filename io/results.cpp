#include "io/results.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"

#include <cstddef>
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
    Handle f = check(H5Fcreate(atomic.temp_path().c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT),
                     H5Fclose, file, "", "H5Fcreate (is the output directory writable?)");
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
        if (ch.stats.empty()) continue;
        Handle gcpl = h5::group_create_plist(file, ch.path + "/allan");
        Handle allan = check(H5Gcreate2(g.get(), "allan", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT),
                             H5Gclose, file, ch.path + "/allan", "H5Gcreate2");
        for (const auto& [name, s] : ch.stats)
          write_stat(allan.get(), name, s, file, ch.path + "/allan/" + name);
      }
    }
    if (f.close() < 0) throw Error(file, "", "H5Fclose failed while flushing (disk full?)");
  }
  atomic.commit();
}

RecordingResult read_results(const std::filesystem::path& path) {
  h5::quiet_library();
  const std::string file = path.string();
  if (H5Fis_hdf5(file.c_str()) <= 0) throw Error(file, "", "not an HDF5 results file");
  Handle f =
      check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, file, "", "H5Fopen");
  RecordingResult r;
  Handle root = check(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
  r.device_id = read_string_attr(root.get(), "device_id", file, "/");
  r.source_file = read_string_attr(root.get(), "source_file", file, "/");
  r.tool_version = read_string_attr(root.get(), "tool_version", file, "/");
  r.created_utc = read_string_attr(root.get(), "created_utc", file, "/");
  r.command_line = read_string_attr(root.get(), "command_line", file, "/");

  // Channel groups are the groups that carry a `status` attribute.
  struct Found {
    std::vector<std::string> groups;
  } found;
  auto visit = [](hid_t obj, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    if (info->type != H5O_TYPE_GROUP || !name || name[0] == '.') return 0;
    if (H5Aexists_by_name(obj, name, "status", H5P_DEFAULT) > 0)
      static_cast<Found*>(data)->groups.push_back(std::string("/") + name);
    return 0;
  };
  if (H5Ovisit2(f.get(), H5_INDEX_NAME, H5_ITER_INC, visit, &found, H5O_INFO_BASIC) < 0)
    throw Error(file, "", "cannot walk the results file");
  for (const std::string& gp : found.groups) {
    Handle g = check(H5Gopen2(f.get(), gp.c_str(), H5P_DEFAULT), H5Gclose, file, gp, "H5Gopen2");
    ChannelResult ch;
    ch.path = gp;
    ch.units = read_string_attr(g.get(), "units", file, gp);
    ch.sample_rate_hz = read_double_attr(g.get(), "sample_rate_hz", file, gp);
    ch.n_samples = static_cast<std::int64_t>(read_double_attr(g.get(), "n_samples", file, gp));
    ch.n_gaps = static_cast<std::int64_t>(read_double_attr(g.get(), "n_gaps", file, gp));
    ch.data_type = read_string_attr(g.get(), "data_type", file, gp);
    ch.status = read_string_attr(g.get(), "status", file, gp);
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
    r.channels.push_back(std::move(ch));
  }
  return r;
}

std::vector<SummaryRow> summary_rows(const RecordingResult& r) {
  std::vector<SummaryRow> rows;
  for (const ChannelResult& ch : r.channels)
    rows.push_back({r.device_id, ch.path, ch.units, ch.n_samples, ch.status, r.source_file});
  return rows;
}

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

// In-memory layout of one /summary record: variable-length UTF-8 strings and an int64.
struct SummaryRecord {
  const char* device_id;
  const char* channel;
  const char* units;
  std::int64_t n_samples;
  const char* status;
  const char* source_file;
};

Handle summary_type(const std::string& file) {
  Handle str = check(H5Tcopy(H5T_C_S1), H5Tclose, file, "/summary", "H5Tcopy");
  H5Tset_size(str.get(), H5T_VARIABLE);
  H5Tset_cset(str.get(), H5T_CSET_UTF8);
  Handle t = check(H5Tcreate(H5T_COMPOUND, sizeof(SummaryRecord)), H5Tclose, file, "/summary",
                   "H5Tcreate");
  H5Tinsert(t.get(), "device_id", offsetof(SummaryRecord, device_id), str.get());
  H5Tinsert(t.get(), "channel", offsetof(SummaryRecord, channel), str.get());
  H5Tinsert(t.get(), "units", offsetof(SummaryRecord, units), str.get());
  H5Tinsert(t.get(), "n_samples", offsetof(SummaryRecord, n_samples), H5T_NATIVE_INT64);
  H5Tinsert(t.get(), "status", offsetof(SummaryRecord, status), str.get());
  H5Tinsert(t.get(), "source_file", offsetof(SummaryRecord, source_file), str.get());
  return t;
}

}  // namespace

void write_lot_summary(const std::filesystem::path& outdir, const std::vector<SummaryRow>& rows) {
  h5::quiet_library();
  std::ostringstream csv;
  csv << "device_id,channel,units,n_samples,status,source_file\n";
  for (const SummaryRow& r : rows)
    csv << csv_field(r.device_id) << ',' << csv_field(r.channel) << ',' << csv_field(r.units) << ','
        << r.n_samples << ',' << csv_field(r.status) << ',' << csv_field(r.source_file) << '\n';
  write_text_atomic(outdir / "lot_summary.csv", csv.str());

  const std::filesystem::path h5path = outdir / "lot_summary.h5";
  const std::string file = h5path.string();
  AtomicFile atomic(h5path);
  {
    Handle f = check(H5Fcreate(atomic.temp_path().c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT),
                     H5Fclose, file, "", "H5Fcreate");
    std::vector<SummaryRecord> recs;
    recs.reserve(rows.size());
    for (const SummaryRow& r : rows)
      recs.push_back({r.device_id.c_str(), r.channel.c_str(), r.units.c_str(), r.n_samples,
                      r.status.c_str(), r.source_file.c_str()});
    Handle type = summary_type(file);
    const hsize_t n = recs.size();
    Handle space =
        check(H5Screate_simple(1, &n, nullptr), H5Sclose, file, "/summary", "H5Screate_simple");
    Handle dcpl = h5::dataset_create_plist(file, "/summary");
    Handle ds = check(H5Dcreate2(f.get(), "summary", type.get(), space.get(), H5P_DEFAULT,
                                 dcpl.get(), H5P_DEFAULT),
                      H5Dclose, file, "/summary", "H5Dcreate2");
    if (n > 0)
      check(H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, recs.data()), file,
            "/summary", "H5Dwrite");
    ds.close();
    if (f.close() < 0) throw Error(file, "", "H5Fclose failed while flushing (disk full?)");
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
  if (n > 0)
    check(H5Dread(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, recs.data()), file,
          "/summary", "H5Dread");
  std::vector<SummaryRow> rows;
  for (const SummaryRecord& r : recs)
    rows.push_back({r.device_id ? r.device_id : "", r.channel ? r.channel : "",
                    r.units ? r.units : "", r.n_samples, r.status ? r.status : "",
                    r.source_file ? r.source_file : ""});
  if (n > 0) H5Dvlen_reclaim(type.get(), space.get(), H5P_DEFAULT, recs.data());
  return rows;
}

}  // namespace allanlot::io
