#include "io/report_data.hpp"

#include "io/error.hpp"
#include "io/hdf5_handle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

namespace allanlot::io {

using h5::check;
using h5::Handle;

namespace {

std::string format_number(double v) {
  if (std::isnan(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

bool link_exists(hid_t loc, const std::string& name) {
  return H5Lexists(loc, name.c_str(), H5P_DEFAULT) > 0;
}

// Strings of a 1-D dataset or of a compound member, whether stored variable-length or
// fixed-length (read_strings in hdf5_handle handles only the former, which allanlot writes;
// other writers, h5py with numpy bytes for one, use the latter).
std::vector<std::string> read_any_strings(hid_t ds, hid_t file_type, std::size_t n,
                                          const std::string& file, const std::string& object) {
  std::vector<std::string> out;
  if (n == 0) return out;
  if (H5Tis_variable_str(file_type) > 0) {
    Handle mem = check(H5Tcopy(H5T_C_S1), H5Tclose, file, object, "H5Tcopy");
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(file_type));
    std::vector<char*> ptrs(n, nullptr);
    check(H5Dread(ds, mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), file, object,
          "H5Dread");
    for (char* p : ptrs)
      out.emplace_back(p ? p : "");
    Handle space = check(H5Dget_space(ds), H5Sclose, file, object, "H5Dget_space");
    H5Dvlen_reclaim(mem.get(), space.get(), H5P_DEFAULT, ptrs.data());
    return out;
  }
  const std::size_t size = H5Tget_size(file_type);
  if (size == 0 || size > 4096) throw Error(file, object, "unusable string size");
  Handle mem = check(H5Tcopy(H5T_C_S1), H5Tclose, file, object, "H5Tcopy");
  H5Tset_size(mem.get(), size + 1);
  H5Tset_strpad(mem.get(), H5T_STR_NULLTERM);
  std::vector<char> buf(n * (size + 1), '\0');
  check(H5Dread(ds, mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()), file, object, "H5Dread");
  for (std::size_t i = 0; i < n; ++i) {
    const char* p = buf.data() + i * (size + 1);
    out.emplace_back(p, strnlen(p, size));
  }
  return out;
}

// A 1-D dataset's length, or nullopt when it is not a 1-D dataset.
std::optional<std::size_t> length_1d(hid_t ds) {
  Handle space(H5Dget_space(ds), H5Sclose);
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 1) return std::nullopt;
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  return static_cast<std::size_t>(n);
}

// Reads `name` under `g` as numbers; nullopt when absent; a note when present but not a 1-D
// numeric dataset.
std::optional<std::vector<double>> try_doubles(hid_t g, const std::string& name,
                                               const std::string& file, const std::string& object,
                                               std::vector<std::string>& notes) {
  if (!link_exists(g, name)) return std::nullopt;
  Handle ds(H5Dopen2(g, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) {
    notes.push_back(object + "/" + name + ": not a dataset");
    return std::nullopt;
  }
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  const H5T_class_t cls = type.valid() ? H5Tget_class(type.get()) : H5T_NO_CLASS;
  const auto n = length_1d(ds.get());
  if ((cls != H5T_FLOAT && cls != H5T_INTEGER) || !n) {
    notes.push_back(object + "/" + name + ": not a 1-D numeric dataset");
    return std::nullopt;
  }
  std::vector<double> v(*n);
  if (!v.empty() &&
      H5Dread(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) {
    notes.push_back(object + "/" + name + ": H5Dread failed");
    return std::nullopt;
  }
  (void)file;
  return v;
}

std::optional<std::vector<std::string>> try_strings(hid_t g, const std::string& name,
                                                    const std::string& file,
                                                    const std::string& object,
                                                    std::vector<std::string>& notes) {
  if (!link_exists(g, name)) return std::nullopt;
  Handle ds(H5Dopen2(g, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) return std::nullopt;
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  const auto n = length_1d(ds.get());
  if (!type.valid() || H5Tget_class(type.get()) != H5T_STRING || !n) {
    notes.push_back(object + "/" + name + ": not a 1-D string dataset");
    return std::nullopt;
  }
  try {
    return read_any_strings(ds.get(), type.get(), *n, file, object + "/" + name);
  } catch (const Error& e) {
    notes.push_back(object + "/" + name + ": " + e.reason());
    return std::nullopt;
  }
}

// An attribute as text: strings as they are, numbers with 6 significant digits, arrays of
// up to 64 numbers joined by ", "; nullopt for anything else.
std::optional<std::string> attribute_text(hid_t attr) {
  Handle type(H5Aget_type(attr), H5Tclose);
  Handle space(H5Aget_space(attr), H5Sclose);
  if (!type.valid() || !space.valid()) return std::nullopt;
  const hssize_t npoints = H5Sget_simple_extent_npoints(space.get());
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls == H5T_STRING && npoints == 1) {
    if (H5Tis_variable_str(type.get()) > 0) {
      Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(mem.get(), H5T_VARIABLE);
      H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
      char* s = nullptr;
      if (H5Aread(attr, mem.get(), &s) < 0) return std::nullopt;
      std::string out = s ? s : "";
      if (s) H5Dvlen_reclaim(mem.get(), space.get(), H5P_DEFAULT, &s);
      return out;
    }
    const std::size_t size = H5Tget_size(type.get());
    if (size == 0 || size > (1u << 20)) return std::nullopt;
    std::vector<char> buf(size + 1, '\0');
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), size + 1);
    if (H5Aread(attr, mem.get(), buf.data()) < 0) return std::nullopt;
    return std::string(buf.data(), strnlen(buf.data(), size));
  }
  if ((cls == H5T_FLOAT || cls == H5T_INTEGER) && npoints >= 1 && npoints <= 64) {
    std::vector<double> v(static_cast<std::size_t>(npoints));
    if (H5Aread(attr, H5T_NATIVE_DOUBLE, v.data()) < 0) return std::nullopt;
    std::string out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.6g", v[i]);
      out += (i ? ", " : "") + std::string(buf);
    }
    return out;
  }
  return std::nullopt;
}

std::vector<std::pair<std::string, std::string>> all_attributes(hid_t obj) {
  std::vector<std::pair<std::string, std::string>> out;
  H5O_info_t info;
  if (H5Oget_info2(obj, &info, H5O_INFO_NUM_ATTRS) < 0) return out;
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    Handle a(H5Aopen_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT),
             H5Aclose);
    if (!a.valid()) continue;
    const ssize_t len = H5Aget_name(a.get(), 0, nullptr);
    if (len <= 0) continue;
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    H5Aget_name(a.get(), name.size(), name.data());
    name.resize(static_cast<std::size_t>(len));
    if (const auto text = attribute_text(a.get())) out.emplace_back(name, *text);
  }
  return out;
}

