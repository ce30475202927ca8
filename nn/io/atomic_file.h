// Files that appear complete or not at all: written under a temporary name beside the target, flushed
// to disk, then renamed over it (rename within one folder is atomic on POSIX file systems).
#pragma once

#include <string>
#include <string_view>

namespace romp::io {

class AtomicFile {
 public:
  // Creates the missing folders of `path`; the caller writes to temp_path() and then commits.
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Removes the temporary unless committed, so a failed write leaves the target as it was.
  ~AtomicFile();

  const std::string& path() const { return path_; }
  // "<path>.tmp-<pid>".
  const std::string& temp_path() const { return temp_path_; }
  bool committed() const { return committed_; }
  // Makes the temporary the target (see rename_durably).
  void commit();

 private:
  std::string path_, temp_path_;
  bool committed_ = false;
};

// Replaces (or creates) `path` with `bytes` through an AtomicFile.
void write_file_atomically(const std::string& path, std::string_view bytes);

// Flushes `from` to disk, renames it over `to` and flushes their folder, so after a crash or power
// loss `to` is either the old file or the new one, complete.
void rename_durably(const std::string& from, const std::string& to);

// Flushes what the operating system holds of `path` to disk (fsync).
void sync_file(const std::string& path);

}  // namespace romp::io
