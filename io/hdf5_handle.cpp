#include "io/hdf5_handle.hpp"
#include "io/atomic_file.hpp"

#include "io/seal.hpp"
#include "io/utf8.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <mutex>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

namespace allanlot::io::h5 {

void quiet_library() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

Handle check(hid_t id, Handle::Closer closer, const std::string& file, const std::string& object,
             const std::string& what) {
  if (id < 0) throw Error(file, object, what + " failed");
  return Handle(id, closer);
}

void check(herr_t rc, const std::string& file, const std::string& object, const std::string& what) {
  if (rc < 0) throw Error(file, object, what + " failed");
}

bool has_attribute(hid_t obj, const std::string& name) {
  return H5Aexists(obj, name.c_str()) > 0;
}

namespace {

Handle open_attribute(hid_t obj, const std::string& name, const std::string& file,
                      const std::string& object) {
  return check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, file, object,
               "H5Aopen(" + name + ")");
}

// Number of elements of an attribute's dataspace (scalar = 1).
hssize_t attribute_points(hid_t attr, const std::string& file, const std::string& object) {
  Handle space = check(H5Aget_space(attr), H5Sclose, file, object, "H5Aget_space");
  return H5Sget_simple_extent_npoints(space.get());
}

}  // namespace

namespace {

// Opens a numeric attribute of `points` elements (0: any number) and reads it as `mem_type`.
template <class T>
bool read_numbers(hid_t obj, const std::string& name, std::vector<T>& out, hid_t mem_type,
                  hssize_t points, const std::string& file, const std::string& object) {
  if (!has_attribute(obj, name)) return false;
  Handle attr = open_attribute(obj, name, file, object);
  Handle type = check(H5Aget_type(attr.get()), H5Tclose, file, object, "H5Aget_type");
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_INTEGER && cls != H5T_FLOAT)
    throw Error(file, object, "attribute '" + name + "' must be a number");
  const hssize_t n = attribute_points(attr.get(), file, object);
  if (points > 0 && n != points)
    throw Error(file, object, "attribute '" + name + "' must be a single number");
  out.assign(static_cast<std::size_t>(n < 0 ? 0 : n), T{});
  if (!out.empty())
    check(H5Aread(attr.get(), mem_type, out.data()), file, object, "H5Aread(" + name + ")");
  return true;
}

}  // namespace

bool read_attribute(hid_t obj, const std::string& name, double& out, const std::string& file,
                    const std::string& object) {
  std::vector<double> v;
  if (!read_numbers(obj, name, v, H5T_NATIVE_DOUBLE, 1, file, object)) return false;
  out = v[0];
  return true;
}

bool read_attribute(hid_t obj, const std::string& name, std::int64_t& out, const std::string& file,
                    const std::string& object) {
  std::vector<std::int64_t> v;
  if (!read_numbers(obj, name, v, H5T_NATIVE_INT64, 1, file, object)) return false;
  out = v[0];
  return true;
}

bool read_attribute(hid_t obj, const std::string& name, std::vector<double>& out,
                    const std::string& file, const std::string& object) {
  return read_numbers(obj, name, out, H5T_NATIVE_DOUBLE, 0, file, object);
}

bool read_attribute(hid_t obj, const std::string& name, std::string& out, const std::string& file,
                    const std::string& object) {
  if (!has_attribute(obj, name)) return false;
  Handle attr = open_attribute(obj, name, file, object);
  Handle type = check(H5Aget_type(attr.get()), H5Tclose, file, object, "H5Aget_type");
  if (H5Tget_class(type.get()) != H5T_STRING)
    throw Error(file, object, "attribute '" + name + "' must be a string");
  if (attribute_points(attr.get(), file, object) != 1)
    throw Error(file, object, "attribute '" + name + "' must be a single string");
  if (H5Tis_variable_str(type.get()) > 0) {
    Handle mem = check(H5Tcopy(H5T_C_S1), H5Tclose, file, object, "H5Tcopy");
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
    char* s = nullptr;
    check(H5Aread(attr.get(), mem.get(), &s), file, object, "H5Aread(" + name + ")");
    out = s ? s : "";
    if (s) {
      Handle space = check(H5Aget_space(attr.get()), H5Sclose, file, object, "H5Aget_space");
      H5Dvlen_reclaim(mem.get(), space.get(), H5P_DEFAULT, &s);
    }
  } else {
    const std::size_t size = H5Tget_size(type.get());
    if (size == 0 || size > (1u << 20))
      throw Error(file, object, "attribute '" + name + "' has an unusable string size");
    std::vector<char> buf(size + 1, '\0');
    Handle mem = check(H5Tcopy(H5T_C_S1), H5Tclose, file, object, "H5Tcopy");
    H5Tset_size(mem.get(), size + 1);
    check(H5Aread(attr.get(), mem.get(), buf.data()), file, object, "H5Aread(" + name + ")");
    out.assign(buf.data(), std::strlen(buf.data()));
  }
  return true;
}

