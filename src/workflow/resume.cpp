#include "src/workflow/resume.hpp"

#include "io/recording.hpp"
#include "src/workflow/inputs.hpp"

namespace fs = std::filesystem;

namespace allanlot::workflow {

std::optional<std::pair<fs::path, std::string>> current_results(const std::string& file,
                                                                const io::InputStat& st,
                                                                const std::string& options,
                                                                const AnalyzeOptions& opt) {
  try {
    io::RecordingReader reader(file, opt.input);
    const std::string id = io::sanitize_device_id(reader.info().device_id);
    const fs::path path = opt.outdir / (id + ".allan.h5");
    const auto stamp = io::read_results_stamp(path);
    if (!stamp || stamp->options != options || stamp->source_file != fs::absolute(file).string() ||
        stamp->input_size != st.size)
      return std::nullopt;
    if (stamp->input_mtime_ns == st.mtime_ns) return std::pair{path, id};
    // Same size, another time (copied, touched): the samples decide.
    std::uint64_t h = io::kHashSeed;
    for (const io::ChannelInfo& ch : reader.info().channels) {
      if (!opt.channels.selects(ch.path)) continue;
      try {
        h = io::combine_hash(h, io::channel_digest(ch.path, reader.read(ch)));
      } catch (const std::exception&) {
        // A channel that cannot be read is not hashed here, as in analyze_recording.
      }
    }
    if (io::hash_hex(h) == stamp->input_hash) return std::pair{path, id};
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

std::string results_of_another_recording(const fs::path& results, const std::string& file,
                                         const std::string& input_hash) {
  const auto stamp = io::read_results_stamp(results);
  if (!stamp) return "";  // absent, damaged or of an earlier version: redone
  // The same recording, or a copy of it under another path (a moved lot): its results.
  if (stamp->source_file == fs::absolute(file).string() || stamp->input_hash == input_hash)
    return "";
  return "its device_id has results in " + results.string() + " made from another recording, " +
         stamp->source_file +
         "; they are kept (give this recording its own device_id, or remove those results)";
}

}  // namespace allanlot::workflow
