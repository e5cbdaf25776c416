#include "io/imu_topics.hpp"

#include "io/error.hpp"
#include "io/time_axis.hpp"
#include "io/utf8.hpp"

#include <algorithm>
#include <filesystem>
#include <fnmatch.h>
#include <stdexcept>

namespace allanlot::io {
namespace {

bool matches(const std::string& glob, const std::string& topic) {
  return fnmatch(glob.c_str(), topic.c_str(), 0) == 0;
}

struct Channel {
  ChannelInfo info;
  std::vector<double> samples;
};

// The channels of every topic, in memory, in the order of their paths.
class ImuSource final : public RecordingSource {
public:
  ImuSource(RecordingInfo info, std::vector<Channel> channels)
      : info_(std::move(info)), channels_(std::move(channels)) {
    std::sort(channels_.begin(), channels_.end(),
              [](const Channel& a, const Channel& b) { return a.info.path < b.info.path; });
    for (const Channel& c : channels_)
      info_.channels.push_back(c.info);
  }
  RecordingInfo describe() const override { return info_; }
  kernels::LargeVector<double> read(const ChannelInfo& channel, std::size_t) const override {
    for (const Channel& c : channels_)
      if (c.info.path == channel.path) {
        kernels::LargeVector<double> out(c.samples.begin(), c.samples.end());
        if (channel.scale != 1.0 || channel.offset != 0.0)
          for (double& v : out)
            v = v * channel.scale + channel.offset;
        return out;
      }
    throw Error(info_.file, channel.path, "no such channel");
  }

private:
  RecordingInfo info_;
  std::vector<Channel> channels_;
};

// The stamps in ns after the first, as doubles: the integers subtracted exactly first (an hour
// in ns, 3.6e12, is exact in double's 53 bits).
std::vector<double> times_of(const std::vector<ImuMessage>& msgs, bool receive,
                             const std::string& file, const std::string& topic) {
  std::vector<double> t(msgs.size());
  const auto stamp = [&](const ImuMessage& m) { return receive ? m.receive_ns : m.header_ns; };
  const std::int64_t t0 = stamp(msgs.front());
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    std::int64_t d = 0;
    if (__builtin_sub_overflow(stamp(msgs[i]), t0, &d))
      throw Error(file, topic,
                  "message " + std::to_string(i + 1) +
                      ": time stamp too far from the first for a 64-bit difference");
    t[i] = static_cast<double>(d);
  }
  return t;
}

void add_notes(const std::string& topic, const TimeAxis& axis, RecordingInfo& info) {
  if (axis.n_duplicate + axis.n_decreasing > 0)
    info.notes.push_back("topic '" + topic + "': " + std::to_string(axis.n_duplicate) +
                         " repeated and " + std::to_string(axis.n_decreasing) +
                         " decreasing time stamp(s), each taken as the next sample (the quality "
                         "screen counts them)");
  if (axis.missing > 0)
    info.notes.push_back("topic '" + topic + "': " + std::to_string(axis.missing) +
                         " dropped message(s) in " + std::to_string(axis.gaps.size()) +
                         " place(s), analysed as gaps");
  if (axis.jitter_rms > 0.01 * axis.step)
    info.notes.push_back("topic '" + topic + "': timing jitter rms " +
                         exact_text(axis.jitter_rms * 1e-9) + " s, " +
                         exact_text(100 * axis.jitter_rms / axis.step) + " % of the step " +
                         exact_text(axis.step * 1e-9) + " s");
}

constexpr const char* kNames[6] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};

// A channel's path under its topic: ROS names are absolute ("/imu") but a bag may hold a
// relative one ("imu"), and a channel path always starts with '/' (docs/formats.md).
std::string channel_path(const std::string& topic, const char* name) {
  return (topic.starts_with('/') ? topic : "/" + topic) + "/" + name;
}

