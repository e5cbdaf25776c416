// Test-only helpers that fabricate HDF5 recordings (good and bad) with the C API, and small
// process/file utilities for end-to-end tests.
#pragma once

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <spawn.h>
#include <stdexcept>
#include <string>
#include <sys/wait.h>
#include <vector>

extern char** environ;  // POSIX: the environment handed to spawned processes

namespace allanlot::test {

/// The samples a reader returned (io::RecordingReader::read), as a plain vector to compare.
template <class Samples>
std::vector<double> as_vector(const Samples& x) {
  return std::vector<double>(x.begin(), x.end());
}

/// A fresh, empty directory under the build tree's test tmp dir.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto p = std::filesystem::path(ALLANLOT_TEST_TMP) / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

/// Minimal RAII HDF5 file for fixtures.
class H5Fixture {
public:
  explicit H5Fixture(const std::filesystem::path& path) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file_ < 0) throw std::runtime_error("fixture: cannot create " + path.string());
  }
  ~H5Fixture() {
    if (file_ >= 0) H5Fclose(file_);
  }
  H5Fixture(const H5Fixture&) = delete;
  H5Fixture& operator=(const H5Fixture&) = delete;

  /// Creates groups along `path` (like mkdir -p).
  void group(const std::string& path) {
    std::string so_far;
    std::size_t pos = 1;
    while (pos <= path.size()) {
      const auto next = path.find('/', pos);
      so_far = path.substr(0, next);
      if (H5Lexists(file_, so_far.c_str(), H5P_DEFAULT) <= 0) {
        const hid_t g = H5Gcreate2(file_, so_far.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        H5Gclose(g);
      }
      if (next == std::string::npos) break;
      pos = next + 1;
    }
  }

  /// 1-D dataset of `mem_type` values converted from doubles by HDF5 (file_type as stored).
  void dataset(const std::string& path, const std::vector<double>& v, hid_t file_type,
               std::vector<hsize_t> dims = {}) {
    parent(path);
    if (dims.empty()) dims = {v.size()};
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t ds =
        H5Dcreate2(file_, path.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (!v.empty()) H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(ds);
    H5Sclose(space);
  }

  void string_dataset(const std::string& path, const std::vector<std::string>& v) {
    parent(path);
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    std::vector<const char*> p;
    for (const auto& s : v)
      p.push_back(s.c_str());
    const hsize_t n = v.size();
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t ds =
        H5Dcreate2(file_, path.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data());
    H5Dclose(ds);
    H5Sclose(space);
    H5Tclose(t);
  }

  void attr(const std::string& obj, const std::string& name, double value) {
    const hid_t o = H5Oopen(file_, obj.c_str(), H5P_DEFAULT);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(o, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, &value);
    H5Aclose(a);
    H5Sclose(space);
    H5Oclose(o);
  }

  void attr(const std::string& obj, const std::string& name, const std::string& value) {
    const hid_t o = H5Oopen(file_, obj.c_str(), H5P_DEFAULT);
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, value.size() + 1);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(o, name.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, t, value.c_str());
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(t);
    H5Oclose(o);
  }

  /// Integer attribute (stored int64): docs/formats.md's numbers may be stored as integers.
  void attr_int(const std::string& obj, const std::string& name, std::int64_t value) {
    const hid_t o = H5Oopen(file_, obj.c_str(), H5P_DEFAULT);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(o, name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_INT64, &value);
    H5Aclose(a);
    H5Sclose(space);
    H5Oclose(o);
  }

  /// 1-D array attribute of doubles (where a single number is expected: a wrong shape).
  void attr_array(const std::string& obj, const std::string& name, const std::vector<double>& v) {
    const hid_t o = H5Oopen(file_, obj.c_str(), H5P_DEFAULT);
    const hsize_t n = v.size();
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t a = H5Acreate2(o, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, v.data());
    H5Aclose(a);
    H5Sclose(space);
    H5Oclose(o);
  }

  /// 1-D compound dataset {double t; double y} of `n` zero records.
  void compound_dataset(const std::string& path, std::size_t n) {
    parent(path);
    struct Rec {
      double t, y;
    };
    const hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(Rec));
    H5Tinsert(t, "t", offsetof(Rec, t), H5T_NATIVE_DOUBLE);
    H5Tinsert(t, "y", offsetof(Rec, y), H5T_NATIVE_DOUBLE);
    const std::vector<Rec> v(n, Rec{0.0, 0.0});
    const hsize_t dim = n;
    const hid_t space = H5Screate_simple(1, &dim, nullptr);
    const hid_t ds =
        H5Dcreate2(file_, path.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(ds);
    H5Sclose(space);
    H5Tclose(t);
  }

  /// The file's identifier, for fixtures the helpers above do not cover.
  hid_t id() const { return file_; }

private:
  void parent(const std::string& path) {
    const auto slash = path.find_last_of('/');
    if (slash > 0) group(path.substr(0, slash));
  }
  hid_t file_ = -1;
};

/// Runs a shell command, returns its exit status and (optionally) its combined output.
inline int run_command(const std::string& cmd, std::string* output = nullptr) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  std::string text;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p))
    text += buf;
  const int status = pclose(p);
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Starts `args[0]` with `args` (stdout and stderr to /dev/null) without waiting; returns its
/// pid, or -1 when it could not be started. For tests that kill or race processes.
inline pid_t spawn(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args)
    argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

/// n samples of white noise of sd 0.01 from `seed` (a channel's samples for tests that need
/// any valid recording).
inline std::vector<double> noise(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(n);
  for (auto& x : v)
    x = 0.01 * g(rng);
  return v;
}

inline std::string binary() {
  return ALLANLOT_BINARY;
}

/// Bytes of a file, to prove inputs are never modified.
inline std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Every regular file below `dir` with its bytes, to prove a command changed none of them.
inline std::map<std::filesystem::path, std::string> snapshot(const std::filesystem::path& dir) {
  std::map<std::filesystem::path, std::string> m;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) m[e.path()] = file_bytes(e.path());
  return m;
}

}  // namespace allanlot::test
