// libFuzzer harness: the sweep manifest reader (nn/rom/sweep_manifest.h) on arbitrary bytes as
// DIR/manifest.json, as `romp train-rom DIR` reads it before any snapshot. Any input must either read or
// throw io::UnusableFileError, which train-rom reports with exit code 3; any other exception (a plain
// romp::Error or a JSON library error would exit 4, as if the machine had failed), a crash, a sanitizer
// report or a hang is a bug. A manifest that reads has at least one member and a value for every parameter.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "nn/io/unusable_file_error.h"
#include "nn/rom/sweep_manifest.h"
#include "tests/fuzz/input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static romp::fuzz::InputFile input("manifest", "manifest.json");
  if (!input.write(data, size)) return 0;
  try {
    const romp::nn::rom::SweepManifest manifest = romp::nn::rom::read_sweep_manifest(input.folder());
    if (manifest.members.empty()) std::abort();
    for (const romp::nn::rom::SweepMember& member : manifest.members)
      if (member.values.size() != manifest.parameter_names.size()) std::abort();
  } catch (const romp::io::UnusableFileError&) {
  } catch (const std::exception& error) {
    std::fprintf(stderr, "not an unusable-file error (train-rom would exit 4, not 3): %s\n", error.what());
    std::abort();
  }
  return 0;
}