// "[\"sinusoid\", \"markov\"]" or "sinusoid, markov" -> {"sinusoid", "markov"}.
std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  const auto flush = [&] {
    const auto b = cur.find_first_not_of(" \t\"'");
    const auto e = cur.find_last_not_of(" \t\"'");
    if (b != std::string::npos) out.push_back(cur.substr(b, e - b + 1));
    cur.clear();
  };
  for (const char c : s) {
    if (c == '[' || c == ']') continue;
    if (c == ',' || c == ';') {
      flush();
      continue;
    }
    cur += c;
  }
  flush();
  return out;
}

std::vector<double> to_deviation(std::vector<double> v, bool is_variance) {
  if (is_variance)
    for (double& x : v)
      x = x >= 0 ? std::sqrt(x) : std::nan("");
  return v;
}

DiagnosisView read_diagnosis(hid_t g, const std::string& file, const std::string& object) {
  DiagnosisView d;
  d.channel = object.substr(0, object.size() - std::strlen("/diagnosis"));
  if (d.channel.empty()) d.channel = "/";
  auto& notes = d.notes;
  const auto doubles = [&](std::initializer_list<const char*> names) {
    for (const char* n : names)
      if (auto v = try_doubles(g, n, file, object, notes)) return *v;
    return std::vector<double>{};
  };
  // A curve as deviations: the first of `names` present, square-rooted unless named adev_*.
  const auto curve = [&](std::initializer_list<const char*> names) {
    for (const char* n : names)
      if (auto v = try_doubles(g, n, file, object, notes))
        return to_deviation(*v, std::string(n).find("adev") == std::string::npos);
    return std::vector<double>{};
  };
  d.tau = doubles({"tau", "tau_s"});
  d.measured = curve({"avar_measured", "adev_measured"});
  d.model_before = curve({"avar_model_before", "adev_model_before"});
  d.model_after = curve({"avar_model_after", "adev_model_after"});
  d.band_lo = curve({"mc_after_lo", "avar_mc_lo", "mc_lo", "mc_band_lo", "adev_mc_lo"});
  d.band_hi = curve({"mc_after_hi", "avar_mc_hi", "mc_hi", "mc_band_hi", "adev_mc_hi"});
  d.band_before_lo = curve({"mc_before_lo"});
  d.band_before_hi = curve({"mc_before_hi"});
  d.edf = doubles({"edf"});
  d.iteration_gap_before = doubles({"gap_iteration_before"});
  d.iteration_gap_after = doubles({"gap_iteration_after", "gap", "gap_per_iteration", "gaps"});
  d.iteration_delta_ic = doubles({"delta_ic"});
  if (auto v = try_strings(g, "parameters", file, object, notes)) d.iteration_parameters = *v;
  for (const char* n : {"effect", "effects_named", "effects"})
    if (auto v = try_strings(g, n, file, object, notes)) {
      d.effects_named = *v;
      break;
    }
  d.attributes = all_attributes(g);
  for (const auto& [k, v] : d.attributes) {
    if (k == "gap_before") d.gap_before = std::strtod(v.c_str(), nullptr);
    if (k == "gap_after") d.gap_after = std::strtod(v.c_str(), nullptr);
    if ((k == "effects_named" || k == "effects") && d.effects_named.empty())
      d.effects_named = split_list(v);
  }
  if (std::isnan(d.gap_before) && !d.iteration_gap_before.empty())
    d.gap_before = d.iteration_gap_before.front();
  if (std::isnan(d.gap_after) && !d.iteration_gap_after.empty())
    d.gap_after = d.iteration_gap_after.back();
  // Curves of another length than tau cannot be drawn against it.
  for (auto* v : {&d.measured, &d.model_before, &d.model_after, &d.band_lo, &d.band_hi,
                  &d.band_before_lo, &d.band_before_hi, &d.edf})
    if (!v->empty() && v->size() != d.tau.size()) {
      notes.push_back(object + ": a curve has " + std::to_string(v->size()) + " values for " +
                      std::to_string(d.tau.size()) + " taus; not drawn");
      v->clear();
    }
  return d;
}

