#include "io/growing.hpp"

#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/recording.hpp"

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace allanlot::io {
namespace {

namespace fs = std::filesystem;

// A text recording up to its last complete line, copied to `copy`; false when it has not grown.
bool text_snapshot(const std::string& path, const fs::path& copy, std::uintmax_t* bytes_seen) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "", "cannot open the recording");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto last = text.rfind('\n');
  text.resize(last == std::string::npos ? 0 : last + 1);
  if (text.size() <= *bytes_seen) return false;
  *bytes_seen = text.size();
  std::ofstream out(copy, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out.flush()) throw Error(path, "", "cannot write its snapshot " + copy.string());
  return true;
}

herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

herr_t collect_attribute(hid_t, const char* name, const H5A_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

// An HDF5 recording its writer holds in SWMR mode (a reader without SWMR access is refused):
// every object under the root copied as it stands now (H5Ocopy: the datasets' current extent,
// their attributes), with the root's string attributes (device_id), into `copy`. False when the
// file cannot be opened for SWMR reading (a file not written in SWMR mode: read in place).
bool swmr_snapshot(const std::string& path, const fs::path& copy) {
  h5::quiet_library();
  const hid_t raw = H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, H5P_DEFAULT);
  if (raw < 0) return false;
  const h5::Handle src(raw, H5Fclose);
  const h5::Handle dst = h5::check(H5Fcreate(copy.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                                   H5Fclose, copy.string(), "", "cannot create the snapshot");
  std::vector<std::string> names, attributes;
  h5::check(H5Literate(src.get(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, collect_name, &names),
            path, "/", "cannot list the root group");
  for (const std::string& n : names)
    h5::check(H5Ocopy(src.get(), n.c_str(), dst.get(), n.c_str(), H5P_DEFAULT, H5P_DEFAULT), path,
              n, "cannot copy it into the snapshot");
  h5::check(H5Aiterate2(src.get(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, collect_attribute,
                        &attributes),
            path, "/", "cannot list the root attributes");
  for (const std::string& a : attributes) {
    std::string value;
    try {
      if (!h5::read_attribute(src.get(), a, value, path, "/")) continue;
    } catch (const Error&) {
      continue;  // not a string: the recording layout has none that matter at the root
    }
    h5::write_attribute(dst.get(), a, value, copy.string(), "/");
  }
  return true;
}

}  // namespace

std::string growing_snapshot(const std::string& path, const std::filesystem::path& dir,
                             std::uintmax_t* bytes_seen) {
  const fs::path copy = dir / fs::path(path).filename();
  if (is_text_recording(path)) return text_snapshot(path, copy, bytes_seen) ? copy.string() : "";
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw Error(path, "", "cannot read the recording: " + ec.message());
  if (size <= *bytes_seen) return "";
  *bytes_seen = size;
  return swmr_snapshot(path, copy) ? copy.string() : path;
}

}  // namespace allanlot::io
