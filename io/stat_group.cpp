#include "io/stat_group.hpp"

#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/schema_h5.hpp"

namespace allanlot::io {

kernels::StatResult read_stat_group(const std::filesystem::path& path, const std::string& group) {
  const std::string file = path.string();
  h5::Handle f = h5::open_sealed(path, "results file");
  if (group.empty() || group[0] != '/') throw Error(file, group, "not an absolute group path");
  // H5Lexists on a nested path needs every ancestor to exist: check them one by one.
  for (std::size_t pos = group.find('/', 1);; pos = group.find('/', pos + 1)) {
    const std::string part = group.substr(0, pos);
    if (H5Lexists(f.get(), part.c_str(), H5P_DEFAULT) <= 0)
      throw Error(file, part, "no such group");
    if (pos == std::string::npos) break;
  }
  h5::Handle g =
      h5::check(H5Gopen2(f.get(), group.c_str(), H5P_DEFAULT), H5Gclose, file, group, "H5Gopen2");
  kernels::StatResult r;
  schema::read_fields(g.get(), r, schema::stat_fields(), schema::Depth::Full, file, group);
  return r;
}

}  // namespace allanlot::io