FitRecord read_fit_tolerant(hid_t g, const std::string& file, const std::string& object,
                            std::vector<std::string>& notes) {
  FitRecord fit;
  const auto terms = try_strings(g, "term", file, object, notes);
  if (!terms) {
    notes.push_back(object + ": no term dataset");
    return fit;
  }
  const auto num = [&](const char* name) {
    auto v = try_doubles(g, name, file, object, notes);
    return v ? *v : std::vector<double>{};
  };
  const auto str = [&](const char* name) {
    auto v = try_strings(g, name, file, object, notes);
    return v ? *v : std::vector<std::string>{};
  };
  const auto value = num("value"), sigma = num("sigma"), upper = num("upper");
  const auto detected = num("detected");
  const auto value_ds = num("value_datasheet"), sigma_ds = num("sigma_datasheet");
  const auto upper_ds = num("upper_datasheet"), value_alt = num("value_datasheet_alt");
  const auto unit = str("unit"), unit_ds = str("unit_datasheet");
  const auto unit_alt = str("unit_datasheet_alt");
  const auto at = [](const std::vector<double>& v, std::size_t i) {
    return i < v.size() ? v[i] : std::nan("");
  };
  const auto sat = [](const std::vector<std::string>& v, std::size_t i) {
    return i < v.size() ? v[i] : std::string();
  };
  for (std::size_t i = 0; i < terms->size(); ++i) {
    TermRecord t;
    t.term = (*terms)[i];
    t.value = at(value, i);
    t.sigma = at(sigma, i);
    t.upper = at(upper, i);
    t.detected = at(detected, i) > 0.5;
    t.unit = sat(unit, i);
    t.value_datasheet = at(value_ds, i);
    t.sigma_datasheet = at(sigma_ds, i);
    t.upper_datasheet = at(upper_ds, i);
    t.unit_datasheet = sat(unit_ds, i);
    t.value_datasheet_alt = at(value_alt, i);
    t.unit_datasheet_alt = sat(unit_alt, i);
    fit.terms.push_back(std::move(t));
  }
  fit.tau = num("tau");
  fit.adev_model = num("adev_model");
  for (const auto& [k, v] : all_attributes(g)) {
    if (k == "method") fit.method = v;
    if (k == "status") fit.status = v;
    if (k == "chi2_dof") fit.chi2_dof = std::strtod(v.c_str(), nullptr);
    if (k == "rank") fit.rank = static_cast<int>(std::strtod(v.c_str(), nullptr));
  }
  return fit;
}

