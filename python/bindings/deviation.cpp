// allanlot._allanlot.deviation: one statistic of one record, with the command line's kernels,
// confidence intervals and tau grids (docs/python.md).
#include "python/bindings/bindings.hpp"
#include "python/bindings/convert.hpp"

#include "kernels/allan/codev.hpp"
#include "kernels/allan/phase.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/allan/tau_grid.hpp"
#include "kernels/uncertainty/confidence.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <stdexcept>
#include <string>

namespace allanlot::python {
namespace {

kernels::DataType parse_data_type(const std::string& t) {
  if (t == "phase") return kernels::DataType::Phase;
  if (t == "freq" || t == "frequency" || t == "rate") return kernels::DataType::Rate;
  throw std::invalid_argument("data_type must be 'phase' or 'freq' (also 'rate'), got '" + t + "'");
}

kernels::Stat parse_stat(const std::string& name) {
  if (const auto s = kernels::parse_stat(name)) return *s;
  std::string known;
  for (const kernels::Stat s : kernels::all_stats()) {
    if (!known.empty()) known += ", ";
    known += kernels::stat_name(s);
  }
  throw std::invalid_argument("unknown statistic '" + name + "' (known: " + known + ")");
}

py::dict deviation(const Samples& data, const std::string& stat, double rate,
                   const std::string& data_type, std::optional<std::vector<std::int64_t>> m,
                   const std::string& grid, double confidence, int threads, bool estimable) {
  const std::span<const double> y = samples_of(data);
  const kernels::Stat s = parse_stat(stat);
  const kernels::DataType type = parse_data_type(data_type);
  if (confidence != 0.0 && !(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("confidence must be in (0, 1), got " + std::to_string(confidence));
  threads = kernel_threads(threads);
  kernels::PhaseData p;
  kernels::StatResult r;
  {
    const py::gil_scoped_release unlocked;
    p = kernels::make_phase(y, type, rate, threads);
    const auto range = estimable ? kernels::MRange::Estimable : kernels::MRange::Stable32;
    const std::int64_t m_max = estimable ? p.n_points() - 1 : kernels::max_m(s, p.n_points());
    const std::vector<std::int64_t> ms =
        m ? *m : kernels::stat_m_list(kernels::parse_tau_grid(grid), s, m_max, p.n_points());
    r = kernels::compute(s, p, ms, threads, nullptr, range);
    if (confidence > 0.0) kernels::add_confidence(s, p, r, confidence, threads);
  }
  py::dict d;
  d["stat"] = py::str(std::string(kernels::stat_name(s)));
  d["m"] = to_array(r.m);
  d["tau"] = to_array(r.tau_s);
  d["dev"] = to_array(r.dev);
  d["n"] = to_array(r.n);
  const std::vector<double> nan(r.size(), std::numeric_limits<double>::quiet_NaN());
  d["edf"] = to_array(r.edf.empty() ? nan : r.edf);
  d["dev_lo"] = to_array(r.dev_lo.empty() ? nan : r.dev_lo);
  d["dev_hi"] = to_array(r.dev_hi.empty() ? nan : r.dev_hi);
  d["alpha"] = to_array(r.alpha.empty() ? std::vector<int>(r.size(), 0) : r.alpha);
  d["confidence"] = r.confidence;
  d["tau0"] = p.tau0_s;
  d["n_points"] = p.n_points();
  d["n_gaps"] = p.n_gaps;
  d["mean_rate"] = p.mean_rate;
  d["has_interval"] = kernels::has_interval(s);
  d["is_time_error"] = kernels::is_time_error(s);
  return d;
}

// The signed Groslambert codeviation of two records at the given m (kernels/allan/codev.hpp).
py::dict codeviation(const Samples& data_1, const Samples& data_2, double rate,
                     const std::string& data_type, const std::vector<std::int64_t>& m,
                     int threads) {
  const std::span<const double> x = samples_of(data_1), y = samples_of(data_2);
  if (x.size() != y.size())
    throw std::invalid_argument("data_1 and data_2 must have the same length, got " +
                                std::to_string(x.size()) + " and " + std::to_string(y.size()));
  const kernels::DataType type = parse_data_type(data_type);
  threads = kernel_threads(threads);
  kernels::StatResult r;
  {
    const py::gil_scoped_release unlocked;
    const kernels::PhaseData px = kernels::make_phase(x, type, rate, threads);
    const kernels::PhaseData py_ = kernels::make_phase(y, type, rate, threads);
    r = kernels::gcodev(px, py_, m, threads);
  }
  py::dict d;
  d["m"] = to_array(r.m);
  d["tau"] = to_array(r.tau_s);
  d["dev"] = to_array(r.dev);
  d["n"] = to_array(r.n);
  return d;
}

py::list stat_names() {
  py::list l;
  for (const kernels::Stat s : kernels::all_stats())
    l.append(py::str(std::string(kernels::stat_name(s))));
  return l;
}

}  // namespace

void bind_deviation(py::module_& m) {
  m.def("deviation", &deviation, py::arg("data"), py::arg("stat"), py::arg("rate"),
        py::arg("data_type"), py::arg("m"), py::arg("grid"), py::arg("confidence"),
        py::arg("threads"), py::arg("estimable"),
        "One statistic of one record (the public wrapper is allanlot.deviation).");
  m.def("gcodev", &codeviation, py::arg("data_1"), py::arg("data_2"), py::arg("rate"),
        py::arg("data_type"), py::arg("m"), py::arg("threads"),
        "Signed Groslambert codeviation at the given m (public wrapper: allanlot.gcodev).");
  m.attr("max_threads") = kernels::kMaxThreads;
  m.def("stats", &stat_names,
        "The statistics this build computes, in the order results list them.");
  m.def(
      "max_m",
      [](const std::string& stat, std::int64_t n_points) {
        return kernels::max_m(parse_stat(stat), n_points);
      },
      py::arg("stat"), py::arg("n_points"),
      "Stable32's largest averaging factor for a record of n_points phase points.");
  m.def(
      "stat_reference",
      [](const std::string& stat) {
        return std::string(kernels::stat_info(parse_stat(stat)).reference);
      },
      py::arg("stat"), "Where the statistic is defined (kernels/allan/stats.hpp StatInfo).");
}

}  // namespace allanlot::python
