#include "io/diagnosis.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/paths.hpp"
#include "io/schema_h5.hpp"
#include "io/seal.hpp"

#include <algorithm>

namespace allanlot::io {

using h5::check;
using h5::Handle;

namespace schema {

void write_diagnosis_group(hid_t channel_group, const DiagnosisRecord& r, const std::string& file) {
  const std::string object = r.channel + "/" + kDiagnosis;
  Handle g = create_group(channel_group, kDiagnosis, file, object);
  write_fields(g.get(), r, diagnosis_fields(), file, object);
  for (const auto& [k, v] : r.number_attributes)
    h5::write_attribute(g.get(), k, v, file, object);
  for (const auto& [k, v] : r.string_attributes)
    h5::write_attribute(g.get(), k, v, file, object);
}

namespace {

std::vector<std::string> attribute_names(hid_t obj, const std::string& file,
                                         const std::string& object) {
  H5O_info_t info{};
  check(H5Oget_info2(obj, &info, H5O_INFO_NUM_ATTRS), file, object, "H5Oget_info2");
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const ssize_t len =
        H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) throw Error(file, object, "H5Aget_name_by_idx failed");
    std::string name(static_cast<std::size_t>(len), '\0');
    H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    names.push_back(std::move(name));
  }
  return names;
}

}  // namespace

// The free attributes in name order: strings to string_attributes, single numbers to
// number_attributes; anything else is not something diagnose writes, and an error.
DiagnosisRecord read_diagnosis_group(hid_t g, const std::string& channel, const std::string& file) {
  DiagnosisRecord r;
  r.channel = channel;
  const std::string object = channel + "/" + kDiagnosis;
  read_fields(g, r, diagnosis_fields(), Depth::Full, file, object);
  for (const std::string& name : attribute_names(g, file, object)) {
    Handle a = check(H5Aopen(g, name.c_str(), H5P_DEFAULT), H5Aclose, file, object, "H5Aopen");
    Handle type = check(H5Aget_type(a.get()), H5Tclose, file, object, "H5Aget_type");
    if (H5Tget_class(type.get()) == H5T_STRING) {
      std::string v;
      h5::read_attribute(g, name, v, file, object);
      r.string_attributes.emplace_back(name, std::move(v));
    } else {
      double v = 0;
      h5::read_attribute(g, name, v, file, object);
      r.number_attributes.emplace_back(name, v);
    }
  }
  return r;
}

}  // namespace schema

void write_diagnosis(const std::filesystem::path& out, const std::filesystem::path& input,
                     const DiagnosisRecord& r) {
  h5::quiet_library();
  const std::string file = out.string();
  const std::filesystem::path inputs[] = {input};
  if (const auto in = replaced_input(out, inputs))
    throw Error(file, "", replaced_input_message(out, *in));
  std::error_code ec;
  // analyze -o writes a folder of results files: naming the folder is a usage slip, which must
  // not surface as a stream error attributed to the input.
  if (std::filesystem::is_directory(out, ec))
    throw Error(file, "",
                "is a folder; -o takes an HDF5 file, new or a results file (analyze -o DIR writes "
                "DIR/<recording>.allan.h5)");
  const bool existing = std::filesystem::exists(out, ec);
  AtomicFile atomic(out);
  {
    // Both a new file and an existing results file are edited in memory and written by one
    // checked write(2), sealed: on a full disk, a clean error instead of HDF5 crashing at exit,
    // and the existing file stays as it was until the rename.
    Handle f = existing ? h5::open_memory_copy(out, file) : h5::create_memory_file(file);
    {
      const std::string object = r.channel + "/diagnosis";
      H5O_info_t oi{};
      if (H5Lexists(f.get(), r.channel.c_str(), H5P_DEFAULT) > 0 &&
          (H5Oget_info_by_name2(f.get(), r.channel.c_str(), &oi, H5O_INFO_BASIC, H5P_DEFAULT) < 0 ||
           oi.type != H5O_TYPE_GROUP))
        throw Error(file, r.channel,
                    "is not a group (a recording?); -o must be a new file or a results file");
      Handle ch = h5::ensure_groups(f.get(), r.channel, file);
      if (H5Lexists(ch.get(), "diagnosis", H5P_DEFAULT) > 0)
        h5::check(H5Ldelete(ch.get(), "diagnosis", H5P_DEFAULT), file, object, "H5Ldelete");
      schema::write_diagnosis_group(ch.get(), r, file);
    }
    h5::write_memory_file(f, atomic, file);
  }
  atomic.commit();
}

namespace {

// Every group named diagnosis/, in path order (H5Ovisit by name).
herr_t collect_diagnosis(hid_t, const char* name, const H5O_info_t* info, void* data) {
  if (info->type != H5O_TYPE_GROUP || !name) return 0;
  const std::string path = std::string("/") + name;
  const std::string suffix = std::string("/") + schema::kDiagnosis;
  if (path.ends_with(suffix)) static_cast<std::vector<std::string>*>(data)->push_back(path);
  return 0;
}

}  // namespace

std::vector<DiagnosisRecord> read_diagnoses(const std::filesystem::path& path) {
  const std::string file = path.string();
  Handle f = h5::open_sealed(path, "file");
  std::vector<std::string> groups;
  if (H5Ovisit2(f.get(), H5_INDEX_NAME, H5_ITER_INC, collect_diagnosis, &groups, H5O_INFO_BASIC) <
      0)
    throw Error(file, "", "cannot walk the file");
  std::vector<DiagnosisRecord> out;
  for (const std::string& p : groups) {
    Handle g = check(H5Gopen2(f.get(), p.c_str(), H5P_DEFAULT), H5Gclose, file, p, "H5Gopen2");
    const std::string channel = p.substr(0, p.size() - std::string("/diagnosis").size());
    out.push_back(schema::read_diagnosis_group(g.get(), channel.empty() ? "/" : channel, file));
  }
  return out;
}

}  // namespace allanlot::io