Handle utf8_string_type(const std::string& file, const std::string& object) {
  Handle t = check(H5Tcopy(H5T_C_S1), H5Tclose, file, object, "H5Tcopy");
  H5Tset_size(t.get(), H5T_VARIABLE);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

Handle open_sealed(const std::filesystem::path& path, const std::string& kind) {
  quiet_library();
  const std::string file = path.string();
  // Checked before HDF5 reads a byte: damaged bytes can crash the library (io/seal.hpp).
  require_intact(path);
  if (H5Fis_hdf5(file.c_str()) <= 0) throw Error(file, "", "not an HDF5 " + kind);
  return check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, file, "", "H5Fopen");
}

namespace {

void replace_attribute(hid_t obj, const std::string& name) {
  if (has_attribute(obj, name)) H5Adelete(obj, name.c_str());
}

template <class T>
void write_scalar_attribute(hid_t obj, const std::string& name, const T* data, hid_t mem_type,
                            hid_t file_type, const std::string& file, const std::string& object) {
  replace_attribute(obj, name);
  Handle space = check(H5Screate(H5S_SCALAR), H5Sclose, file, object, "H5Screate");
  Handle attr =
      check(H5Acreate2(obj, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
            H5Aclose, file, object, "H5Acreate2(" + name + ")");
  check(H5Awrite(attr.get(), mem_type, data), file, object, "H5Awrite(" + name + ")");
}

}  // namespace

void write_attribute(hid_t obj, const std::string& name, const std::string& value,
                     const std::string& file, const std::string& object) {
  replace_attribute(obj, name);
  Handle type = utf8_string_type(file, object);
  Handle space = check(H5Screate(H5S_SCALAR), H5Sclose, file, object, "H5Screate");
  Handle attr =
      check(H5Acreate2(obj, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
            H5Aclose, file, object, "H5Acreate2(" + name + ")");
  const std::string text = valid_utf8(value);
  const char* p = text.c_str();
  check(H5Awrite(attr.get(), type.get(), &p), file, object, "H5Awrite(" + name + ")");
}

void write_attribute(hid_t obj, const std::string& name, double value, const std::string& file,
                     const std::string& object) {
  write_scalar_attribute(obj, name, &value, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, file, object);
}

void write_attribute(hid_t obj, const std::string& name, std::int64_t value,
                     const std::string& file, const std::string& object) {
  write_scalar_attribute(obj, name, &value, H5T_NATIVE_INT64, H5T_STD_I64LE, file, object);
}

void write_attribute(hid_t obj, const std::string& name, const std::vector<double>& value,
                     const std::string& file, const std::string& object) {
  replace_attribute(obj, name);
  const hsize_t n = value.size();
  Handle space =
      check(H5Screate_simple(1, &n, nullptr), H5Sclose, file, object, "H5Screate_simple");
  Handle attr =
      check(H5Acreate2(obj, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
            H5Aclose, file, object, "H5Acreate2(" + name + ")");
  check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, value.data()), file, object,
        "H5Awrite(" + name + ")");
}

namespace {
Handle untimed_plist(hid_t cls, const std::string& file, const std::string& object) {
  Handle p = check(H5Pcreate(cls), H5Pclose, file, object, "H5Pcreate");
  check(H5Pset_obj_track_times(p.get(), false), file, object, "H5Pset_obj_track_times");
  return p;
}
}  // namespace

Handle group_create_plist(const std::string& file, const std::string& object) {
  return untimed_plist(H5P_GROUP_CREATE, file, object);
}

Handle dataset_create_plist(const std::string& file, const std::string& object) {
  return untimed_plist(H5P_DATASET_CREATE, file, object);
}

Handle create_memory_file(const std::string& file, Sealed sealed) {
  Handle fapl = check(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, file, "", "H5Pcreate");
  // Grow the image 1 MiB at a time; backing_store = false: nothing is written by HDF5.
  check(H5Pset_fapl_core(fapl.get(), std::size_t{1} << 20, false), file, "", "H5Pset_fapl_core");
  // The user block holds the seal (io/seal.hpp): write_memory_file writes it before the image.
  Handle fcpl = check(H5Pcreate(H5P_FILE_CREATE), H5Pclose, file, "", "H5Pcreate");
  if (sealed == Sealed::Yes)
    check(H5Pset_userblock(fcpl.get(), kSealBytes), file, "", "H5Pset_userblock");
  return check(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose, file, "",
               "H5Fcreate (in memory)");
}

Handle open_memory_copy(const std::filesystem::path& path, const std::string& file) {
  require_intact(path);
  Handle fapl = check(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, file, "", "H5Pcreate");
  check(H5Pset_fapl_core(fapl.get(), std::size_t{1} << 20, false), file, "", "H5Pset_fapl_core");
  return check(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()), H5Fclose, file, "",
               "H5Fopen (in memory)");
}

