#include "io/hdf5_source.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/isolation.hpp"
#include "io/recording_source.hpp"
#include "io/text_fields.hpp"
#include "io/text_recording.hpp"
#include "io/usage_error.hpp"
#include "io/virtual_dataset.hpp"
#include "kernels/model/units.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <span>
#include <sstream>
#include <sys/stat.h>

namespace allanlot::io {

using h5::check;
using h5::Handle;

namespace {

// An HDF5 recording (docs/formats.md "Input recordings"): its channels are the 1-D numeric
// datasets in the scope of a sample_rate_hz attribute.
class Hdf5Source final : public RecordingSource {
public:
  Hdf5Source(const std::string& path, const InputOptions& options);
  ~Hdf5Source() override;
  RecordingInfo describe() const override { return info_; }
  kernels::LargeVector<double> read(const ChannelInfo& channel, std::size_t chunk) const override;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  RecordingInfo info_;
};

std::string describe_type(hid_t type) {
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t bits = H5Tget_size(type) * 8;
  if (cls == H5T_FLOAT) return "float" + std::to_string(bits);
  if (cls == H5T_INTEGER)
    return std::string(H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + std::to_string(bits);
  switch (cls) {
  case H5T_STRING:
    return "string";
  case H5T_COMPOUND:
    return "compound";
  case H5T_ENUM:
    return "enum";
  case H5T_ARRAY:
    return "array";
  case H5T_VLEN:
    return "variable-length";
  default:
    return "non-numeric";
  }
}

// One hard link of a group, as the walk below lists it.
struct Link {
  std::string name;
  H5O_type_t type = H5O_TYPE_UNKNOWN;
  haddr_t addr = HADDR_UNDEF;
};

herr_t list_link(hid_t group, const char* name, const H5L_info_t* info, void* data) {
  if (info->type != H5L_TYPE_HARD) return 0;  // as H5Ovisit: soft and external links not followed
  H5O_info_t oi;
  if (H5Oget_info_by_name2(group, name, &oi, H5O_INFO_BASIC, H5P_DEFAULT) < 0) return -1;
  static_cast<std::vector<Link>*>(data)->push_back({name, oi.type, oi.addr});
  return 0;
}

// Every dataset of the file, each object once, depth first in name order (what H5Ovisit gives),
// each group opened by its name in its parent: linear in the number of objects, where H5Ovisit
// took over a minute for 2000 nested groups.
std::vector<std::string> list_datasets(hid_t file, const std::string& path) {
  struct Frame {
    Handle group;
    std::string path;
    std::vector<Link> links;
    std::size_t next = 0;
  };
  std::vector<std::string> datasets;
  std::set<haddr_t> seen;
  std::vector<Frame> stack;
  const auto push = [&](Handle group, std::string at) {
    std::vector<Link> links;
    if (H5Literate(group.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, list_link, &links) < 0)
      // A group below the root is named; the root's failure is the file's.
      throw Error(path, at, "cannot walk the file's objects (corrupt HDF5 file)");
    stack.push_back({std::move(group), std::move(at), std::move(links)});
  };
  Handle root = check(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose, path, "/", "H5Gopen2");
  H5O_info_t root_info;
  if (H5Oget_info2(root.get(), &root_info, H5O_INFO_BASIC) >= 0) seen.insert(root_info.addr);
  push(std::move(root), "");
  while (!stack.empty()) {
    Frame& top = stack.back();
    if (top.next == top.links.size()) {
      stack.pop_back();
      continue;
    }
    const Link link = top.links[top.next++];
    if (!seen.insert(link.addr).second) continue;
    const std::string at = top.path + "/" + link.name;
    if (link.type == H5O_TYPE_DATASET) datasets.push_back(at);
    if (link.type == H5O_TYPE_GROUP)
      push(check(H5Gopen2(top.group.get(), link.name.c_str(), H5P_DEFAULT), H5Gclose, path, at,
                 "H5Gopen2"),
           at);
  }
  return datasets;
}

}  // namespace

struct Hdf5Source::Impl {
  std::string path;
  Handle file;

  // A dataset without filters stores every sample it declares; one that stores less was never
  // (wholly) written, and HDF5 would return its fill value (zeros) for the rest: a 1.4 KB file
  // may declare 3e8 samples. Refused before the samples are allocated. (Compressed datasets
  // cannot be checked this way; their reads fail on a missing chunk.)
  void check_stored(hid_t ds, hsize_t n, const std::string& object) const {
    Handle dcpl = check(H5Dget_create_plist(ds), H5Pclose, path, object, "H5Dget_create_plist");
    Handle type = check(H5Dget_type(ds), H5Tclose, path, object, "H5Dget_type");
    const int n_filters = H5Pget_nfilters(dcpl.get());
    for (int i = 0; i < n_filters; ++i)
      require_filter(dcpl.get(), static_cast<unsigned>(i), object);
    if (n_filters != 0) return;
    hsize_t need = 0;
    const hsize_t stored = H5Dget_storage_size(ds);
    if (__builtin_mul_overflow(n, H5Tget_size(type.get()), &need) || stored < need)
      throw Error(path, object,
                  "declares " + std::to_string(n) + " samples but stores only " +
                      std::to_string(stored) + " bytes of them (never written?)");
  }

