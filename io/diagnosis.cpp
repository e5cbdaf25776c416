#include "io/diagnosis.hpp"

#include "io/atomic_file.hpp"
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"

namespace allanlot::io {

using h5::check;
using h5::Handle;

void write_diagnosis(const std::filesystem::path& out, const std::filesystem::path& input,
                     const DiagnosisRecord& r) {
  h5::quiet_library();
  const std::string file = out.string();
  std::error_code ec;
  if (std::filesystem::exists(out, ec) && std::filesystem::equivalent(out, input, ec))
    throw Error(file, "", "is the input recording; the input is never written (choose another -o)");
  const bool existing = std::filesystem::exists(out, ec);
  AtomicFile atomic(out);
  {
    Handle f;
    if (existing) {
      // Copy, then edit the copy: the original stays intact until the rename.
      std::filesystem::copy_file(out, atomic.temp_path(), ec);
      if (ec) throw Error(file, "", "cannot copy to a temporary file: " + ec.message());
      f = check(H5Fopen(atomic.temp_path().c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose, file, "",
                "H5Fopen (an existing -o must be an HDF5 file)");
    } else {
      f = check(H5Fcreate(atomic.temp_path().c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT),
                H5Fclose, file, "", "H5Fcreate (is the directory writable?)");
    }
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
      Handle gcpl = h5::group_create_plist(file, object);
      Handle g = check(H5Gcreate2(ch.get(), "diagnosis", H5P_DEFAULT, gcpl.get(), H5P_DEFAULT),
                       H5Gclose, file, object, "H5Gcreate2");
      const auto put = [&](const char* name, const auto& v) {
        h5::write_dataset(g.get(), name, v, file, object);
      };
      put("m", r.m);
      put("tau", r.tau);
      put("avar_measured", r.avar_measured);
      put("edf", r.edf);
      put("avar_model_before", r.avar_model_before);
      put("avar_model_after", r.avar_model_after);
      put("mc_before_lo", r.mc_before_lo);
      put("mc_before_hi", r.mc_before_hi);
      put("mc_after_lo", r.mc_after_lo);
      put("mc_after_hi", r.mc_after_hi);
      put("z_before", r.z_before);
      put("z_after", r.z_after);
      put("significant_before", r.significant_before);
      put("significant_after", r.significant_after);
      put("effect", r.effect);
      put("parameters", r.parameters_json);
      put("gap_iteration_before", r.gap_before);
      put("gap_iteration_after", r.gap_after);
      put("delta_ic", r.delta_ic);
      for (const auto& [k, v] : r.number_attributes)
        h5::write_attribute(g.get(), k, v, file, object);
      for (const auto& [k, v] : r.string_attributes)
        h5::write_attribute(g.get(), k, v, file, object);
    }
    if (f.close() < 0) throw Error(file, "", "H5Fclose failed while flushing (disk full?)");
  }
  atomic.commit();
}

}  // namespace allanlot::io