void write_memory_file(Handle& f, const AtomicFile& out, const std::string& file, Sealed sealed) {
  check(H5Fflush(f.get(), H5F_SCOPE_GLOBAL), file, "", "H5Fflush (in memory)");
  const ssize_t size = H5Fget_file_image(f.get(), nullptr, 0);
  if (size < 0) throw Error(file, "", "H5Fget_file_image failed");
  std::vector<char> image(static_cast<std::size_t>(size));
  if (H5Fget_file_image(f.get(), image.data(), image.size()) != size)
    throw Error(file, "", "H5Fget_file_image failed");
  if (f.close() < 0) throw Error(file, "", "H5Fclose (in memory) failed");
  if (sealed == Sealed::Yes) {
    const auto seal = seal_block(image);
    image.insert(image.begin(), seal.begin(), seal.end());
  }
  out.write(image.data(), image.size());
}

Handle ensure_groups(hid_t file_id, const std::string& path, const std::string& file) {
  Handle current = check(H5Gopen2(file_id, "/", H5P_DEFAULT), H5Gclose, file, "/", "H5Gopen2");
  std::string so_far;
  std::size_t pos = 0;
  while (pos < path.size()) {
    const std::size_t next = path.find('/', pos);
    const std::string part =
        path.substr(pos, next == std::string::npos ? std::string::npos : next - pos);
    pos = next == std::string::npos ? path.size() : next + 1;
    if (part.empty()) continue;
    so_far += "/" + part;
    const htri_t exists = H5Lexists(current.get(), part.c_str(), H5P_DEFAULT);
    if (exists > 0) {
      current = check(H5Gopen2(current.get(), part.c_str(), H5P_DEFAULT), H5Gclose, file, so_far,
                      "H5Gopen2");
    } else {
      current = check(H5Gcreate2(current.get(), part.c_str(), H5P_DEFAULT,
                                 group_create_plist(file, so_far).get(), H5P_DEFAULT),
                      H5Gclose, file, so_far, "H5Gcreate2");
    }
  }
  return current;
}

namespace {

template <class T>
void write_plain(hid_t loc, const std::string& name, const std::vector<T>& v, hid_t mem_type,
                 hid_t file_type, const std::string& file, const std::string& object) {
  const hsize_t n = v.size();
  Handle space =
      check(H5Screate_simple(1, &n, nullptr), H5Sclose, file, object, "H5Screate_simple");
  Handle ds = check(H5Dcreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT,
                               dataset_create_plist(file, object).get(), H5P_DEFAULT),
                    H5Dclose, file, object + "/" + name, "H5Dcreate2");
  if (n > 0)
    check(H5Dwrite(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), file,
          object + "/" + name, "H5Dwrite");
}

Handle open_dataset(hid_t loc, const std::string& name, const std::string& file,
                    const std::string& object) {
  return check(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose, file, object + "/" + name,
               "H5Dopen2");
}

std::size_t dataset_length(hid_t ds, const std::string& file, const std::string& object) {
  Handle space = check(H5Dget_space(ds), H5Sclose, file, object, "H5Dget_space");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank != 1) throw Error(file, object, "expected a 1-D dataset");
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  return static_cast<std::size_t>(n);
}

template <class T>
std::vector<T> read_plain(hid_t loc, const std::string& name, hid_t mem_type,
                          const std::string& file, const std::string& object) {
  Handle ds = open_dataset(loc, name, file, object);
  std::vector<T> v(dataset_length(ds.get(), file, object + "/" + name));
  if (!v.empty())
    check(H5Dread(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), file,
          object + "/" + name, "H5Dread");
  return v;
}

}  // namespace