// The six channels of one topic; a topic that cannot be timed is a problem of each.
void add_channels(const std::string& topic, const std::vector<ImuMessage>& msgs,
                  const std::string& file, bool receive, RecordingInfo& info,
                  std::vector<Channel>& out) {
  const auto problem = [&](const std::string& reason) {
    for (const char* name : kNames)
      info.problems.push_back({channel_path(topic, name), reason});
  };
  if (msgs.size() < 2) {
    problem("topic has " + std::to_string(msgs.size()) + " message(s): its step is unknown");
    return;
  }
  TimeAxis axis;
  try {
    axis = make_time_axis(times_of(msgs, receive, file, topic),
                          100 * static_cast<std::int64_t>(msgs.size()));
  } catch (const std::invalid_argument& e) {
    problem(std::string(receive ? "receive times: " : "header stamps: ") + e.what());
    return;
  }
  const double rate = 1e9 / axis.step;
  if (!(rate >= kMinSampleRateHz && rate <= kMaxSampleRateHz)) {
    problem("sample rate " + exact_text(rate) + " Hz is outside the rates analysed");
    return;
  }
  add_notes(topic, axis, info);
  if (info.facts.size() == 4) {  // the first topic's step, as a text recording's time column
    add_time_axis_facts(info.facts, axis, 1e-9);
  }
  for (std::size_t k = 0; k < 6; ++k) {
    Channel c;
    std::vector<double> values(msgs.size());
    for (std::size_t i = 0; i < msgs.size(); ++i)
      values[i] = k < 3 ? msgs[i].gyro[k] : msgs[i].accel[k - 3];
    c.samples = with_gaps(std::move(values), axis);
    c.info.path = channel_path(topic, kNames[k]);
    c.info.units = k < 3 ? "rad/s" : "m/s^2";
    c.info.sample_rate_hz = rate;
    c.info.n_samples = static_cast<std::int64_t>(c.samples.size());
    c.info.storage_type = "float64";
    c.info.time_stamps = {axis.n_duplicate, axis.first_duplicate, axis.n_decreasing,
                          axis.first_decreasing};
    in_canonical_units(c.info, InputOptions{}, topic);
    out.push_back(std::move(c));
  }
}

std::string device_of(const std::string& file) {
  std::filesystem::path p = std::filesystem::path(file).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p.stem().string();
}

}  // namespace

ImuTopics::ImuTopics(std::string file, std::string layout, const InputOptions& options)
    : file_(std::move(file)), layout_(std::move(layout)), options_(options) {}

int ImuTopics::add_topic(const std::string& raw_topic, const std::string& raw_type) {
  // Names from the file may hold any bytes; channel paths and messages are valid UTF-8.
  const std::string topic = valid_utf8(raw_topic), type = valid_utf8(raw_type);
  // A topic again (a second publisher, the next file of a split bag): the same channels.
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == topic) return static_cast<int>(i);
  if (std::find(all_.begin(), all_.end(), std::make_pair(topic, type)) != all_.end()) return -1;
  all_.emplace_back(topic, type);
  if (type != kRos1ImuType && type != kRos2ImuType) return -1;
  const bool selected = options_.topics.empty() ||
                        std::any_of(options_.topics.begin(), options_.topics.end(),
                                    [&](const std::string& g) { return matches(g, topic); });
  if (!selected) return -1;
  names_.push_back(topic);
  topics_.emplace_back();
  return static_cast<int>(names_.size()) - 1;
}

std::unique_ptr<RecordingSource> ImuTopics::finish() {
  std::string listed;
  for (const auto& [topic, type] : all_)
    listed += (listed.empty() ? "" : ", ") + topic + " (" + type + ")";
  if (listed.empty()) listed = "none";
  for (const std::string& glob : options_.topics) {
    if (std::any_of(names_.begin(), names_.end(), [&](const auto& t) { return matches(glob, t); }))
      continue;
    for (const auto& [topic, type] : all_)
      if (matches(glob, topic))
        throw Error(file_, topic,
                    "is a " + type + " topic, not sensor_msgs/Imu (--topic '" + glob + "')");
    throw Error(file_, "", "--topic '" + glob + "' matches no topic (topics: " + listed + ")");
  }
  if (names_.empty()) throw Error(file_, "", "no sensor_msgs/Imu topic (topics: " + listed + ")");
  RecordingInfo info;
  info.file = file_;
  info.device_id = device_of(file_);
  info.facts = {{"source_file_name", std::filesystem::path(file_).filename().string()},
                {"source_layout", layout_},
                {"time_column", options_.receive_time ? "receive time" : "header.stamp"},
                {"time_unit", "ns"}};
  std::vector<Channel> channels;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    add_channels(names_[i], topics_[i], file_, options_.receive_time, info, channels);
    topics_[i] = {};
  }
  return std::make_unique<ImuSource>(std::move(info), std::move(channels));
}

}  // namespace allanlot::io
