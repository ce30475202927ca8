// libFuzzer harness: the scene reader (host/scene/scene_parser.h: libtoml++, TableReader and the schema) on
// arbitrary text as a scene file, read as `romp check` reads one (load_scene, then the sweep's members);
// toml++ is compiled in (toml_implementation.cpp), so the fuzzer sees its branches too. Any input
// must either read or throw scene::SceneError, which `romp check` reports with file:line:column and exit
// code 3; any other exception (a plain romp::Error would exit 4, as if the run had failed), a crash, a
// sanitizer report or a hang is a bug. Beside the scene lie the files a seed may name: mesh.obj (empty: the
// parser only checks that it is there) and law.h5 (a law file's format attributes, all the parser reads).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "host/scene/scene_parser.h"
#include "host/scene/sweep.h"
#include "host/scene/toml_reader.h"
#include "kernels/core/error.h"
#include "nn/nclaw/law_file_format.h"
#include "tests/fuzz/input_file.h"

namespace {

// Writes mesh.obj and law.h5 beside the input.
bool write_named_files(romp::fuzz::InputFile& input) {
  std::FILE* mesh = std::fopen(input.beside("mesh.obj").c_str(), "wb");
  if (mesh == nullptr || std::fclose(mesh) != 0) return false;
  romp::io::write_versioned_file(input.beside("law.h5"), romp::nn::nclaw::kLawFile, [](romp::io::hdf5::File&) {});
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static romp::fuzz::InputFile input("scene", "scene.toml");
  static const bool ready = write_named_files(input);
  if (!ready || !input.write(data, size)) return 0;
  try {
    const romp::scene::Scene scene = romp::scene::load_scene(input.path());
    if (scene.sweep) romp::scene::sweep_members(*scene.sweep);
  } catch (const romp::scene::SceneError&) {
  } catch (const romp::Error& error) {
    std::fprintf(stderr, "not a scene error (romp check would exit 4, not 3): %s\n", error.what());
    std::abort();
  }
  return 0;
}