void write_dataset(hid_t loc, const std::string& name, const std::vector<double>& v,
                   const std::string& file, const std::string& object) {
  write_plain(loc, name, v, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, file, object);
}
void write_dataset(hid_t loc, const std::string& name, const std::vector<std::int64_t>& v,
                   const std::string& file, const std::string& object) {
  write_plain(loc, name, v, H5T_NATIVE_INT64, H5T_STD_I64LE, file, object);
}
void write_dataset(hid_t loc, const std::string& name, const std::vector<int>& v,
                   const std::string& file, const std::string& object) {
  write_plain(loc, name, v, H5T_NATIVE_INT, H5T_STD_I32LE, file, object);
}

namespace {

// A transfer list whose conversion buffers hold the n strings of one dataset at once. HDF5's
// default, 1 MiB for the conversion and another for the background buffer, is calloc'ed and
// cleared for every string dataset read or written: most of the time a results file took
// (page faults and memset, some 60 % of `analyze` on a lot of one-minute units). One pass
// over the whole dataset, as before, so the file holds the same bytes.
Handle string_transfer_plist(std::size_t n, const std::string& file, const std::string& object) {
  // Wider than an element of either side: a char* in memory, a 16-byte global heap ID on file.
  constexpr std::size_t kElementBound = 32;
  Handle dxpl = check(H5Pcreate(H5P_DATASET_XFER), H5Pclose, file, object, "H5Pcreate");
  check(H5Pset_buffer(dxpl.get(), std::max<std::size_t>(n, 1) * kElementBound, nullptr, nullptr),
        file, object, "H5Pset_buffer");
  return dxpl;
}

}  // namespace

void write_dataset(hid_t loc, const std::string& name, const std::vector<std::string>& v,
                   const std::string& file, const std::string& object) {
  Handle type = utf8_string_type(file, object);
  std::vector<std::string> texts;
  texts.reserve(v.size());
  for (const auto& s : v)
    texts.push_back(valid_utf8(s));
  std::vector<const char*> ptrs;
  ptrs.reserve(v.size());
  for (const auto& s : texts)
    ptrs.push_back(s.c_str());
  const hsize_t n = v.size();
  Handle space =
      check(H5Screate_simple(1, &n, nullptr), H5Sclose, file, object, "H5Screate_simple");
  Handle ds = check(H5Dcreate2(loc, name.c_str(), type.get(), space.get(), H5P_DEFAULT,
                               dataset_create_plist(file, object).get(), H5P_DEFAULT),
                    H5Dclose, file, object + "/" + name, "H5Dcreate2");
  if (n > 0)
    check(H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL,
                   string_transfer_plist(v.size(), file, object).get(), ptrs.data()),
          file, object + "/" + name, "H5Dwrite");
}

void write_dataset(hid_t loc, const std::string& name, const std::vector<std::uint8_t>& v,
                   const std::string& file, const std::string& object) {
  write_plain(loc, name, v, H5T_NATIVE_UINT8, H5T_STD_U8LE, file, object);
}

std::vector<double> read_doubles(hid_t loc, const std::string& name, const std::string& file,
                                 const std::string& object) {
  return read_plain<double>(loc, name, H5T_NATIVE_DOUBLE, file, object);
}
std::vector<std::int64_t> read_int64s(hid_t loc, const std::string& name, const std::string& file,
                                      const std::string& object) {
  return read_plain<std::int64_t>(loc, name, H5T_NATIVE_INT64, file, object);
}
std::vector<std::string> read_strings(hid_t loc, const std::string& name, const std::string& file,
                                      const std::string& object) {
  Handle ds = open_dataset(loc, name, file, object);
  const std::size_t n = dataset_length(ds.get(), file, object + "/" + name);
  Handle type = utf8_string_type(file, object);
  std::vector<char*> ptrs(n, nullptr);
  if (n > 0)
    check(H5Dread(ds.get(), type.get(), H5S_ALL, H5S_ALL,
                  string_transfer_plist(n, file, object).get(), ptrs.data()),
          file, object + "/" + name, "H5Dread");
  std::vector<std::string> out;
  out.reserve(n);
  for (char* p : ptrs)
    out.emplace_back(p ? p : "");
  if (n > 0) {
    Handle space = check(H5Dget_space(ds.get()), H5Sclose, file, object, "H5Dget_space");
    H5Dvlen_reclaim(type.get(), space.get(), H5P_DEFAULT, ptrs.data());
  }
  return out;
}

}  // namespace allanlot::io::h5
