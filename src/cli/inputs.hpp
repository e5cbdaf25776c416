// The INPUT arguments of `analyze` and `convert` and the channel selection, as the commands'
// options name them: the workflow owns them (src/workflow/inputs.hpp).
#pragma once

#include "src/workflow/inputs.hpp"

namespace allanlot::cli {

using workflow::channel_matches;
using workflow::ChannelSelection;
using workflow::expand_inputs;
using workflow::InputList;
using workflow::note_unmatched;
using workflow::unselected_reason;

}  // namespace allanlot::cli
