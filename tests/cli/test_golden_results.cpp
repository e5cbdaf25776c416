// Behaviour unchanged by a restructuring: a small simulated unit goes through `simulate` and
// `analyze` with every default, and every dataset and attribute of the results file, and every
// row of the lot summary, must equal the digest written by the code before the restructuring
// (tests/data/golden/). What may differ is only what records the run rather than the analysis:
// the creation time, the version and git revision, the command line, the paths, the input's
// modification time and the schema version.
//
// The digest is text, one line per object, so a failure names the dataset that moved. Numbers
// are hashed from their stored bytes (bit for bit); strings by their characters, whatever their
// storage (variable or fixed length). To accept an intended change of results, run this test
// with ALLANLOT_WRITE_GOLDEN=1 and commit the new digest with the reason.
#include "support/h5_fixture.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

namespace allanlot {
namespace {

namespace fs = std::filesystem;
using test::binary;
using test::run_command;

const fs::path kGoldenDir = fs::path(ALLANLOT_REFERENCE_DIR) / "golden";

// Attributes that describe the run, not the analysis.
const std::set<std::string> kRunAttributes = {"created_utc",   "tool_version", "git_sha",
                                              "command_line",  "source_file",  "input_mtime_ns",
                                              "schema_version"};

std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = 1469598103934665603ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i)
    h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

std::string hex(std::uint64_t h) {
  std::ostringstream s;
  s << std::hex << h;
  return s.str();
}

// "string" or "<class><bytes>" (f8, i8, u1, ...) and the element count of a dataspace.
struct Shape {
  std::string kind;
  std::size_t count = 0;
};

Shape shape_of(hid_t type, hid_t space) {
  Shape s;
  const auto n = H5Sget_simple_extent_npoints(space);
  s.count = n < 0 ? 0 : static_cast<std::size_t>(n);
  const H5T_class_t c = H5Tget_class(type);
  if (c == H5T_STRING) {
    s.kind = "string";
  } else {
    const bool is_signed = c == H5T_INTEGER && H5Tget_sign(type) == H5T_SGN_2;
    s.kind = (c == H5T_FLOAT     ? "f"
              : is_signed        ? "i"
              : c == H5T_INTEGER ? "u"
                                 : "other") +
             std::to_string(H5Tget_size(type));
  }
  return s;
}

// Reads the values of a dataset (is_attr false) or attribute into a hash. Strings are read as
// variable-length C strings in memory whatever their storage, numbers in their native type.
std::uint64_t hash_values(hid_t obj, bool is_attr, hid_t type, const Shape& s) {
  std::uint64_t h = fnv1a(s.kind.data(), s.kind.size());
  if (s.kind == "string") {
    const hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5T_CSET_UTF8);
    std::vector<char*> v(s.count, nullptr);
    const herr_t rc = is_attr ? H5Aread(obj, mem, v.data())
                              : H5Dread(obj, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    EXPECT_GE(rc, 0);
    for (char* p : v) {
      const std::string str = p ? p : "";
      h = fnv1a(str.c_str(), str.size() + 1, h);
      H5free_memory(p);
    }
    H5Tclose(mem);
    return h;
  }
  const hid_t mem = H5Tget_native_type(type, H5T_DIR_ASCEND);
  std::vector<unsigned char> bytes(s.count * H5Tget_size(mem));
  const herr_t rc = is_attr ? H5Aread(obj, mem, bytes.data())
                            : H5Dread(obj, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data());
  EXPECT_GE(rc, 0);
  H5Tclose(mem);
  return fnv1a(bytes.data(), bytes.size(), h);
}

struct Walk {
  std::vector<std::string> lines;
};

herr_t visit_attribute(hid_t obj, const char* name, const H5A_info_t*, void* data) {
  auto& w = *static_cast<std::vector<std::string>*>(data);
  if (kRunAttributes.count(name)) return 0;
  const hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  const hid_t type = H5Aget_type(a);
  const hid_t space = H5Aget_space(a);
  const Shape s = shape_of(type, space);
  w.push_back("@" + std::string(name) + " " + s.kind + "[" + std::to_string(s.count) + "] " +
              hex(hash_values(a, true, type, s)));
  H5Sclose(space);
  H5Tclose(type);
  H5Aclose(a);
  return 0;
}

// One line per attribute of the object at `path`, in name order.
void add_attributes(hid_t file, const std::string& path, std::vector<std::string>& lines) {
  const hid_t obj = H5Oopen(file, path.c_str(), H5P_DEFAULT);
  std::vector<std::string> attrs;
  H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, nullptr, visit_attribute, &attrs);
  H5Oclose(obj);
  for (const auto& a : attrs)
    lines.push_back(path + a);
}