  // A filter (compression) this HDF5 library lacks, neither built in nor a plugin on
  // HDF5_PLUGIN_PATH: named, instead of the read failing as if the data were corrupt.
  void require_filter(hid_t dcpl, unsigned i, const std::string& object) const {
    unsigned flags = 0, config = 0;
    std::size_t n_values = 0;
    char name[256] = {};
    const H5Z_filter_t id =
        H5Pget_filter2(dcpl, i, &flags, &n_values, nullptr, sizeof name, name, &config);
    if (id < 0 || H5Zfilter_avail(id) > 0) return;
    throw Error(path, object,
                "compressed with HDF5 filter " + std::to_string(id) +
                    (name[0] ? " (" + std::string(name) + ")" : std::string()) +
                    ", which this HDF5 library does not have: install its plugin (on "
                    "HDF5_PLUGIN_PATH) or rewrite the file without it (h5repack -f NONE)");
  }

  // The file must still hold all that its HDF5 layout addresses: HDF5 refuses to open a file
  // shorter than that, but one truncated after it was opened reads as zeros past its new end
  // without an error (a recording still being copied, a disk that filled up).
  void check_whole(const std::string& object) const {
    haddr_t eoa = 0;
    if (H5Fget_eoa(file.get(), &eoa) < 0) return;
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0)
      throw Error(path, object, std::string("vanished while it was read: ") + std::strerror(errno));
    if (static_cast<haddr_t>(st.st_size) < eoa)
      throw Error(path, object,
                  "truncated while it was read: " + std::to_string(st.st_size) +
                      " bytes, its HDF5 layout needs " + std::to_string(eoa));
  }

  // A channel's dataset, refused when it is virtual (io/virtual_dataset.hpp) or its raw data
  // lie in external files that are not regular files beside the recording (check_external).
  Handle open_dataset(const std::string& object) const {
    Handle ds = check(H5Dopen2(file.get(), object.c_str(), H5P_DEFAULT), H5Dclose, path, object,
                      "H5Dopen2");
    refuse_virtual_dataset(ds.get(), path, object);
    check_external(ds.get(), object);
    return ds;
  }

  // External raw storage (H5Pset_external) is read from wherever its names point, as the
  // library resolves them (from the working directory): a FIFO would block the read for ever,
  // /etc/shadow or /dev/urandom would be read as samples. Only a regular file (not a link) in
  // the recording's own directory is accepted. (The library's "${ORIGIN}" prefix is no way
  // out: a dataset opened with one cannot be opened again without it, as attributes are.)
  void check_external(hid_t ds, const std::string& object) const {
    Handle dcpl = check(H5Dget_create_plist(ds), H5Pclose, path, object, "H5Dget_create_plist");
    const int n = H5Pget_external_count(dcpl.get());
    std::error_code ec;
    const auto home = std::filesystem::weakly_canonical(path, ec).parent_path();
    for (int i = 0; i < n; ++i) {
      char name[4096] = {};
      off_t offset = 0;
      hsize_t size = 0;
      if (H5Pget_external(dcpl.get(), static_cast<unsigned>(i), sizeof name, name, &offset, &size) <
          0)
        throw Error(path, object, "its external raw data storage cannot be read");
      const std::string ext(name, ::strnlen(name, sizeof name));
      const std::string what = "raw data in the external file '" + ext + "': ";
      struct stat st {};
      if (ext.empty() || ::lstat(ext.c_str(), &st) != 0)
        throw Error(path, object, what + std::strerror(ext.empty() ? ENOENT : errno));
      if (!S_ISREG(st.st_mode)) throw Error(path, object, what + "not a regular file");
      if (std::filesystem::weakly_canonical(ext, ec).parent_path() != home || ec)
        throw Error(path, object, what + "not beside the recording");
    }
  }

  // The root, each group on the way to `object`, and `object`, with their paths: each opened
  // by its name in its parent, so the cost is linear in the depth (opened by full path, each
  // ancestor costs its own depth again: 2000 nested groups took over a minute).
  std::vector<std::pair<std::string, Handle>> open_chain(const std::string& object) const {
    std::vector<std::pair<std::string, Handle>> chain;
    chain.emplace_back(
        "/", check(H5Oopen(file.get(), "/", H5P_DEFAULT), H5Oclose, path, "/", "H5Oopen"));
    std::size_t pos = 1;
    while (pos < object.size()) {
      const std::size_t next = std::min(object.find('/', pos), object.size());
      const std::string at = object.substr(0, next);
      const std::string name = object.substr(pos, next - pos);
      chain.emplace_back(at, check(H5Oopen(chain.back().second.get(), name.c_str(), H5P_DEFAULT),
                                   H5Oclose, path, at, "H5Oopen"));
      pos = next + 1;
    }
    return chain;
  }

