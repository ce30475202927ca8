// The file a libFuzzer harness writes each input to, for readers that take a path.
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace romp::fuzz {

// /tmp/romp_TARGET_fuzzer_PID.h5, or with `file_name` that name in the folder /tmp/romp_TARGET_fuzzer_PID
// (for readers that take a folder, or whose messages and defaults use the file's name). Removed when the
// run ends (libFuzzer exits normally after -runs or -max_total_time; a crash leaves it, beside the crash-*
// input that made it).
class InputFile {
 public:
  explicit InputFile(const std::string& target, const std::string& file_name = "") {
    const std::string stem = "/tmp/romp_" + target + "_fuzzer_" + std::to_string(getpid());
    if (file_name.empty()) {
      path_ = stem + ".h5";
    } else {
      folder_ = stem;
      mkdir(folder_.c_str(), 0700);
      path_ = folder_ + "/" + file_name;
    }
  }
  InputFile(const InputFile&) = delete;  // the copy's destructor would remove the file
  InputFile& operator=(const InputFile&) = delete;
  ~InputFile() {
    std::remove(path_.c_str());
    for (const std::string& path : beside_) std::remove(path.c_str());
    if (!folder_.empty()) rmdir(folder_.c_str());
  }

  // Replaces the file's content with `data`; false if it cannot be written.
  bool write(const std::uint8_t* data, std::size_t size) const {
    std::FILE* file = std::fopen(path_.c_str(), "wb");
    if (file == nullptr) return false;
    const bool whole = std::fwrite(data, 1, size, file) == size;
    return std::fclose(file) == 0 && whole;
  }
  const std::string& path() const { return path_; }
  // The folder that holds the file (empty without a file name).
  const std::string& folder() const { return folder_; }
  // The path of a file `name` in the input's folder (an input with a file name), for the harness to write
  // there; removed with the input.
  std::string beside(const std::string& name) {
    beside_.push_back(folder_ + "/" + name);
    return beside_.back();
  }

 private:
  std::string path_, folder_;
  std::vector<std::string> beside_;
};

}  // namespace romp::fuzz
