#include "io/text_source.hpp"

#include "io/error.hpp"
#include "io/line_reader.hpp"
#include "io/text_recording.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace allanlot::io {
namespace {

// No NUL byte and few control characters in the first 4 KiB: text, not binary.
bool looks_like_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char buf[4096];
  in.read(buf, sizeof buf);
  const auto n = static_cast<std::size_t>(in.gcount());
  if (n == 0) return false;
  std::size_t control = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(buf[i]);
    if (c == 0) return false;
    if (c < 0x20 && c != '\n' && c != '\r' && c != '\t') ++control;
  }
  return control * 100 < n;
}

}  // namespace

bool is_text_recording(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".h5" || ext == ".hdf5") return false;
  return is_text_name(path) || is_gzip_file(path) || looks_like_text(path);
}

namespace {

// The channels of a text recording, all with the recording's rate and data type.
void describe_text(const TextRecording& text, RecordingInfo& info, const InputOptions& options,
                   const std::string& file) {
  info.device_id = text.device_id;
  info.facts = text.facts;
  info.notes = text.notes;
  for (const TextChannel& tc : text.channels) {
    ChannelInfo ch;
    ch.path = tc.path;
    ch.units = tc.units;
    ch.sample_rate_hz = text.sample_rate_hz;
    ch.data_type = text.data_type.value_or(kernels::DataType::Rate);
    ch.data_type_default = !text.data_type;
    ch.n_samples = static_cast<std::int64_t>(tc.samples.size());
    ch.storage_type = "text";
    ch.time_stamps = text.time_stamps;
    in_canonical_units(ch, options, file);
    const double rate = text.sample_rate_hz;
    if (!(rate >= kMinSampleRateHz && rate <= kMaxSampleRateHz)) {
      std::ostringstream msg;
      msg << "sample rate " << rate << " Hz is outside " << kMinSampleRateHz << " .. "
          << kMaxSampleRateHz << " Hz, where the statistics stay within double precision";
      info.problems.push_back({tc.path, msg.str()});
      continue;
    }
    info.channels.push_back(std::move(ch));
  }
}

// A text recording, parsed whole when opened.
class TextSource final : public RecordingSource {
public:
  TextSource(const std::string& path, const InputOptions& options)
      : path_(path), text_(read_text_recording(path, options)) {
    info_.file = path;
    describe_text(text_, info_, options, path);
  }
  RecordingInfo describe() const override { return info_; }

  kernels::LargeVector<double> read(const ChannelInfo& channel, std::size_t) const override {
    for (const TextChannel& tc : text_.channels) {
      if (tc.path != channel.path) continue;
      kernels::LargeVector<double> out(tc.samples.begin(), tc.samples.end());
      to_physical(channel, out);
      return out;
    }
    throw Error(path_, channel.path, "no such column");
  }

private:
  std::string path_;
  TextRecording text_;
  RecordingInfo info_;
};

bool recognises_text(const std::string& path) {
  std::error_code ec;
  return !std::filesystem::is_directory(path, ec) && is_text_recording(path);
}

std::unique_ptr<RecordingSource> open_text(const std::string& path, const InputOptions& options) {
  return std::make_unique<TextSource>(path, options);
}

}  // namespace

SourceFormat text_format() {
  return {"text", recognises_text, check_text_options, open_text};
}

}  // namespace allanlot::io
