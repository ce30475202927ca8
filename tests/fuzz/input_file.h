// The file a libFuzzer harness writes each input to, for readers that take a path.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace romp::fuzz {

// Removed when the run ends (libFuzzer exits normally after -runs or -max_total_time; a crash leaves it,
// beside the crash-* input that made it).
class InputFile {
 public:
  explicit InputFile(const std::string& target)
      : path_("/tmp/romp_" + target + "_fuzzer_" + std::to_string(getpid()) + ".h5") {}
  ~InputFile() { std::remove(path_.c_str()); }

  // Replaces the file's content with `data`; false if it cannot be written.
  bool write(const std::uint8_t* data, std::size_t size) const {
    std::FILE* file = std::fopen(path_.c_str(), "wb");
    if (file == nullptr) return false;
    const bool whole = std::fwrite(data, 1, size, file) == size;
    return std::fclose(file) == 0 && whole;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace romp::fuzz
