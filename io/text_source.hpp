// Text recordings (io/text_recording.hpp, docs/formats.md "Text recordings") as a recording
// source.
#pragma once

#include "io/recording_source.hpp"

namespace allanlot::io {

/// Recognises a file named like a text recording, gzip-compressed, or text in its first block.
SourceFormat text_format();

}  // namespace allanlot::io