struct Walk {
  std::vector<std::string> psd_fit, diagnosis;
};

herr_t visit(hid_t, const char* name, const H5O_info_t* info, void* data) {
  if (info->type != H5O_TYPE_GROUP || !name) return 0;
  const std::string path = std::string("/") + name;
  const auto slash = path.find_last_of('/');
  const std::string base = path.substr(slash + 1);
  auto* w = static_cast<Walk*>(data);
  if (base == "psd_fit") w->psd_fit.push_back(path);
  if (base == "diagnosis") w->diagnosis.push_back(path);
  return 0;
}

}  // namespace

ReportExtras read_report_extras(const std::filesystem::path& path) {
  h5::quiet_library();
  const std::string file = path.string();
  if (H5Fis_hdf5(file.c_str()) <= 0) throw Error(file, "", "not an HDF5 file");
  Handle f =
      check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, file, "", "H5Fopen");
  ReportExtras x;
  {
    Handle root(H5Gopen2(f.get(), "/", H5P_DEFAULT), H5Gclose);
    if (root.valid() && H5Aexists(root.get(), "device_id") > 0) {
      Handle a(H5Aopen(root.get(), "device_id", H5P_DEFAULT), H5Aclose);
      if (a.valid())
        if (const auto t = attribute_text(a.get())) x.device_id = *t;
    }
  }
  Walk w;
  if (H5Ovisit2(f.get(), H5_INDEX_NAME, H5_ITER_INC, visit, &w, H5O_INFO_BASIC) < 0) {
    x.notes.push_back(file + ": cannot walk the file");
    return x;
  }
  for (const std::string& p : w.psd_fit) {
    Handle g(H5Gopen2(f.get(), p.c_str(), H5P_DEFAULT), H5Gclose);
    if (!g.valid()) continue;
    try {
      FitRecord fit = read_fit_tolerant(g.get(), file, p, x.notes);
      if (!fit.terms.empty()) x.psd_fits.emplace_back(p.substr(0, p.size() - 8), std::move(fit));
    } catch (const std::exception& e) {
      x.notes.push_back(p + ": " + e.what());
    }
  }
  for (const std::string& p : w.diagnosis) {
    Handle g(H5Gopen2(f.get(), p.c_str(), H5P_DEFAULT), H5Gclose);
    if (!g.valid()) continue;
    try {
      x.diagnoses.push_back(read_diagnosis(g.get(), file, p));
    } catch (const std::exception& e) {
      x.notes.push_back(p + ": " + e.what());
    }
  }
  return x;
}

