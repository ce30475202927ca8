// libFuzzer harness: the ROM model file reader (nn/rom/rom_model_file_content.h, what read_rom_model checks
// before it builds the LibTorch networks) on arbitrary bytes as a file, as `romp run`, `romp check` and
// `romp rom-eval` read the model a reduced scene names. Any input must either read or throw
// io::UnusableFileError (exit 3); any other exception (exit 4, as if the machine had failed), a crash (in romp
// or in libhdf5), a sanitizer report, an allocation past libFuzzer's limit or a hang is a bug. A model that
// reads holds everything read_rom_model then copies into modules of the shapes its sizes give: layers of those
// shapes, finite values, a usable normalisation, encoder indices that increase below the particle count, and
// sizes within the fused kernels' limits.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "kernels/rom/deformation_map_eval.h"
#include "nn/io/unusable_file_error.h"
#include "nn/rom/encoder_shape.h"
#include "nn/rom/rom_model_file_content.h"
#include "tests/fuzz/input_file.h"

namespace {

using romp::nn::rom::StoredLayer;

bool usable(const StoredLayer& layer, const std::vector<std::int64_t>& weight_shape) {
  if (layer.weight_shape != weight_shape) return false;
  std::size_t count = 1;
  for (std::int64_t extent : weight_shape) count *= std::size_t(extent);
  if (layer.weight.size() != count || layer.bias.size() != std::size_t(weight_shape[0])) return false;
  for (float value : layer.weight)
    if (!std::isfinite(value)) return false;
  for (float value : layer.bias)
    if (!std::isfinite(value)) return false;
  return true;
}

bool usable(const romp::nn::rom::RomModelFileContent& model) {
  namespace rom = romp::nn::rom;
  const rom::MapArchitecture& architecture = model.architecture;
  if (architecture.latent < 1 || architecture.latent > romp::rom::kMaxMapLatent) return false;
  if (!rom::normalisation_problem(model.normalisation).empty()) return false;
  const auto shapes = rom::map_layer_shapes(architecture);
  if (model.map_layers.size() != shapes.size()) return false;
  for (std::size_t k = 0; k < shapes.size(); ++k)
    if (!usable(model.map_layers[k], {shapes[k][0], shapes[k][1]})) return false;
  const std::int64_t points = std::int64_t(model.encoder_indices.size());
  if (points < 1 || points > model.training.particle_count) return false;
  for (std::size_t i = 0; i < model.encoder_indices.size(); ++i) {
    const std::int64_t index = model.encoder_indices[i];
    if (index < 0 || index >= model.training.particle_count) return false;
    if (i > 0 && index <= model.encoder_indices[i - 1]) return false;
  }
  if (std::int64_t(model.encoder_convolutions.size()) != rom::encoder_conv_layers(points)) return false;
  for (const StoredLayer& conv : model.encoder_convolutions)
    if (!usable(conv, {rom::kEncoderChannels, rom::kEncoderChannels, rom::kEncoderKernel})) return false;
  return usable(model.encoder_linears[0], {rom::kEncoderHidden, rom::encoder_conv_features(points)}) &&
         usable(model.encoder_linears[1], {architecture.latent, rom::kEncoderHidden});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const romp::fuzz::InputFile input("model");
  if (!input.write(data, size)) return 0;
  try {
    if (!usable(romp::nn::rom::read_rom_model_file_content(input.path()))) std::abort();
  } catch (const romp::io::UnusableFileError&) {
  } catch (const std::exception& error) {
    std::fprintf(stderr, "not an unusable-file error (romp would exit 4, not 3): %s\n", error.what());
    std::abort();
  }
  return 0;
}