  // Looks `attr` up on `object`, then on each ancestor group up to the root (the lookup order
  // of docs/formats.md "Input recordings"); returns the path where it was found, or "" when
  // absent everywhere.
  template <class T>
  std::string find_attribute(const std::string& object, const std::string& attr, T& out) const {
    const auto chain = open_chain(object);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it)
      if (h5::read_attribute(it->second.get(), attr, out, path, it->first)) return it->first;
    return "";
  }
};

namespace {
// The root's device_id (else the file's stem) and the facts of a recording (kTextFactNames).
void read_root(hid_t root, const std::string& path, RecordingInfo& info) {
  std::string id;
  if (h5::read_attribute(root, "device_id", id, path, "/") && !id.empty()) {
    info.device_id = id;
  } else {
    info.device_id = std::filesystem::path(path).stem().string();
  }
  for (const char* name : kTextFactNames) {
    std::string value;
    try {
      if (h5::read_attribute(root, name, value, path, "/")) info.facts.emplace_back(name, value);
    } catch (const Error&) {
      // A root attribute of that name but another type is the file's own, not a fact.
    }
  }
}

}  // namespace

Hdf5Source::Hdf5Source(const std::string& path, const InputOptions& options)
    : impl_(std::make_unique<Impl>()) {
  h5::quiet_library();
  impl_->path = path;
  info_.file = path;
  // The metadata is read once in a child process first (io/isolation.hpp): hostile bytes that
  // crash the HDF5 library fail this input, not the process.
  if (!in_isolated_child()) run_isolated(path, [&] { Hdf5Source probe(path, options); });
  impl_->file = check(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "",
                      "H5Fopen (corrupt or unreadable HDF5 file)");

  Handle root =
      check(H5Gopen2(impl_->file.get(), "/", H5P_DEFAULT), H5Gclose, path, "/", "H5Gopen2");
  read_root(root.get(), path, info_);
  // A recording of `allanlot simulate` (its model at the root) holds rates: simulate
  // synthesizes rate channels only, so their data type is known, not a default.
  const bool simulated = H5Aexists(root.get(), "simulated_model") > 0;

  std::vector<std::string> datasets = list_datasets(impl_->file.get(), path);
  std::sort(datasets.begin(), datasets.end());

  for (const std::string& ds_path : datasets) {
    const std::string leaf = ds_path.substr(ds_path.find_last_of('/') + 1);
    if (is_time_name(leaf)) continue;  // time stamps, never a channel
    try {
      ChannelInfo ch;
      ch.path = ds_path;
      double rate = 0.0;
      const std::string rate_at = impl_->find_attribute(ds_path, "sample_rate_hz", rate);
      if (rate_at.empty()) continue;  // not in any channel's scope: not a channel
      Handle ds = impl_->open_dataset(ds_path);
      Handle type = check(H5Dget_type(ds.get()), H5Tclose, path, ds_path, "H5Dget_type");
      const H5T_class_t cls = H5Tget_class(type.get());
      ch.storage_type = describe_type(type.get());
      Handle space = check(H5Dget_space(ds.get()), H5Sclose, path, ds_path, "H5Dget_space");
      const int rank = H5Sget_simple_extent_ndims(space.get());
      if (cls != H5T_INTEGER && cls != H5T_FLOAT) {
        // A non-numeric dataset beside the channels (labels, metadata) is not a channel; it
        // is an error only when it carries sample_rate_hz itself, i.e. claims to be one.
        if (rate_at == ds_path)
          info_.problems.push_back(
              {ds_path, "dataset of type " + ch.storage_type + " cannot be a channel"});
        continue;
      }
      if (rank != 1) {
        info_.problems.push_back({ds_path, "dataset has " + std::to_string(rank) +
                                               " dimensions; a channel must be 1-D"});
        continue;
      }
      if (!std::isfinite(rate) || rate <= 0.0) {
        std::ostringstream msg;
        msg << "sample_rate_hz = " << rate << " (on " << rate_at << ") must be finite and > 0";
        info_.problems.push_back({ds_path, msg.str()});
        continue;
      }
      if (rate < kMinSampleRateHz || rate > kMaxSampleRateHz) {
        std::ostringstream msg;
        msg << "sample_rate_hz = " << rate << " (on " << rate_at << ") is outside "
            << kMinSampleRateHz << " .. " << kMaxSampleRateHz
            << " Hz, where the statistics stay within double precision";
        info_.problems.push_back({ds_path, msg.str()});
        continue;
      }
      ch.sample_rate_hz = rate;
      hsize_t n = 0;
      H5Sget_simple_extent_dims(space.get(), &n, nullptr);
      if (n > kMaxSamples) {
        info_.problems.push_back({ds_path, "declares " + std::to_string(n) +
                                               " samples, more than any memory holds (at most " +
                                               std::to_string(kMaxSamples) + ")"});
        continue;
      }
      ch.n_samples = static_cast<std::int64_t>(n);
      impl_->find_attribute(ds_path, "units", ch.units);
      ch.has_scale = !impl_->find_attribute(ds_path, "scale", ch.scale).empty();
      impl_->find_attribute(ds_path, "offset", ch.offset);
      in_canonical_units(ch, options, path);
      if (!std::isfinite(ch.scale) || ch.scale == 0.0 || !std::isfinite(ch.offset)) {
        info_.problems.push_back({ds_path, "scale must be finite and non-zero, offset finite"});
        continue;
      }
      std::string dtype;
      if (options.data_type) {
        ch.data_type = *options.data_type;  // --data-type overrides the file
      } else if (impl_->find_attribute(ds_path, "data_type", dtype).empty()) {
        ch.data_type_default = !simulated;
      } else {
        if (dtype == "rate") {
          ch.data_type = kernels::DataType::Rate;
        } else if (dtype == "phase") {
          ch.data_type = kernels::DataType::Phase;
        } else {
          info_.problems.push_back(
              {ds_path, "data_type '" + dtype + "' is neither 'rate' nor 'phase'"});
          continue;
        }
      }
      info_.channels.push_back(std::move(ch));
    } catch (const Error& e) {
      info_.problems.push_back({ds_path, e.reason()});
    }
  }
}

