// Complete-or-absent output files: everything allanlot writes goes to a temporary name in
// the destination's directory and is renamed into place only when complete and synced, so a
// crash, a kill or a full disk never leaves a half-written file under the final name.
#pragma once

#include <filesystem>
#include <string>

namespace allanlot::io {

class AtomicFile {
public:
  /// Chooses a unique temporary path beside `final_path` (same directory, so the rename is
  /// atomic). Nothing is created yet.
  explicit AtomicFile(std::filesystem::path final_path);
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::filesystem::path& temp_path() const { return temp_; }
  const std::filesystem::path& final_path() const { return final_; }
  /// fsyncs the temporary file, renames it to the final path and fsyncs the directory.
  /// Throws io::Error naming the final path on failure (the temporary is then removed).
  void commit();

private:
  std::filesystem::path final_, temp_;
  bool committed_ = false;
};

/// Writes `text` to `path` atomically (CSV summaries, model files).
void write_text_atomic(const std::filesystem::path& path, const std::string& text);

}  // namespace allanlot::io
