// libFuzzer harness: the snapshot reader (nn/io/snapshot_reader.h) on arbitrary bytes as a file, reading
// the header and every frame as `romp run --compare`, `--output-points` and `train-rom` do. Any input
// must either read or throw romp::Error; a crash (in romp or in libhdf5) is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "kernels/core/error.h"
#include "nn/io/snapshot_reader.h"

namespace {

// The file each input is written to, removed when the run ends (libFuzzer exits normally after -runs or
// -max_total_time; a crash leaves it, beside the crash-* input that made it).
struct InputFile {
  std::string path = "/tmp/romp_snapshot_fuzzer_" + std::to_string(getpid()) + ".h5";
  ~InputFile() { std::remove(path.c_str()); }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const InputFile input;
  const std::string& path = input.path;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data, 1, size, file);
  std::fclose(file);
  try {
    const romp::io::SnapshotReader reader(path);
    for (std::int64_t frame = 0; frame < reader.frame_count(); ++frame) reader.read_frame(frame);
  } catch (const romp::Error&) {
  }
  return 0;
}
