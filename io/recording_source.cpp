#include "io/recording_source.hpp"

#include "io/error.hpp"
#include "io/hdf5_source.hpp"
#include "io/mcap.hpp"
#include "io/ros1_bag.hpp"
#include "io/ros2_bag.hpp"
#include "io/text_source.hpp"
#include "io/usage_error.hpp"
#include "io/utf8.hpp"
#include "kernels/model/units.hpp"

#include <filesystem>
#include <fnmatch.h>

namespace allanlot::io {

std::span<const SourceFormat> source_formats() {
  // Binary formats by their signatures first; text, which takes any file of text, last.
  static const SourceFormat formats[] = {
      hdf5_format(), ros1_bag_format(), mcap_format(), ros2_bag_format(), text_format(),
  };
  return formats;
}

const SourceFormat* find_source_format(const std::string& path) {
  for (const SourceFormat& f : source_formats())
    if (f.recognises(path)) return &f;
  return nullptr;
}

std::string sanitize_device_id(const std::string& id) {
  std::string out;
  out.reserve(id.size());
  for (std::size_t i = 0; i < id.size(); ++i) {
    bool letter = false;
    if (const std::size_t n = name_letter_length(id, i, letter); n > 0) {
      // Another script's letters: device ids in Cyrillic stay apart. Anything else one '_'.
      if (letter)
        out.append(id, i, n);
      else
        out.push_back('_');
      i += n - 1;
      continue;
    }
    const char c = id[i];
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-';
    out.push_back(ok ? c : '_');
  }
  if (out.empty()) out.push_back('_');  // not `out = "_"`: GCC 12 bug 105329 (-Wrestrict)
  if (out[0] == '.') out[0] = '_';      // never ".", "..", or a hidden file
  return out;
}

bool channel_glob_matches(const std::string& glob, const std::string& path) {
  if (glob.empty()) return true;
  const std::string name = path.substr(path.find_last_of('/') + 1);
  return fnmatch(glob.c_str(), path.c_str(), 0) == 0 || fnmatch(glob.c_str(), name.c_str(), 0) == 0;
}

std::string needs_nominal_frequency(const std::string& units) {
  return "units '" + units +
         "' are a frequency: give --nominal-frequency F (Hz) to read it as fractional frequency "
         "(f - F) / F";
}

void in_canonical_units(ChannelInfo& ch, const InputOptions& options, const std::string& file) {
  const auto known = kernels::units::parse_channel_units(ch.units);
  if (!known) return;
  if (known->per_nominal) {
    if (!(options.nominal_frequency_hz > 0))
      throw UsageError(file, ch.path, needs_nominal_frequency(ch.units));
    ch.nominal_hz = options.nominal_frequency_hz;
  }
  ch.units = known->canonical;
  ch.scale *= known->scale;
  ch.offset *= known->scale;
}

void to_physical(const ChannelInfo& channel, std::span<double> samples) {
  if (channel.scale != 1.0 || channel.offset != 0.0)  // a clock's ns or ppb (units.hpp)
    for (double& v : samples)
      v = v * channel.scale + channel.offset;
  if (channel.nominal_hz > 0)
    for (double& v : samples)
      v = kernels::units::to_fractional_frequency(v, channel.nominal_hz);
}

void check_input_options(const std::string& path, const InputOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return;
  const SourceFormat* format = find_source_format(path);
  if (format && format->check_options) format->check_options(path, options);
}

RecordingReader::RecordingReader(const std::string& path, const InputOptions& options) {
  info_.file = path;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(path, "", "no such file");
  const SourceFormat* format = find_source_format(path);
  if (!format && std::filesystem::is_directory(path, ec)) throw Error(path, "", "is a directory");
  if (!format) throw Error(path, "", "not an HDF5 file (or truncated/corrupt)");
  source_ = format->open(path, options);
  info_ = source_->describe();
}

RecordingReader::~RecordingReader() = default;

kernels::LargeVector<double> RecordingReader::read(const ChannelInfo& channel,
                                                   std::size_t chunk) const {
  return source_->read(channel, chunk);
}

}  // namespace allanlot::io
