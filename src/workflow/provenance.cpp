#include "src/workflow/provenance.hpp"

#include <allanlot/version.hpp>

#include <ctime>

namespace allanlot::workflow {

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string tool_version() {
  return std::string(kVersion) + " (" + kGitSha + ")";
}

}  // namespace allanlot::workflow
