// libFuzzer harness: the run checkpoint reader (nn/io/checkpoint.h) on arbitrary bytes as a file, as
// `romp run --resume` reads one. Any input must either read or throw romp::Error; a crash (in romp or in
// libhdf5) is a bug. A checkpoint that reads must hold what a run can resume from: the fields' shapes
// agree with particle_count and every value is finite (read_checkpoint promises both).
#include <cmath>
#include <cstdlib>

#include "kernels/core/error.h"
#include "nn/io/checkpoint.h"
#include "tests/fuzz/input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const romp::fuzz::InputFile input("checkpoint");
  if (!input.write(data, size)) return 0;
  try {
    const romp::io::Checkpoint checkpoint = romp::io::read_checkpoint(input.path());
    const std::size_t n = checkpoint.state.x.size() / 3;
    for (const romp::io::FieldInfo& info : romp::io::kFieldInfos) {
      if (!(info.bit & romp::io::kStateFields)) continue;
      const std::vector<float>& values = checkpoint.state.field(info.bit);
      if (values.size() != info.components * n) std::abort();
      for (float value : values)
        if (!std::isfinite(value)) std::abort();
    }
  } catch (const romp::Error&) {
  }
  return 0;
}
