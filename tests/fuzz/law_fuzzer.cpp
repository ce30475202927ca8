// libFuzzer harness: the neural-law file reader (nn/nclaw/law_file_content.h, the HDF5 half of read_law_file)
// on arbitrary bytes as a file, as `romp run` and `romp check` read a law a scene names. Any input must either
// read or throw io::UnusableFileError, which romp reports with exit code 3; any other exception (a plain
// romp::Error exits 4, as if the machine had failed), a crash (in romp or in libhdf5), a sanitizer report or a
// hang is a bug. A law that reads has its networks' shapes, finite weights and a positive plastic step, all
// that read_law_file then copies into the LibTorch modules (which this harness does not link).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "nn/io/unusable_file_error.h"
#include "nn/nclaw/law_file_content.h"
#include "tests/fuzz/input_file.h"

namespace {

bool usable(const romp::nn::nclaw::LawNetworkWeights& weights) {
  for (std::size_t layer = 0; layer < weights.size(); ++layer) {
    const std::array<std::uint64_t, 2> shape = romp::nn::nclaw::law_weight_shape(layer);
    if (weights[layer].size() != shape[0] * shape[1]) return false;
    for (double value : weights[layer])
      if (!std::isfinite(value)) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const romp::fuzz::InputFile input("law");
  if (!input.write(data, size)) return 0;
  try {
    const romp::nn::nclaw::LawFileContent law = romp::nn::nclaw::read_law_file_content(input.path());
    if (!usable(law.elastic) || !usable(law.plastic)) std::abort();
    if (!(std::isfinite(law.plastic_step) && law.plastic_step > 0.0)) std::abort();
  } catch (const romp::io::UnusableFileError&) {
  } catch (const std::exception& error) {
    std::fprintf(stderr, "not an unusable-file error (romp would exit 4, not 3): %s\n", error.what());
    std::abort();
  }
  return 0;
}