Hdf5Source::~Hdf5Source() = default;

kernels::LargeVector<double> Hdf5Source::read(const ChannelInfo& channel, std::size_t chunk) const {
  const std::string& file = impl_->path;
  Handle ds = impl_->open_dataset(channel.path);
  Handle fspace = check(H5Dget_space(ds.get()), H5Sclose, file, channel.path, "H5Dget_space");
  hsize_t n = 0;
  H5Sget_simple_extent_dims(fspace.get(), &n, nullptr);
  if (n > kMaxSamples)
    throw Error(file, channel.path,
                "declares " + std::to_string(n) + " samples, more than any memory holds");
  impl_->check_stored(ds.get(), n, channel.path);
  kernels::LargeVector<double> out(static_cast<std::size_t>(n));  // every element is read
  chunk = std::max<std::size_t>(chunk, 1);
  // Chunked hyperslab reads: HDF5 converts each block (int16, float32, ...) to double in a
  // conversion buffer of the block's size instead of the whole dataset's.
  for (hsize_t start = 0; start < n; start += chunk) {
    hsize_t count = std::min<hsize_t>(chunk, n - start);
    check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr), file,
          channel.path, "H5Sselect_hyperslab");
    Handle mspace = check(H5Screate_simple(1, &count, nullptr), H5Sclose, file, channel.path,
                          "H5Screate_simple");
    check(H5Dread(ds.get(), H5T_NATIVE_DOUBLE, mspace.get(), fspace.get(), H5P_DEFAULT,
                  out.data() + start),
          file, channel.path, "H5Dread (truncated or corrupt data)");
  }
  impl_->check_whole(channel.path);
  to_physical(channel, out);
  return out;
}

namespace {

bool is_hdf5_recording(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return false;
  h5::quiet_library();
  return H5Fis_hdf5(path.c_str()) > 0;
}

std::unique_ptr<RecordingSource> open_hdf5(const std::string& path, const InputOptions& options) {
  return std::make_unique<Hdf5Source>(path, options);
}

// A channel in Hz needs --nominal-frequency, a usage error before any work. The reader reads it
// with any F; the channels that took one are the ones in Hz. Any other problem of the file is
// reported when it is read.
void check_hdf5_options(const std::string& path, const InputOptions& options) {
  if (options.nominal_frequency_hz > 0) return;
  InputOptions probe = options;
  probe.nominal_frequency_hz = 1.0;
  std::unique_ptr<Hdf5Source> source;
  try {
    source = std::make_unique<Hdf5Source>(path, probe);
  } catch (const std::exception&) {
    return;
  }
  for (const ChannelInfo& ch : source->describe().channels)
    if (ch.nominal_hz > 0) throw UsageError(path, ch.path, needs_nominal_frequency("Hz"));
}

}  // namespace

SourceFormat hdf5_format() {
  return {"HDF5", is_hdf5_recording, check_hdf5_options, open_hdf5};
}

}  // namespace allanlot::io
