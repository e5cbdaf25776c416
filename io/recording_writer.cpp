#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/recording.hpp"

#include <algorithm>

namespace allanlot::io {

using h5::check;
using h5::Handle;

struct RecordingWriter::Impl {
  std::string final_path;
  std::unique_ptr<AtomicFile> atomic;
  Handle file, group;
  std::string group_path;
  int deflate = -1;  // no compression

  std::string object(const std::string& name) const {
    return (group_path == "/" ? group_path : group_path + "/") + name;
  }

  // Contiguous by default; chunked (at most 2^16 samples a chunk), shuffled and deflated when
  // asked: chunks of whole samples keep a reader's hyperslabs cheap.
  Handle create_plist(hsize_t n, const std::string& object) const {
    Handle dcpl = h5::dataset_create_plist(final_path, object);
    if (deflate < 0 || n == 0) return dcpl;
    const hsize_t chunk = std::min<hsize_t>(n, hsize_t{1} << 16);
    check(H5Pset_chunk(dcpl.get(), 1, &chunk), final_path, object, "H5Pset_chunk");
    check(H5Pset_shuffle(dcpl.get()), final_path, object, "H5Pset_shuffle");
    check(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(deflate)), final_path, object,
          "H5Pset_deflate");
    return dcpl;
  }
};

RecordingWriter::RecordingWriter(const std::string& path, const std::string& device_id,
                                 double sample_rate_hz, const std::string& group)
    : impl_(std::make_unique<Impl>()) {
  h5::quiet_library();
  impl_->final_path = path;
  impl_->atomic = std::make_unique<AtomicFile>(path);
  // Built in memory and written by one checked write(2), like results files: an HDF5 file on
  // disk whose write fails (a full disk) stays open in the library, which then crashes
  // flushing it at exit.
  impl_->file = h5::create_memory_file(path, h5::Sealed::No);
  Handle root =
      check(H5Gopen2(impl_->file.get(), "/", H5P_DEFAULT), H5Gclose, path, "/", "H5Gopen2");
  h5::write_attribute(root.get(), "device_id", device_id, path, "/");
  impl_->group_path = "/" + group;
  impl_->group = group.empty() ? std::move(root)
                               : h5::ensure_groups(impl_->file.get(), impl_->group_path, path);
  if (sample_rate_hz > 0)
    h5::write_attribute(impl_->group.get(), "sample_rate_hz", sample_rate_hz, path,
                        impl_->group_path);
}

void RecordingWriter::set_deflate(int level) {
  impl_->deflate = level;
}

void RecordingWriter::add_channel_attribute(const std::string& name, const std::string& attr,
                                            const std::string& value) {
  const std::string object = impl_->object(name);
  Handle ds = check(H5Dopen2(impl_->file.get(), object.c_str(), H5P_DEFAULT), H5Dclose,
                    impl_->final_path, object, "H5Dopen2");
  h5::write_attribute(ds.get(), attr, value, impl_->final_path, object);
}

RecordingWriter::~RecordingWriter() = default;

void RecordingWriter::add_channel(const ChannelData& channel, const ChannelAttributes& attributes) {
  const std::string& path = impl_->final_path;
  const std::string object = impl_->object(channel.name);
  const hsize_t n = channel.samples.size();
  Handle space =
      check(H5Screate_simple(1, &n, nullptr), H5Sclose, path, object, "H5Screate_simple");
  Handle dcpl = impl_->create_plist(n, object);
  // Groups on the way to a channel named with a path ("imu/gyro_x") are created as needed.
  Handle lcpl = check(H5Pcreate(H5P_LINK_CREATE), H5Pclose, path, object, "H5Pcreate");
  check(H5Pset_create_intermediate_group(lcpl.get(), 1), path, object,
        "H5Pset_create_intermediate_group");
  Handle ds = check(H5Dcreate2(impl_->group.get(), channel.name.c_str(), H5T_IEEE_F64LE,
                               space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
                    H5Dclose, path, object, "H5Dcreate2");
  if (n > 0)
    check(H5Dwrite(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                   channel.samples.data()),
          path, object, "H5Dwrite (disk full?)");
  if (!channel.units.empty()) h5::write_attribute(ds.get(), "units", channel.units, path, object);
  if (!attributes.data_type.empty())
    h5::write_attribute(ds.get(), "data_type", attributes.data_type, path, object);
  if (attributes.sample_rate_hz > 0)
    h5::write_attribute(ds.get(), "sample_rate_hz", attributes.sample_rate_hz, path, object);
}

void RecordingWriter::add_root_attribute(const std::string& name, const std::string& value) {
  Handle root = check(H5Gopen2(impl_->file.get(), "/", H5P_DEFAULT), H5Gclose, impl_->final_path,
                      "/", "H5Gopen2");
  h5::write_attribute(root.get(), name, value, impl_->final_path, "/");
}

void RecordingWriter::commit() {
  impl_->group.close();
  h5::write_memory_file(impl_->file, *impl_->atomic, impl_->final_path, h5::Sealed::No);
  impl_->atomic->commit();
}

}  // namespace allanlot::io