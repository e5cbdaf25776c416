// HDF5 virtual datasets (VDS, HDF5 1.10): a dataset whose samples the library gathers from
// datasets in other files (or the same one) on every read. allanlot refuses them as channels,
// naming the dataset and its first source: the sources are HDF5 files whose metadata nothing
// has checked (io/isolation.hpp reads only the recording's), and a source that is missing or
// unreadable reads as the fill value (zeros) without an error, samples that were never measured.
#pragma once

#include <hdf5.h>

#include <string>

namespace allanlot::io {

/// Throws io::Error naming `file`, `object` and the dataset's first source when `ds` is a
/// virtual dataset; nothing otherwise.
void refuse_virtual_dataset(hid_t ds, const std::string& file, const std::string& object);

}  // namespace allanlot::io
