// OutputLock: flock on a lock file beside the output, with the lock holder's pid in it for the message.
#include "nn/io/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "kernels/core/error.h"

namespace romp::io {
namespace {

namespace fs = std::filesystem;

// The pid a holder wrote into the lock file, or "another process" where it cannot be read.
std::string holder(int fd) {
  char text[32] = {};
  const ssize_t length = pread(fd, text, sizeof(text) - 1, 0);
  return length > 0 ? fmt::format("process {}", std::string(text, std::size_t(length))) : "another process";
}

}  // namespace

OutputLock::OutputLock(const std::string& output) : path_(output + ".lock") {
  const fs::path folder = fs::path(output).parent_path();
  if (!folder.empty()) fs::create_directories(folder);
  // A holder removes the file when it is done; one that opened the file just before then would lock a
  // file no longer at the path, so the lock counts only when the path still names the locked file.
  for (;;) {
    fd_ = open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw Error(fmt::format("{}: cannot create the lock file: {}", path_, std::strerror(errno)));
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      const std::string who = holder(fd_);
      close(fd_);
      fd_ = -1;
      if (error == EWOULDBLOCK)
        throw Error(
            fmt::format("{} is being written by {} (it holds {}); wait for that run to end, or write to "
                        "another file with -o",
                        output, who, path_));
      throw Error(fmt::format("{}: cannot lock: {}", path_, std::strerror(error)));
    }
    struct stat locked {
    }, named{};
    if (fstat(fd_, &locked) == 0 && stat(path_.c_str(), &named) == 0 && locked.st_ino == named.st_ino &&
        locked.st_dev == named.st_dev)
      break;
    close(fd_);  // the holder removed it meanwhile: claim the new one
  }
  // The pid only serves the message a second writer gets; the lock holds without it.
  const std::string pid = std::to_string(getpid());
  const bool written = ftruncate(fd_, 0) == 0 && pwrite(fd_, pid.data(), pid.size(), 0) == ssize_t(pid.size());
  (void)written;
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  unlink(path_.c_str());  // while still locked, so no other process can have claimed this file
  close(fd_);
}

}  // namespace romp::io