herr_t visit_object(hid_t file, const char* name, const H5O_info_t* info, void* data) {
  auto& w = *static_cast<Walk*>(data);
  const std::string path = std::string("/") + (std::string(name) == "." ? "" : name);
  if (info->type == H5O_TYPE_DATASET) {
    const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
    const hid_t type = H5Dget_type(ds);
    const hid_t space = H5Dget_space(ds);
    const Shape s = shape_of(type, space);
    w.lines.push_back(path + " " + s.kind + "[" + std::to_string(s.count) + "] " +
                      hex(hash_values(ds, false, type, s)));
    H5Sclose(space);
    H5Tclose(type);
    H5Dclose(ds);
  } else {
    w.lines.push_back(path + " group");
  }
  add_attributes(file, path, w.lines);
  return 0;
}

// The digest of a results file: every object in name order with its attributes.
std::vector<std::string> digest_h5(const fs::path& file) {
  Walk w;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  if (f < 0) return {};
  H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_INC, visit_object, &w, H5O_INFO_BASIC);
  H5Fclose(f);
  return w.lines;
}

// A CSV summary row by row, with the source_file column cut to the file name (the path is the
// test's temporary folder).
std::vector<std::string> digest_csv(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    const auto at = line.find("/golden_unit/");
    if (at != std::string::npos) {
      const auto start = line.rfind(',', at);
      line.erase(start + 1, at + std::string("/golden_unit/").size() - start - 1);
    }
    lines.push_back(file.filename().string() + ": " + line);
  }
  return lines;
}

std::vector<std::string> read_lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> v;
  for (std::string l; std::getline(in, l);)
    v.push_back(l);
  return v;
}

TEST(GoldenResults, SameResultsAsBeforeTheRestructuring) {
  const auto dir = test::fresh_dir("golden_unit");
  std::string out;
  // The paper's six-channel unit (the embedded default model), 2 minutes at 1 kHz.
  ASSERT_EQ(run_command(binary() + " simulate --duration 120 --seed 11 --threads 2 -q -o " +
                            (dir / "unit_g.h5").string(),
                        &out),
            0)
      << out;
  ASSERT_EQ(run_command(binary() + " analyze --threads 2 -q -o " + (dir / "out").string() + " " +
                            (dir / "unit_g.h5").string(),
                        &out),
            0)
      << out;
  std::vector<std::string> digest;
  const std::string rec = test::file_bytes(dir / "unit_g.h5");
  digest.push_back("recording unit_g.h5 " + hex(fnv1a(rec.data(), rec.size())));
  for (auto& l : digest_h5(dir / "out" / "unit_g.allan.h5"))
    digest.push_back("unit_g.allan.h5:" + l);
  for (const char* csv : {"lot_summary.csv", "lot_statistics.csv"})
    for (auto& l : digest_csv(dir / "out" / csv))
      digest.push_back(l);

  const fs::path golden = kGoldenDir / "unit_g.digest";
  if (std::getenv("ALLANLOT_WRITE_GOLDEN")) {
    fs::create_directories(kGoldenDir);
    std::ofstream o(golden);
    for (const auto& l : digest)
      o << l << '\n';
    GTEST_SKIP() << "wrote " << golden;
  }
  const auto want = read_lines(golden);
  ASSERT_FALSE(want.empty()) << "no golden digest at " << golden;
  EXPECT_EQ(digest.size(), want.size());
  for (std::size_t i = 0; i < std::min(digest.size(), want.size()); ++i)
    EXPECT_EQ(digest[i], want[i]) << "line " << i + 1 << " of " << golden;
}

}  // namespace
}  // namespace allanlot
