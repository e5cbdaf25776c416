#include "src/cli/input_options.hpp"

#include "io/usage_error.hpp"
#include "src/cli/cli.hpp"

namespace allanlot::cli {

void add_input_options(CLI::App* sub, InputArgs& a) {
  sub->add_option("--data-type", a.data_type,
                  "rate or phase, for every channel (overrides the files; text files with one "
                  "column need it)")
      ->check(CLI::IsMember({"rate", "phase"}));
  auto* rate = sub->add_option("--sample-rate", a.sample_rate_hz,
                               "Sample rate in Hz of text files without a time column")
                   ->check(finite_number() & CLI::PositiveNumber);
  sub->add_option("--tau0", a.tau0_s, "Sample interval in s (instead of --sample-rate)")
      ->check(finite_number() & CLI::PositiveNumber)
      ->excludes(rate);
  sub->add_option("--column", a.options.column,
                  "The value column (1-based) of a text file without a header")
      ->check(CLI::Range(1, 1 << 20));
  sub->add_option("--time-column", a.options.time_column,
                  "The time column of a CSV/TSV file, by its header name");
  sub->add_option("--time-unit", a.time_unit, "Unit of a numeric time column: s, ms, us or ns")
      ->check(CLI::IsMember({"s", "ms", "us", "ns"}));
  sub->add_option("--units", a.units,
                  "Units of text columns: UNIT for those whose header names none, GLOB=UNIT for "
                  "the columns the glob matches (comma-separated, repeatable)")
      ->allow_extra_args(false);
  sub->add_option("--topic", a.options.topics,
                  "sensor_msgs/Imu topics of a ROS bag or MCAP file to read (globs, repeatable; "
                  "default every Imu topic)")
      ->allow_extra_args(false);
  sub->add_flag("--receive-time", a.options.receive_time,
                "Time a bag's messages by when they were recorded, not by their header stamps");
  sub->add_option("--nominal-frequency", a.nominal_frequency_hz,
                  "Nominal frequency F in Hz of clock channels in Hz, read as fractional "
                  "frequency (f - F) / F")
      ->check(finite_number() & CLI::PositiveNumber);
}

io::InputOptions input_options(const InputArgs& a) {
  try {
    return workflow::checked_input_options(a);
  } catch (const workflow::OptionError& e) {
    throw CLI::ValidationError(e.option, e.message);
  }
}

void add_channel_options(CLI::App* sub, std::vector<std::string>& include,
                         std::vector<std::string>& exclude) {
  sub->add_option("--channels", include,
                  "Only channels whose path or name matches one of these globs (comma-separated, "
                  "repeatable; !GLOB excludes)")
      ->allow_extra_args(false);
  sub->add_option("--exclude-channels", exclude,
                  "Leave out channels whose path or name matches one of these globs "
                  "(comma-separated, repeatable)")
      ->allow_extra_args(false);
}

workflow::ChannelSelection channel_selection(const std::vector<std::string>& include,
                                             const std::vector<std::string>& exclude) {
  try {
    return workflow::ChannelSelection(include, exclude);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--channels", e.what());
  }
}

void check_inputs_need(const std::vector<std::string>& files, const io::InputOptions& options) {
  try {
    workflow::check_inputs_need(files, options);
  } catch (const io::UsageError& e) {
    throw CLI::ValidationError(e.what());
  }
}

}  // namespace allanlot::cli
