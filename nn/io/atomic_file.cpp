// AtomicFile: temporary names, fsync and rename.
#include "nn/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "kernels/core/error.h"

namespace romp::io {
namespace {

// fsync of a file or folder; `what` names it in the error.
void sync_to_disk(const std::string& path, int flags, const char* what) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) throw Error(fmt::format("{} {}: cannot open to flush: {}", what, path, std::strerror(errno)));
  const bool synced = ::fsync(fd) == 0;
  const int error = errno;
  ::close(fd);
  if (!synced) throw Error(fmt::format("{} {}: cannot flush to disk: {}", what, path, std::strerror(error)));
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  temp_path_ = fmt::format("{}.tmp-{}", path_, ::getpid());
  const std::filesystem::path folder = std::filesystem::path(path_).parent_path();
  std::error_code error;
  if (!folder.empty()) std::filesystem::create_directories(folder, error);
  if (error) throw Error(fmt::format("{}: cannot create folder {}: {}", path_, folder.string(), error.message()));
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  std::error_code ignored;
  std::filesystem::remove(temp_path_, ignored);
}

void AtomicFile::commit() {
  rename_durably(temp_path_, path_);
  committed_ = true;
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  AtomicFile file(path);
  {
    std::ofstream out(file.temp_path(), std::ios::binary | std::ios::trunc);
    if (!out) throw Error(fmt::format("{}: cannot create {}: {}", path, file.temp_path(), std::strerror(errno)));
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw Error(fmt::format("{}: cannot write {} bytes to {}", path, bytes.size(), file.temp_path()));
  }
  file.commit();
}

void sync_file(const std::string& path) { sync_to_disk(path, O_RDONLY, "file"); }

void rename_durably(const std::string& from, const std::string& to) {
  sync_file(from);
  std::error_code error;
  std::filesystem::rename(from, to, error);
  if (error) throw Error(fmt::format("cannot rename {} to {}: {}", from, to, error.message()));
  const std::filesystem::path folder = std::filesystem::path(to).parent_path();
  sync_to_disk(folder.empty() ? "." : folder.string(), O_RDONLY | O_DIRECTORY, "folder");
}

}  // namespace romp::io
