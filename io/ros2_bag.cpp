#include "io/ros2_bag.hpp"

#include "io/cdr_imu.hpp"
#include "io/error.hpp"
#include "io/imu_topics.hpp"
#include "io/mapped_file.hpp"
#include "io/mcap.hpp"
#include "io/utf8.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <map>

namespace allanlot::io {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kSqliteMagic("SQLite format 3\0", 16);

// One statement, finalized on every path.
class Statement {
public:
  Statement(sqlite3* db, const char* sql, const std::string& file) {
    if (sqlite3_prepare_v2(db, sql, -1, &st_, nullptr) != SQLITE_OK)
      throw Error(file, "", std::string("not a rosbag2 sqlite3 file (") + sqlite3_errmsg(db) + ")");
  }
  ~Statement() { sqlite3_finalize(st_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  sqlite3_stmt* get() const { return st_; }

private:
  sqlite3_stmt* st_ = nullptr;
};

std::string text(sqlite3_stmt* st, int col) {
  const auto* p = sqlite3_column_text(st, col);
  return p ? reinterpret_cast<const char*>(p) : "";
}

// Reads one .db3 file, opened read-only and immutable (no journal or lock is written beside
// an input).
void read_db3(const std::string& file, ImuTopics& topics) {
  sqlite3* db = nullptr;
  const std::string uri = "file:" + fs::absolute(file).string() + "?immutable=1";
  const int rc = sqlite3_open_v2(uri.c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr);
  const std::unique_ptr<sqlite3, int (*)(sqlite3*)> owner(db, sqlite3_close);
  if (rc != SQLITE_OK)
    throw Error(file, "", "cannot open as sqlite3: " + std::string(sqlite3_errstr(rc)));
  std::map<std::int64_t, std::pair<std::string, int>> by_id;  // topic id: name, index
  {
    const Statement st(db, "SELECT id, name, type, serialization_format FROM topics", file);
    while (sqlite3_step(st.get()) == SQLITE_ROW) {
      const std::string name = valid_utf8(text(st.get(), 1)), type = text(st.get(), 2);
      const std::string format = valid_utf8(text(st.get(), 3));
      if (type == kRos2ImuType && format != "cdr")
        throw Error(file, name, "Imu messages serialized as '" + format + "' (read: cdr)");
      by_id[sqlite3_column_int64(st.get(), 0)] = {name, topics.add_topic(name, type)};
    }
  }
  const Statement st(db, "SELECT topic_id, timestamp, data FROM messages ORDER BY id", file);
  int step = 0;
  std::int64_t row = 0;
  while ((step = sqlite3_step(st.get())) == SQLITE_ROW) {
    ++row;
    const auto t = by_id.find(sqlite3_column_int64(st.get(), 0));
    if (t == by_id.end() || t->second.second < 0) continue;
    ImuMessage m;
    m.receive_ns = sqlite3_column_int64(st.get(), 1);
    const auto* data = static_cast<const unsigned char*>(sqlite3_column_blob(st.get(), 2));
    const auto n = static_cast<std::size_t>(sqlite3_column_bytes(st.get(), 2));
    if (const std::string why = parse_cdr_imu({data, n}, m); !why.empty())
      throw Error(file, t->second.first, "message " + std::to_string(row) + ": " + why);
    topics.add(t->second.second, m);
  }
  if (step != SQLITE_DONE)
    throw Error(file, "",
                std::string("reading its messages: ") + sqlite3_errmsg(db) +
                    " (corrupt or truncated?)");
}

// The split number of a storage file, `bag_12.db3` -> 12, so that 10 comes after 9.
long split_number(const fs::path& p) {
  const std::string stem = p.stem().string();
  const auto u = stem.find_last_of('_');
  try {
    return u == std::string::npos ? 0 : std::stol(stem.substr(u + 1));
  } catch (const std::exception&) {
    return 0;
  }
}

void read_folder(const std::string& dir, ImuTopics& topics) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".db3" || ext == ".mcap")) files.push_back(e.path());
  }
  if (files.empty()) throw Error(dir, "", "a ROS 2 bag folder without .db3 or .mcap files");
  std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
    return std::make_pair(split_number(a), a.string()) <
           std::make_pair(split_number(b), b.string());
  });
  for (const fs::path& f : files) {
    if (f.extension() == ".db3") {
      read_db3(f.string(), topics);
    } else {
      const MappedFile map(f.string());
      read_mcap(map.bytes(), f.string(), topics);
    }
  }
}

bool recognises_ros2(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return fs::is_regular_file(fs::path(path) / "metadata.yaml", ec);
  return starts_with_bytes(path, kSqliteMagic);
}

std::unique_ptr<RecordingSource> open_ros2(const std::string& path, const InputOptions& options) {
  std::error_code ec;
  ImuTopics topics(path, "ROS 2 bag", options);
  if (fs::is_directory(path, ec))
    read_folder(path, topics);
  else
    read_db3(path, topics);
  return topics.finish();
}

}  // namespace

SourceFormat ros2_bag_format() {
  return {"ROS 2 bag", recognises_ros2, nullptr, open_ros2};
}

}  // namespace allanlot::io
