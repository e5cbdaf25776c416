#include "io/virtual_dataset.hpp"

#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/utf8.hpp"

#include <vector>

namespace allanlot::io {
namespace {

// One name of a mapping (H5Pget_virtual_filename, _dsetname): its length first, then the text.
template <class Get>
std::string mapping_name(Get get) {
  const ssize_t n = get(nullptr, 0);
  if (n <= 0) return "?";
  std::vector<char> text(static_cast<std::size_t>(n) + 1);
  if (get(text.data(), text.size()) < 0) return "?";
  return printable(std::string(text.data(), static_cast<std::size_t>(n)));
}

}  // namespace

void refuse_virtual_dataset(hid_t ds, const std::string& file, const std::string& object) {
  h5::Handle dcpl =
      h5::check(H5Dget_create_plist(ds), H5Pclose, file, object, "H5Dget_create_plist");
  if (H5Pget_layout(dcpl.get()) != H5D_VIRTUAL) return;
  std::size_t count = 0;
  std::string first = "no source";
  if (H5Pget_virtual_count(dcpl.get(), &count) >= 0 && count > 0) {
    const hid_t p = dcpl.get();
    const std::string src =
        mapping_name([&](char* t, std::size_t n) { return H5Pget_virtual_filename(p, 0, t, n); });
    const std::string set =
        mapping_name([&](char* t, std::size_t n) { return H5Pget_virtual_dsetname(p, 0, t, n); });
    first = "the first '" + src + ":" + set + "'";
  }
  throw Error(file, object,
              "a virtual dataset (HDF5 VDS) of " + std::to_string(count) + " source(s), " + first +
                  ": not read, as its sources are HDF5 files nothing has checked and a missing "
                  "one reads as zeros without an error; copy it into a regular dataset "
                  "(h5repack -l " +
                  object + ":CONTI) to analyse it");
}

}  // namespace allanlot::io