int SummaryColumns::find(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

SummaryColumns read_summary_columns(const std::filesystem::path& h5_path) {
  h5::quiet_library();
  const std::string file = h5_path.string();
  if (H5Fis_hdf5(file.c_str()) <= 0) throw Error(file, "", "not an HDF5 file");
  Handle f =
      check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, file, "", "H5Fopen");
  Handle ds =
      check(H5Dopen2(f.get(), "summary", H5P_DEFAULT), H5Dclose, file, "/summary", "H5Dopen2");
  Handle type = check(H5Dget_type(ds.get()), H5Tclose, file, "/summary", "H5Dget_type");
  if (H5Tget_class(type.get()) != H5T_COMPOUND)
    throw Error(file, "/summary", "not a compound dataset");
  const auto n = length_1d(ds.get());
  if (!n) throw Error(file, "/summary", "not a 1-D dataset");
  SummaryColumns cols;
  cols.rows = *n;
  const int members = H5Tget_nmembers(type.get());
  for (int i = 0; i < members; ++i) {
    char* raw = H5Tget_member_name(type.get(), static_cast<unsigned>(i));
    if (!raw) continue;
    const std::string name = raw;
    H5free_memory(raw);
    Handle mt(H5Tget_member_type(type.get(), static_cast<unsigned>(i)), H5Tclose);
    if (!mt.valid()) continue;
    const H5T_class_t cls = H5Tget_class(mt.get());
    std::vector<std::string> text;
    // One member at a time through a one-member memory compound: HDF5 converts compounds by
    // member name, so members this code does not know are simply not read.
    if (cls == H5T_FLOAT || cls == H5T_INTEGER) {
      Handle mem =
          check(H5Tcreate(H5T_COMPOUND, sizeof(double)), H5Tclose, file, "/summary", "H5Tcreate");
      H5Tinsert(mem.get(), name.c_str(), 0, H5T_NATIVE_DOUBLE);
      std::vector<double> v(cols.rows);
      if (!v.empty())
        check(H5Dread(ds.get(), mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), file,
              "/summary", "H5Dread(" + name + ")");
      for (const double x : v)
        text.push_back(format_number(x));
    } else if (cls == H5T_STRING && H5Tis_variable_str(mt.get()) > 0) {
      Handle str = check(H5Tcopy(H5T_C_S1), H5Tclose, file, "/summary", "H5Tcopy");
      H5Tset_size(str.get(), H5T_VARIABLE);
      H5Tset_cset(str.get(), H5Tget_cset(mt.get()));
      Handle mem =
          check(H5Tcreate(H5T_COMPOUND, sizeof(char*)), H5Tclose, file, "/summary", "H5Tcreate");
      H5Tinsert(mem.get(), name.c_str(), 0, str.get());
      std::vector<char*> v(cols.rows, nullptr);
      if (!v.empty()) {
        check(H5Dread(ds.get(), mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), file,
              "/summary", "H5Dread(" + name + ")");
        for (char* p : v)
          text.emplace_back(p ? p : "");
        Handle space = check(H5Dget_space(ds.get()), H5Sclose, file, "/summary", "H5Dget_space");
        H5Dvlen_reclaim(mem.get(), space.get(), H5P_DEFAULT, v.data());
      }
    } else if (cls == H5T_STRING) {
      const std::size_t size = H5Tget_size(mt.get());
      if (size == 0 || size > 4096) continue;
      Handle str = check(H5Tcopy(H5T_C_S1), H5Tclose, file, "/summary", "H5Tcopy");
      H5Tset_size(str.get(), size + 1);
      Handle mem =
          check(H5Tcreate(H5T_COMPOUND, size + 1), H5Tclose, file, "/summary", "H5Tcreate");
      H5Tinsert(mem.get(), name.c_str(), 0, str.get());
      std::vector<char> buf(cols.rows * (size + 1), '\0');
      if (!buf.empty())
        check(H5Dread(ds.get(), mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()), file,
              "/summary", "H5Dread(" + name + ")");
      for (std::size_t r = 0; r < cols.rows; ++r) {
        const char* p = buf.data() + r * (size + 1);
        text.emplace_back(p, strnlen(p, size));
      }
    } else {
      continue;
    }
    cols.names.push_back(name);
    cols.values.push_back(std::move(text));
  }
  return cols;
}

}  // namespace allanlot::io
