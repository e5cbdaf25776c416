// HDF5 recordings (docs/formats.md "Input recordings") as a recording source.
#pragma once

#include "io/recording_source.hpp"

namespace allanlot::io {

/// Recognises a file the HDF5 library takes for its own (its signature at 0, 512, 1024, ...).
SourceFormat hdf5_format();

}  // namespace allanlot::io
