#include "io/recording.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/isolation.hpp"
#include "io/line_reader.hpp"
#include "io/text_fields.hpp"
#include "io/text_recording.hpp"
#include "io/usage_error.hpp"
#include "io/utf8.hpp"
#include "io/virtual_dataset.hpp"
#include "kernels/model/units.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fnmatch.h>
#include <fstream>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <sys/stat.h>

namespace allanlot::io {

using h5::check;
using h5::Handle;

std::string sanitize_device_id(const std::string& id) {
  std::string out;
  out.reserve(id.size());
  for (std::size_t i = 0; i < id.size(); ++i) {
    bool letter = false;
    if (const std::size_t n = name_letter_length(id, i, letter); n > 0) {
      // Another script's letters: device ids in Cyrillic stay apart. Anything else one '_'.
      if (letter)
        out.append(id, i, n);
      else
        out.push_back('_');
      i += n - 1;
      continue;
    }
    const char c = id[i];
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-';
    out.push_back(ok ? c : '_');
  }
  if (out.empty()) out.push_back('_');  // not `out = "_"`: GCC 12 bug 105329 (-Wrestrict)
  if (out[0] == '.') out[0] = '_';      // never ".", "..", or a hidden file
  return out;
}

bool channel_glob_matches(const std::string& glob, const std::string& path) {
  if (glob.empty()) return true;
  const std::string name = path.substr(path.find_last_of('/') + 1);
  return fnmatch(glob.c_str(), path.c_str(), 0) == 0 || fnmatch(glob.c_str(), name.c_str(), 0) == 0;
}

namespace {

std::string needs_nominal_frequency(const std::string& units) {
  return "units '" + units +
         "' are a frequency: give --nominal-frequency F (Hz) to read it as fractional frequency "
         "(f - F) / F";
}

// The channel's unit in the one vocabulary (kernels/model/units.hpp): "dps" is deg/s, "m/s2"
// m/s^2; a clock's phase in ns or frequency in ppb is scaled to s or 1, its frequency in Hz
// made fractional with --nominal-frequency (a usage error without it). Units outside the
// vocabulary stay as written (analyze warns about them).
void in_canonical_units(ChannelInfo& ch, const InputOptions& options, const std::string& file) {
  const auto known = kernels::units::parse_channel_units(ch.units);
  if (!known) return;
  if (known->per_nominal) {
    if (!(options.nominal_frequency_hz > 0))
      throw UsageError(file, ch.path, needs_nominal_frequency(ch.units));
    ch.nominal_hz = options.nominal_frequency_hz;
  }
  ch.units = known->canonical;
  ch.scale *= known->scale;
  ch.offset *= known->scale;
}

// Raw samples to the channel's canonical units: the file's scale and offset, the unit's factor,
// and a frequency in Hz made fractional.
void to_physical(const ChannelInfo& channel, std::span<double> samples) {
  if (channel.scale != 1.0 || channel.offset != 0.0)  // a clock's ns or ppb (units.hpp)
    for (double& v : samples)
      v = v * channel.scale + channel.offset;
  if (channel.nominal_hz > 0)
    for (double& v : samples)
      v = kernels::units::to_fractional_frequency(v, channel.nominal_hz);
}

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

// No NUL byte and few control characters in the first 4 KiB: text, not binary.
bool looks_like_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char buf[4096];
  in.read(buf, sizeof buf);
  const auto n = static_cast<std::size_t>(in.gcount());
  if (n == 0) return false;
  std::size_t control = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(buf[i]);
    if (c == 0) return false;
    if (c < 0x20 && c != '\n' && c != '\r' && c != '\t') ++control;
  }
  return control * 100 < n;
}

}  // namespace

bool is_text_recording(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".h5" || ext == ".hdf5") return false;
  return is_text_name(path) || is_gzip_file(path) || looks_like_text(path);
}

void check_input_options(const std::string& path, const InputOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return;
  h5::quiet_library();
  if (H5Fis_hdf5(path.c_str()) <= 0 && is_text_recording(path)) {
    check_text_options(path, options);
  } else if (H5Fis_hdf5(path.c_str()) > 0 && !(options.nominal_frequency_hz > 0)) {
    // A channel in Hz needs --nominal-frequency. The reader reads it with any F; the channels
    // that took one are the ones in Hz. Any other problem of the file is reported when it is
    // read.
    InputOptions probe = options;
    probe.nominal_frequency_hz = 1.0;
    std::optional<RecordingReader> reader;
    try {
      reader.emplace(path, probe);
    } catch (const std::exception&) {
      return;
    }
    for (const ChannelInfo& ch : reader->info().channels)
      if (ch.nominal_hz > 0) throw UsageError(path, ch.path, needs_nominal_frequency("Hz"));
  }
}

struct RecordingReader::Impl {
  std::string path;
  Handle file;
  std::optional<TextRecording> text;  // a text recording, parsed whole

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

// The channels of a text recording, all with the recording's rate and data type.
void describe_text(const TextRecording& text, RecordingInfo& info, const InputOptions& options,
                   const std::string& file) {
  info.device_id = text.device_id;
  info.facts = text.facts;
  info.notes = text.notes;
  for (const TextChannel& tc : text.channels) {
    ChannelInfo ch;
    ch.path = tc.path;
    ch.units = tc.units;
    ch.sample_rate_hz = text.sample_rate_hz;
    ch.data_type = text.data_type.value_or(kernels::DataType::Rate);
    ch.data_type_default = !text.data_type;
    ch.n_samples = static_cast<std::int64_t>(tc.samples.size());
    ch.storage_type = "text";
    ch.time_stamps = text.time_stamps;
    in_canonical_units(ch, options, file);
    const double rate = text.sample_rate_hz;
    if (!(rate >= kMinSampleRateHz && rate <= kMaxSampleRateHz)) {
      std::ostringstream msg;
      msg << "sample rate " << rate << " Hz is outside " << kMinSampleRateHz << " .. "
          << kMaxSampleRateHz << " Hz, where the statistics stay within double precision";
      info.problems.push_back({tc.path, msg.str()});
      continue;
    }
    info.channels.push_back(std::move(ch));
  }
}

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

RecordingReader::RecordingReader(const std::string& path, const InputOptions& options)
    : impl_(std::make_unique<Impl>()) {
  h5::quiet_library();
  impl_->path = path;
  info_.file = path;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(path, "", "no such file");
  if (std::filesystem::is_directory(path, ec)) throw Error(path, "", "is a directory");
  if (H5Fis_hdf5(path.c_str()) <= 0 && is_text_recording(path)) {
    impl_->text = read_text_recording(path, options);
    describe_text(*impl_->text, info_, options, path);
    return;
  }
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw Error(path, "", "not an HDF5 file (or truncated/corrupt)");
  // The metadata is read once in a child process first (io/isolation.hpp): hostile bytes that
  // crash the HDF5 library fail this input, not the process.
  if (!in_isolated_child()) run_isolated(path, [&] { RecordingReader probe(path, options); });
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

RecordingReader::~RecordingReader() = default;

kernels::LargeVector<double> RecordingReader::read(const ChannelInfo& channel,
                                                   std::size_t chunk) const {
  const std::string& file = impl_->path;
  if (impl_->text) {
    for (const TextChannel& tc : impl_->text->channels) {
      if (tc.path != channel.path) continue;
      kernels::LargeVector<double> out(tc.samples.begin(), tc.samples.end());
      to_physical(channel, out);
      return out;
    }
    throw Error(file, channel.path, "no such column");
  }
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
