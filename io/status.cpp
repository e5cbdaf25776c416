#include "io/status.hpp"

#include "io/error.hpp"

#include <array>
#include <ostream>

namespace allanlot::io {

namespace {
constexpr std::string_view kFailedPrefix = "failed: ";
}  // namespace

std::string to_string(const ChannelStatus& s) {
  if (s.state == ChannelState::Ok) return "ok";
  return std::string(kFailedPrefix) + s.reason;
}

ChannelStatus parse_channel_status(std::string_view text, const std::string& file,
                                   const std::string& object) {
  if (text == "ok") return ChannelStatus::ok();
  if (text.starts_with(kFailedPrefix))
    return ChannelStatus::failed(std::string(text.substr(kFailedPrefix.size())));
  throw Error(file, object,
              "unknown channel status '" + std::string(text) +
                  "' (expected 'ok' or 'failed: ...')");
}

std::string to_string(kernels::FitStatus s) {
  return std::string(kernels::fit_status_name(s));
}

kernels::FitStatus parse_fit_status(std::string_view text, const std::string& file,
                                    const std::string& object) {
  using kernels::FitStatus;
  constexpr std::array kAll = {FitStatus::Ok, FitStatus::PoorFit, FitStatus::NoData,
                               FitStatus::RankDeficient, FitStatus::NoConvergence};
  for (const FitStatus s : kAll)
    if (kernels::fit_status_name(s) == text) return s;
  throw Error(file, object, "unknown fit status '" + std::string(text) + "'");
}

std::ostream& operator<<(std::ostream& os, const ChannelStatus& s) {
  return os << to_string(s);
}

}  // namespace allanlot::io
