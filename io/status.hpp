// Statuses of the results schema: enums in memory, text only at the file boundary
// (docs/formats.md "Results file layout": the channel's and fit/'s `status` attributes; "Lot
// summary": the `status` column). One to_string/parse pair per enum; parse names the file and
// the dataset of an unknown spelling.
#pragma once

#include "kernels/model/fit.hpp"

#include <iosfwd>
#include <string>
#include <string_view>

namespace allanlot::io {

/// A channel's outcome (or a failed input's, in the lot summary): ok, or failed and why.
enum class ChannelState { Ok, Failed };

struct ChannelStatus {
  ChannelState state = ChannelState::Ok;
  std::string reason;  // why it failed; empty when ok

  static ChannelStatus ok() { return {}; }
  static ChannelStatus failed(std::string why) { return {ChannelState::Failed, std::move(why)}; }
  bool is_ok() const { return state == ChannelState::Ok; }
  bool operator==(const ChannelStatus&) const = default;
};

/// "ok", or "failed: <reason>".
std::string to_string(const ChannelStatus& s);
/// Inverse of to_string; io::Error(file, object, ...) naming the text for anything else.
ChannelStatus parse_channel_status(std::string_view text, const std::string& file,
                                   const std::string& object);

/// The fit's status as fit/ and psd_fit/ store it: kernels::fit_status_name ("ok", "no data",
/// "rank deficient", "no convergence").
std::string to_string(kernels::FitStatus s);
/// Inverse of to_string; io::Error(file, object, ...) naming the text for anything else.
kernels::FitStatus parse_fit_status(std::string_view text, const std::string& file,
                                    const std::string& object);

/// The text of to_string, for messages and test output.
std::ostream& operator<<(std::ostream& os, const ChannelStatus& s);

}  // namespace allanlot::io
