// allanlot._allanlot: `plan` and `watch` as the command line runs them (src/workflow/plan.hpp,
// src/workflow/watch.hpp), and the sequential rule's quantile (kernels/plan/sequential.hpp).
#include "python/bindings/bindings.hpp"

#include "kernels/plan/sequential.hpp"
#include "src/lot/spec.hpp"
#include "src/workflow/plan.hpp"
#include "src/workflow/watch.hpp"

#include <pybind11/stl.h>

#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

namespace allanlot::python {
namespace {

// The JSON of `allanlot plan --json` as a dict; ValueError with the command's message.
py::object plan(const std::string& model, const std::map<std::string, double>& targets,
                const std::string& spec, double margin, double confidence, int verify,
                std::uint64_t seed, double max_duration, int threads) {
  workflow::PlanOptions opt;
  opt.model_path = model;
  for (const auto& [term, precision] : targets)
    opt.targets.push_back(term + "=" + std::to_string(precision));
  opt.spec_path = spec;
  if (opt.targets.empty() == opt.spec_path.empty())
    throw std::invalid_argument("give either targets or spec");
  opt.margin = margin;
  opt.confidence_given = confidence > 0.0;
  if (opt.confidence_given) opt.confidence = confidence;
  opt.verify = verify;
  opt.seed = seed;
  opt.max_duration_s = max_duration;
  opt.threads = kernel_threads(threads);
  std::string json;
  {
    const py::gil_scoped_release unlocked;
    try {
      json = workflow::plan_json(workflow::plan_recording(opt)).dump();
    } catch (const spec::Error& e) {
      std::string text;
      for (const std::string& msg : e.messages())
        text += (text.empty() ? "" : "\n") + msg;
      throw std::invalid_argument(text);
    } catch (const std::exception& e) {
      throw std::invalid_argument(e.what());
    }
  }
  return py::module_::import("json").attr("loads")(json);
}

// (exit status, printed text) of `allanlot watch`.
py::tuple watch(const std::string& recording, const std::string& spec, double interval,
                double max_duration, bool replay, double poll, double idle_timeout,
                double sample_rate, const std::string& units, int threads) {
  workflow::WatchOptions opt;
  opt.recording = recording;
  opt.spec_path = spec;
  opt.interval_s = interval;
  opt.max_duration_s = max_duration;
  opt.replay = replay;
  opt.poll_s = poll;
  opt.idle_timeout_s = idle_timeout;
  opt.input.sample_rate_hz = sample_rate;
  if (!units.empty()) opt.input.units.push_back(units);
  opt.threads = kernel_threads(threads);
  std::ostringstream out, err;
  int rc = 0;
  {
    const py::gil_scoped_release unlocked;
    rc = workflow::run_watch(opt, out, err);
  }
  if (rc == workflow::kExitUsage) throw std::invalid_argument(err.str());
  return py::make_tuple(rc, out.str());
}

}  // namespace

void bind_plan(py::module_& m) {
  m.def("plan", &plan, py::arg("model"), py::arg("targets"), py::arg("spec"), py::arg("margin"),
        py::arg("confidence"), py::arg("verify"), py::arg("seed"), py::arg("max_duration"),
        py::arg("threads"));
  m.def("watch", &watch, py::arg("recording"), py::arg("spec"), py::arg("interval"),
        py::arg("max_duration"), py::arg("replay"), py::arg("poll"), py::arg("idle_timeout"),
        py::arg("sample_rate"), py::arg("units"), py::arg("threads"));
  m.def("look_quantile", &kernels::look_quantile, py::arg("alpha"), py::arg("t_prev"), py::arg("t"),
        py::arg("t_max"));
}

}  // namespace allanlot::python
