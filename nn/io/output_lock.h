// An exclusive claim on an output file for as long as a run writes it, so that two processes never
// write the same snapshot (and its partial file and checkpoint) at once.
#pragma once

#include <string>

namespace romp::io {

// Locks `<output>.lock` (flock, exclusive, not waiting), creating the output's folder and the lock file
// where they are missing; the lock file is removed when the claim ends. Throws romp::Error naming the
// output and the process that holds it when another process (or another OutputLock) holds it.
class OutputLock {
 public:
  explicit OutputLock(const std::string& output);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  const std::string& path() const { return path_; }  // the lock file

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace romp::io
