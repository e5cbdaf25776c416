// The JSON form of a diagnosis (docs/diagnose.md "The JSON object"): one owner for what `diagnose
// --json` prints, the diagnosis/ group stores and the Python module's diagnose() returns.
#pragma once

#include "kernels/diagnose/diagnose.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace allanlot::workflow {

using Json = nlohmann::ordered_json;

/// The JSON object of docs/diagnose.md for channel `channel`, with further keys after the
/// required ones.
Json diagnosis_json(const std::string& channel, const kernels::Diagnosis& d);

/// {"parameters": {name: value}, "sigmas": {name: sigma or null}} of one effect.
Json parameters_json(const std::vector<kernels::Parameter>& ps);

}  // namespace allanlot::workflow
