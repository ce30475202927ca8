// libFuzzer harness: the snapshot reader (nn/io/snapshot_reader.h) on arbitrary bytes as a file, reading
// the header and every frame as `romp run --compare`, `--output-points` and `train-rom` do. Any input
// must either read or throw romp::Error; a crash (in romp or in libhdf5) is a bug.
#include "kernels/core/error.h"
#include "nn/io/snapshot_reader.h"
#include "tests/fuzz/input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const romp::fuzz::InputFile input("snapshot");
  if (!input.write(data, size)) return 0;
  try {
    const romp::io::SnapshotReader reader(input.path());
    for (std::int64_t frame = 0; frame < reader.frame_count(); ++frame) reader.read_frame(frame);
  } catch (const romp::Error&) {
  }
  return 0;
}
