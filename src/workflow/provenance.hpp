// What every results file allanlot writes says of its making (docs/formats.md "Results file
// layout": tool_version, created_utc): the one spelling of both, for analyze and the paired
// commands alike.
#pragma once

#include <string>

namespace allanlot::workflow {

/// Now, as results files record their creation: ISO 8601 UTC, e.g. "2026-11-24T10:46:04Z".
std::string utc_now();

/// This build: "VERSION (GIT_SHA)".
std::string tool_version();

}  // namespace allanlot::workflow
