// allanlot._allanlot: a recording in any format the command line reads (HDF5, CSV/TSV, ROS 1
// and ROS 2 bags, MCAP; io/recording_source.hpp), its channels as numpy arrays.
#include "python/bindings/bindings.hpp"
#include "python/bindings/convert.hpp"

#include "io/recording.hpp"

#include <pybind11/stl.h>

#include <string>
#include <vector>

namespace allanlot::python {
namespace {

bool selected(const std::vector<std::string>& globs, const std::string& path) {
  if (globs.empty()) return true;
  for (const auto& g : globs)
    if (io::channel_glob_matches(g, path)) return true;
  return false;
}

py::dict channel_dict(const io::RecordingReader& reader, const io::ChannelInfo& ch) {
  std::vector<double> samples;
  {
    const py::gil_scoped_release unlocked;
    const auto v = reader.read(ch);
    samples.assign(v.begin(), v.end());
  }
  py::dict d;
  d["samples"] = to_array(samples);
  d["sample_rate_hz"] = ch.sample_rate_hz;
  d["units"] = ch.units;
  d["data_type"] = ch.data_type == kernels::DataType::Phase ? "phase" : "rate";
  return d;
}

// {device_id, channels: {path: {samples, sample_rate_hz, units, data_type}}, problems, notes}.
py::dict read_recording(const std::string& path, const std::vector<std::string>& channels,
                        const std::vector<std::string>& topics, bool receive_time,
                        double sample_rate) {
  io::InputOptions options;
  options.topics = topics;
  options.receive_time = receive_time;
  options.sample_rate_hz = sample_rate;
  io::check_input_options(path, options);
  const io::RecordingReader reader(path, options);
  py::dict out, chans, problems;
  out["device_id"] = reader.info().device_id;
  for (const auto& ch : reader.info().channels)
    if (selected(channels, ch.path)) chans[py::str(ch.path)] = channel_dict(reader, ch);
  for (const auto& p : reader.info().problems)
    problems[py::str(p.path)] = p.reason;
  out["channels"] = chans;
  out["problems"] = problems;
  out["notes"] = reader.info().notes;
  return out;
}

}  // namespace

void bind_recording(py::module_& m) {
  m.def("read_recording", &read_recording, py::arg("path"), py::arg("channels"), py::arg("topics"),
        py::arg("receive_time"), py::arg("sample_rate"), "A recording's channels as numpy arrays.");
}

}  // namespace allanlot::python
