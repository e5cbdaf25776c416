// allanlot._allanlot: the eq. (3) fit of a deviation curve, and results files and lot summaries
// read back as dicts of numpy arrays, keyed by the names of the results schema (io/schema.hpp).
#include "python/bindings/bindings.hpp"
#include "python/bindings/convert.hpp"

#include "io/error.hpp"
#include "io/paths.hpp"
#include "io/results.hpp"
#include "io/schema.hpp"
#include "src/pipeline/channel_fit.hpp"

#include <pybind11/stl.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::python {

py::dict fit_dict(const io::FitRecord& f) {
  py::dict d = fields_dict(f, io::schema::fit_fields());
  d["status_text"] = io::fit_status_text(f);
  d["terms"] = columns_dict(f.terms, io::schema::term_columns());
  d["readouts"] = columns_dict(f.readouts, io::schema::readout_columns());
  d["effects"] = columns_dict(f.effects, io::schema::effect_columns());
  return d;
}

namespace {

py::dict fit(const std::vector<std::int64_t>& m, const std::vector<double>& tau,
             const std::vector<double>& dev, const std::vector<std::int64_t>& n,
             const std::vector<double>& edf, double tau0, std::int64_t n_samples,
             const std::string& units, const std::string& lowpass) {
  const std::size_t k = m.size();
  if (tau.size() != k || dev.size() != k || n.size() != k || edf.size() != k)
    throw std::invalid_argument("fit: m, tau, dev, n and edf must have the same length");
  if (!(tau0 > 0.0)) throw std::invalid_argument("fit: tau0 must be > 0");
  kernels::StatResult oadev;
  oadev.m = m;
  oadev.tau_s = tau;
  oadev.dev = dev;
  oadev.n = n;
  oadev.edf = edf;
  const pipeline::LowpassChoice choice = pipeline::parse_lowpass_choice(lowpass);
  io::FitRecord f;
  {
    const py::gil_scoped_release unlocked;
    f = pipeline::fit_channel(oadev, tau0, n_samples, units, choice);
  }
  return fit_dict(f);
}

py::dict channel_dict(const io::ChannelResult& c) {
  namespace schema = io::schema;
  py::dict d = fields_dict(c, schema::channel_fields());
  py::dict allan;
  for (const auto& [name, r] : c.stats)
    allan[py::str(name)] = fields_dict(r, schema::stat_fields());
  d[schema::kAllan] = allan;
  if (c.fit) d[schema::kFit] = fit_dict(*c.fit);
  if (c.psd_fit) d[schema::kPsdFit] = fit_dict(*c.psd_fit);
  if (c.psd) d[schema::kPsd] = fields_dict(*c.psd, schema::psd_fields());
  if (c.crosscheck)
    d[schema::kCrosscheck] = fields_dict(*c.crosscheck, schema::crosscheck_fields());
  if (c.quality) d[schema::kQuality] = fields_dict(*c.quality, schema::quality_fields());
  if (c.diagnosis) {
    py::dict g = fields_dict(*c.diagnosis, schema::diagnosis_fields());
    for (const auto& [name, v] : c.diagnosis->number_attributes)
      g[py::str(name)] = v;
    for (const auto& [name, v] : c.diagnosis->string_attributes)
      g[py::str(name)] = py::str(v);
    d[schema::kDiagnosis] = g;
  }
  return d;
}

// A file to read must be a regular file: a FIFO would block open(2) for ever. io::Error
// (OSError) "no such file", "is a directory", "not a regular file (a FIFO)" otherwise.
void require_regular(const std::filesystem::path& path) {
  if (const std::string why = io::input_file_problem(path); !why.empty())
    throw io::Error(path.string(), "", why);
}

py::dict read_results(const std::string& path) {
  require_regular(path);
  io::RecordingResult r;
  {
    const py::gil_scoped_release unlocked;
    r = io::read_results(path);
  }
  py::dict d = fields_dict(r, io::schema::root_fields());
  py::dict attributes;
  for (const auto& [name, value] : r.attributes)
    attributes[py::str(name)] = py::str(value);
  d["attributes"] = attributes;
  py::dict channels;
  for (const auto& c : r.channels)
    channels[py::str(c.path)] = channel_dict(c);
  d["channels"] = channels;
  return d;
}

py::dict table_dict(std::vector<io::schema::TableColumn> table) {
  py::dict d;
  for (auto& c : table)
    d[py::str(c.name)] = c.numeric ? py::object(to_array(c.numbers)) : to_py(c.text);
  return d;
}

// A lot summary is named by its OUTDIR (as `summarize` takes it) or by its lot_summary.h5.
std::filesystem::path summary_file(const std::filesystem::path& p) {
  return std::filesystem::is_directory(p) ? p / "lot_summary.h5" : p;
}

}  // namespace

void bind_records(py::module_& m) {
  m.def("fit", &fit, py::arg("m"), py::arg("tau"), py::arg("dev"), py::arg("n"), py::arg("edf"),
        py::arg("tau0"), py::arg("n_samples"), py::arg("units"), py::arg("lowpass") = "auto",
        "The eq. (3) fit of an overlapping Allan deviation curve (public wrapper: allanlot.fit).");
  m.def("read_results", &read_results, py::arg("path"), "A results file as nested dicts.");
  m.def(
      "read_lot_summary",
      [](const std::string& p) {
        const std::filesystem::path file = summary_file(p);
        require_regular(file);
        std::vector<io::SummaryRow> rows;
        {
          const py::gil_scoped_release unlocked;
          rows = io::read_lot_summary(file);
        }
        return table_dict(io::schema::summary_table(rows));
      },
      py::arg("path"), "The lot summary's columns.");
  m.def(
      "read_lot_statistics",
      [](const std::string& p) {
        const std::filesystem::path file = summary_file(p);
        require_regular(file);
        std::vector<io::StatisticsRow> rows;
        {
          const py::gil_scoped_release unlocked;
          rows = io::read_lot_statistics(file);
        }
        return table_dict(io::schema::statistics_table(rows));
      },
      py::arg("path"), "The lot statistics' columns.");
}

}  // namespace allanlot::python
