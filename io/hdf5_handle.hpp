// Small RAII wrappers over HDF5 C API identifiers. Private to io/: the only header that
// includes hdf5.h, and only io/*.cpp include it.
#pragma once

#include "io/error.hpp"

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace allanlot::io {
class AtomicFile;
}  // namespace allanlot::io

namespace allanlot::io::h5 {

/// Silences HDF5's own error-stack printing: allanlot reports every failure itself, with the
/// file, the dataset and the reason (io::Error), and never lets the library write to stderr.
void quiet_library();

/// Owns one hid_t and closes it with the matching H5*close on destruction. Move-only.
class Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), close_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      close_ = o.close_;
    }
    return *this;
  }
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Closes now and reports failure (a close can be where buffered data are written).
  herr_t close() {
    herr_t rc = 0;
    if (id_ >= 0 && close_) rc = close_(id_);
    id_ = H5I_INVALID_HID;
    return rc;
  }

private:
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = H5I_INVALID_HID;
  }
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

/// Checks an identifier returned by the C API: throws io::Error(file, object, what) when < 0.
Handle check(hid_t id, Handle::Closer closer, const std::string& file, const std::string& object,
             const std::string& what);
/// Checks a status return.
void check(herr_t rc, const std::string& file, const std::string& object, const std::string& what);

// Attribute helpers. Readers return false when the attribute is absent and throw io::Error
// (naming file, object and attribute) when it exists with an unusable type or shape.
bool has_attribute(hid_t obj, const std::string& name);
bool read_attribute(hid_t obj, const std::string& name, double& out, const std::string& file,
                    const std::string& object);
bool read_attribute(hid_t obj, const std::string& name, std::string& out, const std::string& file,
                    const std::string& object);
bool read_attribute(hid_t obj, const std::string& name, std::int64_t& out, const std::string& file,
                    const std::string& object);
bool read_attribute(hid_t obj, const std::string& name, std::vector<double>& out,
                    const std::string& file, const std::string& object);
void write_attribute(hid_t obj, const std::string& name, const std::string& value,
                     const std::string& file, const std::string& object);
void write_attribute(hid_t obj, const std::string& name, double value, const std::string& file,
                     const std::string& object);
void write_attribute(hid_t obj, const std::string& name, std::int64_t value,
                     const std::string& file, const std::string& object);
void write_attribute(hid_t obj, const std::string& name, const std::vector<double>& value,
                     const std::string& file, const std::string& object);

/// Creation property lists for groups and datasets with object time tracking off: HDF5 stores
/// modification times by default, which would make two runs with the same inputs write
/// different bytes (docs/cli.md "Command: simulate": same seed and model, the same bytes).
Handle group_create_plist(const std::string& file, const std::string& object);
Handle dataset_create_plist(const std::string& file, const std::string& object);

/// A new HDF5 file held in memory (core driver, no backing store): results and lot summaries
/// are built here and reach the disk only through write_memory_file. Why: when a write fails
/// inside HDF5 (a full disk: ENOSPC in H5Dclose or H5Fclose), HDF5 1.10 leaves the file
/// half-closed and dereferences it at library shutdown, a segfault at exit after the error
/// was reported (found by tests/cli/test_faults.cpp on a full tmpfs). Outside HDF5 the same
/// failure is one checked write(2). `file` names the destination in messages.
/// Whether the file carries the seal of io/seal.hpp (results and summaries do; recordings, which
/// other programs write too, do not).
enum class Sealed { Yes, No };
Handle create_memory_file(const std::string& file, Sealed sealed = Sealed::Yes);

/// A sealed file allanlot wrote, checked (io/seal.hpp) and read whole into memory for editing
/// (core driver, no backing store): the edits reach the disk only through write_memory_file, for
/// the reason given above. io::Error naming `file` when it is damaged or not HDF5.
Handle open_memory_copy(const std::filesystem::path& path, const std::string& file);

/// A variable-length UTF-8 string type, as every string allanlot writes is stored.
Handle utf8_string_type(const std::string& file, const std::string& object);

/// Opens a file allanlot wrote (results, lot summary, diagnosis) read-only, after its seal was
/// checked (io/seal.hpp); io::Error naming the file when it is damaged or not HDF5 (`kind`
/// says what was expected: "results file", ...).
Handle open_sealed(const std::filesystem::path& path, const std::string& kind);

/// Writes the complete image of the in-memory file `f` to the temporary file of `out` with
/// write(2), and closes `f`. Throws io::Error naming `file` with the system's reason (e.g.
/// "write: No space left on device"); `out` then removes its incomplete temporary.
void write_memory_file(Handle& f, const AtomicFile& out, const std::string& file,
                       Sealed sealed = Sealed::Yes);

/// Creates every missing group along `path` ("/a/b/c") under `file_id` and returns the last.
Handle ensure_groups(hid_t file_id, const std::string& path, const std::string& file);

/// Writes a 1-D dataset of doubles / int64 / strings / uint8.
void write_dataset(hid_t loc, const std::string& name, const std::vector<double>& v,
                   const std::string& file, const std::string& object);
void write_dataset(hid_t loc, const std::string& name, const std::vector<std::int64_t>& v,
                   const std::string& file, const std::string& object);
void write_dataset(hid_t loc, const std::string& name, const std::vector<int>& v,
                   const std::string& file, const std::string& object);
void write_dataset(hid_t loc, const std::string& name, const std::vector<std::string>& v,
                   const std::string& file, const std::string& object);
void write_dataset(hid_t loc, const std::string& name, const std::vector<std::uint8_t>& v,
                   const std::string& file, const std::string& object);

/// Reads a whole 1-D dataset converted to the requested element type.
std::vector<double> read_doubles(hid_t loc, const std::string& name, const std::string& file,
                                 const std::string& object);
std::vector<std::int64_t> read_int64s(hid_t loc, const std::string& name, const std::string& file,
                                      const std::string& object);
std::vector<std::string> read_strings(hid_t loc, const std::string& name, const std::string& file,
                                      const std::string& object);

}  // namespace allanlot::io::h5
