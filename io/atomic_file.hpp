// Complete-or-absent output files: everything allanlot writes goes to a temporary name in
// the destination's directory and is renamed into place only when complete and synced, so a
// crash, a kill or a full disk never leaves a half-written file under the final name.
#pragma once

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <string>

namespace allanlot::io {

class AtomicFile {
public:
  /// Creates the temporary file beside `final_path` (same directory, so the rename is atomic)
  /// with O_CREAT | O_EXCL | O_NOFOLLOW under a name that carries 64 random bits: nothing
  /// planted in the directory (a symbolic link, a file of another user) can redirect or
  /// pre-empt it. Throws io::Error naming the final path when it cannot be created.
  explicit AtomicFile(std::filesystem::path final_path);
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::filesystem::path& temp_path() const { return temp_; }
  const std::filesystem::path& final_path() const { return final_; }
  /// Appends `bytes` to the temporary file through the descriptor it was created with (never
  /// reopened by name). Throws io::Error naming the final path with the system's reason.
  void write(const char* bytes, std::size_t n) const;
  /// fsyncs the temporary file (once; commit() does it when not done yet). Throws io::Error
  /// naming the final path on failure.
  void sync();
  /// fsyncs and closes the temporary file, renames it to the final path (in the same
  /// directory) and fsyncs the directory. Throws io::Error naming the final path on failure
  /// (the temporary is then removed), also when the final path is a device, pipe or
  /// directory, which is never replaced.
  void commit();

private:
  std::filesystem::path final_, temp_;
  int fd_ = -1;
  bool synced_ = false, committed_ = false;
};

/// Commits files that belong together (lot_summary.csv, lot_statistics.csv, lot_summary.h5):
/// every temporary is synced before the first rename, so a failure of any write or sync
/// leaves every final file as it was; only a failing rename(2) between two renames could leave
/// them apart.
void commit_together(std::initializer_list<AtomicFile*> files);

/// An exclusive advisory lock (flock) on a directory, held until destruction. Two `analyze`
/// runs sharing an OUTDIR each rebuild the lot summary from the results files present; under
/// this lock the listing and the write of one run never interleave with the other's, so the
/// summary written last has seen every results file written before it. The directory itself
/// is locked, so no lock file is left in OUTDIR. Best effort: where the directory cannot be
/// opened or the file system has no flock (some network file systems), it locks nothing, as
/// runs did before.
class DirectoryLock {
public:
  explicit DirectoryLock(const std::filesystem::path& directory);
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;
  bool locked() const { return fd_ >= 0; }

private:
  int fd_ = -1;
};

/// This host's name as temporary file names carry it (letters, digits, '-'; others '_').
/// Temporary names are `.<name>.tmp.<host>.<pid>.<16 random hex digits>`.
std::string host_tag();

/// Writes `text` to the temporary file of `f` (not committed). Throws io::Error naming the
/// final path with the system's reason.
void write_text(const AtomicFile& f, const std::string& text);

/// Writes `text` to `path` atomically (model files, exports); a character device or a pipe
/// (`-o /dev/null`, `-o /dev/stdout`) is written through instead, and a named pipe without a
/// reader is an error, not a wait.
void write_text_atomic(const std::filesystem::path& path, const std::string& text);

}  // namespace allanlot::io
