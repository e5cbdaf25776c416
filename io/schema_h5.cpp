#include "io/schema_h5.hpp"

namespace allanlot::io::schema {

using h5::check;
using h5::Handle;

Handle create_group(hid_t parent, const char* name, const std::string& file,
                    const std::string& object) {
  Handle gcpl = h5::group_create_plist(file, object);
  return check(H5Gcreate2(parent, name, H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose, file,
               object, "H5Gcreate2");
}

Handle open_group(hid_t parent, const char* name, const std::string& file,
                  const std::string& object) {
  return check(H5Gopen2(parent, name, H5P_DEFAULT), H5Gclose, file, object, "H5Gopen2");
}

bool has_link(hid_t parent, const char* name) {
  return H5Lexists(parent, name, H5P_DEFAULT) > 0;
}

void write_version(hid_t root, const std::string& file) {
  h5::write_attribute(root, kVersionAttribute, kVersion, file, "/");
}

void check_version(hid_t root, const std::string& file) {
  std::int64_t version = 1;  // files from before the attribute: today's layout
  h5::read_attribute(root, kVersionAttribute, version, file, "/");
  if (version < 1 || version > kVersion)
    throw Error(file, "/",
                "schema_version " + std::to_string(version) +
                    " is not one this allanlot reads (1 to " + std::to_string(kVersion) +
                    "); a newer allanlot wrote it");
}

}  // namespace allanlot::io::schema
