#include "src/cli/convert.hpp"

#include "io/error.hpp"
#include "io/paths.hpp"
#include "io/recording.hpp"
#include "io/text_recording.hpp"
#include "src/cli/input_options.hpp"
#include "src/workflow/inputs.hpp"
#include "src/workflow/notes.hpp"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

namespace allanlot::cli {
namespace {

namespace fs = std::filesystem;

struct ConvertArgs {
  std::vector<std::string> inputs, manifests;
  std::string outdir;
  InputArgs input;
  bool quiet = false;
};

// Deflate level of the converted datasets: level 4 compresses sensor data about as well as 9
// in a fraction of the time.
constexpr int kDeflate = 4;

// Writes one input as OUTDIR/<device_id>.h5; returns the path written. The channels keep
// their paths, each with its own sample_rate_hz, units and (when anyone said it) data_type;
// the root keeps device_id, the source file's name and what was inferred from a text file.
// A channel that cannot be converted (named on `err`) sets `left_out`; the others are written.
// What was inferred from a text file goes to `notes`.
fs::path convert_one(const std::string& file, const io::InputOptions& options,
                     const fs::path& outdir, const std::vector<fs::path>& inputs,
                     std::map<std::string, std::string>& written, std::ostream& err,
                     std::ostream& notes, bool& left_out) {
  const io::RecordingReader reader(file, options);
  const io::RecordingInfo& info = reader.info();
  for (const std::string& note : info.notes)
    notes << "allanlot: note: " << file << ": " << note << "\n";
  for (const io::ChannelProblem& p : info.problems) {
    err << "allanlot: error: " << file << ":" << p.path << ": " << p.reason << " (left out)\n";
    left_out = true;
  }
  if (info.channels.empty()) throw io::Error(file, "", "no channel found");
  const std::string id = io::sanitize_device_id(info.device_id);
  const fs::path path = outdir / (id + ".h5");
  if (const auto in = io::replaced_input(path, inputs))
    throw io::Error(file, "", io::replaced_input_message(path, *in));
  if (const auto it = written.find(id); it != written.end())
    throw io::Error(file, "",
                    "device_id '" + id + "' is also that of " + it->second +
                        ", converted to the same file");
  io::RecordingWriter w(path.string(), info.device_id, 0.0, "");
  w.set_deflate(kDeflate);
  bool has_name = false;
  for (const auto& [name, value] : info.facts) {
    w.add_root_attribute(name, value);
    has_name = has_name || name == "source_file_name";
  }
  if (!has_name) w.add_root_attribute("source_file_name", fs::path(file).filename().string());
  for (const io::ChannelInfo& ch : info.channels) {
    const kernels::LargeVector<double> samples = reader.read(ch);
    io::ChannelAttributes attributes;
    attributes.sample_rate_hz = ch.sample_rate_hz;
    if (!ch.data_type_default)
      attributes.data_type = ch.data_type == kernels::DataType::Rate ? "rate" : "phase";
    w.add_channel({ch.path.substr(1), ch.units, samples}, attributes);
  }
  w.commit();
  written.emplace(id, file);
  return path;
}

int run_convert(const ConvertArgs& a, const io::InputOptions& options) {
  const fs::path outdir = a.outdir;
  std::error_code ec;
  fs::create_directories(outdir, ec);
  if (ec || !fs::is_directory(outdir, ec)) {
    std::cerr << "allanlot: error: cannot create output directory " << outdir.string() << "\n";
    return kExitUsage;
  }
  std::vector<std::string> given = a.inputs;
  for (const std::string& m : a.manifests)
    given.push_back("@" + m);
  if (given.empty()) throw CLI::ValidationError("INPUT", "no input: give files or @MANIFEST");
  const workflow::InputList inputs = workflow::expand_inputs(given, outdir);
  check_inputs_need(inputs.files, options);
  const std::vector<fs::path> paths(inputs.files.begin(), inputs.files.end());
  for (const auto& [what, reason] : inputs.failures)
    std::cerr << "allanlot: error: " << what << ": " << reason << "\n";
  std::map<std::string, std::string> written;
  std::size_t n_ok = 0;
  bool left_out = false;
  for (const std::string& file : inputs.files) {
    try {
      const fs::path out = convert_one(file, options, outdir, paths, written, std::cerr,
                                       workflow::notes_stream(a.quiet, std::cerr), left_out);
      ++n_ok;
      if (!a.quiet) std::cout << file << " -> " << out.string() << "\n";
    } catch (const io::Error& e) {
      std::cerr << "allanlot: error: " << e.what() << "\n";
    } catch (const std::exception& e) {
      std::cerr << "allanlot: error: " << file << ": " << e.what() << "\n";
    }
  }
  if (n_ok == 0) return kExitUsage;
  const bool all = n_ok == inputs.files.size() + inputs.failures.size() && !left_out;
  return all ? kExitOk : kExitSomeFailed;
}

}  // namespace

Command add_convert_command(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  auto* sub = app.add_subcommand(
      "convert", "Write recordings (text or HDF5) as HDF5 recordings in the canonical layout");
  sub->add_option("-o,--output", a->outdir, "Output directory (one <device_id>.h5 per input)")
      ->required();
  sub->add_option("inputs", a->inputs,
                  "Recordings (text: .txt .dat .csv .tsv, optionally .gz; HDF5), directories, "
                  "or @MANIFEST");
  sub->add_option("--manifest", a->manifests, "A file listing recordings, one per line");
  add_input_options(sub, a->input);
  sub->add_flag("-q,--quiet", a->quiet, "Print only errors");
  return {sub, [a](const std::string&) { return run_convert(*a, input_options(a->input)); }};
}

}  // namespace allanlot::cli
