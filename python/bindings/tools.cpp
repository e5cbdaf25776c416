// allanlot._allanlot: the Welch PSD, the simulator and diagnose, as the command line runs them.
#include "python/bindings/bindings.hpp"
#include "python/bindings/convert.hpp"

#include "kernels/simulate/simulate.hpp"
#include "kernels/spectral/psd.hpp"
#include "src/lot/model.hpp"
#include "src/workflow/diagnose.hpp"
#include "src/workflow/diagnosis_json.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace allanlot::python {
namespace {

py::dict psd(const Samples& data, double rate, std::int64_t min_segments, int bins_per_decade,
             int threads) {
  const std::span<const double> y = samples_of(data);
  if (min_segments < 1) throw std::invalid_argument("segments must be >= 1");
  threads = kernel_threads(threads);
  kernels::PsdResult r;
  kernels::BinnedPsd b;
  {
    const py::gil_scoped_release unlocked;
    r = kernels::welch_psd(y, rate, threads, min_segments);
    if (bins_per_decade > 0) b = kernels::log_bin(r, bins_per_decade);
  }
  py::dict d;
  if (bins_per_decade > 0) {
    d["f"] = to_array(b.f_hz);
    d["psd"] = to_array(b.psd);
    d["edf"] = to_array(b.edf);
    d["n_avg"] = to_array(b.n_avg);
  } else {
    d["f"] = to_array(r.f_hz);
    d["psd"] = to_array(r.psd);
    d["edf"] = to_array(r.edf);
  }
  d["df"] = r.df_hz;
  d["segment_length"] = r.segment_length;
  d["n_segments"] = r.n_segments;
  d["n_skipped"] = r.n_skipped;
  return d;
}

model::UnitModel model_of(const std::string& json_text, const std::string& source) {
  return json_text.empty() ? model::default_demo_model() : model::parse_model(json_text, source);
}

// Unit 0 of `simulate`: the same streams as `allanlot simulate -o FILE` (no lot spread drawn),
// so the arrays equal the recording's datasets bit for bit.
py::list simulate(const std::string& json_text, const std::string& source, double duration_s,
                  std::uint64_t seed, int threads, py::dict& info) {
  const model::UnitModel m = model_of(json_text, source);
  const double n_real = duration_s * m.sample_rate_hz;
  if (!(std::isfinite(duration_s) && duration_s > 0.0) || !(n_real >= 2.0) || n_real > 4.0e9)
    throw std::invalid_argument("duration " + std::to_string(duration_s) + " s at " +
                                std::to_string(m.sample_rate_hz) + " Hz gives " +
                                std::to_string(n_real) + " samples; need 2 to 4e9");
  const auto n = static_cast<std::size_t>(std::llround(n_real));
  threads = kernel_threads(threads);
  info["sample_rate_hz"] = m.sample_rate_hz;
  py::list channels;
  kernels::SimulationPlan plan(n);
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    py::array_t<double> a(static_cast<py::ssize_t>(n));
    const std::span<double> out(a.mutable_data(), n);
    {
      const py::gil_scoped_release unlocked;
      plan.run(model::to_spec(m, c), seed, model::channel_stream(0, c), out, threads);
    }
    channels.append(py::make_tuple(m.channels[c].name, m.channels[c].units, a));
  }
  return channels;
}

std::string diagnose(const Samples& data, double rate, const std::string& data_type,
                     const std::string& json_text, const std::string& source,
                     const std::string& channel, int replicas, std::uint64_t seed, int threads,
                     int max_effects) {
  const std::span<const double> samples = samples_of(data);
  std::vector<double> y(samples.begin(), samples.end());
  if (data_type == "phase")
    workflow::phase_to_rate(y, rate);  // as `allanlot diagnose` does
  else if (data_type != "freq" && data_type != "rate")
    throw std::invalid_argument("data_type must be 'phase' or 'freq' (also 'rate')");
  const model::UnitModel m = model_of(json_text, source);
  std::size_t mc = 0;
  if (m.channels.size() > 1) {
    while (mc < m.channels.size() && m.channels[mc].name != channel)
      ++mc;
    if (mc == m.channels.size())
      throw std::invalid_argument(source + ": " +
                                  (channel.empty() ? std::string("several channels; choose one")
                                                   : "no channel '" + channel + "'") +
                                  " (channel=...)");
  }
  if (replicas < 0) throw std::invalid_argument("replicas must be >= 0");
  const workflow::DiagnoseSettings settings{replicas, max_effects, seed, kernel_threads(threads)};
  const std::string name = channel.empty() ? m.channels[mc].name : channel;
  workflow::ChannelDiagnosis d;
  {
    const py::gil_scoped_release unlocked;
    d = workflow::diagnose_channel(y, rate, m, mc, name, settings);
  }
  return workflow::diagnosis_json(name, d.diagnosis).dump();
}

}  // namespace

void bind_tools(py::module_& m) {
  m.def("psd", &psd, py::arg("data"), py::arg("rate"), py::arg("segments"),
        py::arg("bins_per_decade"), py::arg("threads"),
        "Welch PSD (public wrapper: allanlot.psd).");
  m.def(
      "simulate",
      [](const std::string& json_text, const std::string& source, double duration_s,
         std::uint64_t seed, int threads) {
        py::dict info;
        py::list channels = simulate(json_text, source, duration_s, seed, threads, info);
        return py::make_tuple(info["sample_rate_hz"], channels);
      },
      py::arg("model_json"), py::arg("source"), py::arg("duration"), py::arg("seed"),
      py::arg("threads"), "Simulated unit (public wrapper: allanlot.simulate).");
  m.def("diagnose", &diagnose, py::arg("data"), py::arg("rate"), py::arg("data_type"),
        py::arg("model_json"), py::arg("source"), py::arg("channel"), py::arg("replicas"),
        py::arg("seed"), py::arg("threads"), py::arg("max_effects"),
        "diagnose --json as text (public: allanlot.diagnose).");
  m.def(
      "default_model", [] { return model::to_json(model::default_demo_model()); },
      "The demo unit's model (the paper's Table) as model-file JSON.");
}

}  // namespace allanlot::python
