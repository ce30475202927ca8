// Loading a ROM model file for a scene and encoding the scene's initial state.
#include "host/engine/rom_model_loader.h"

#include <fmt/format.h>

#include "kernels/core/error.h"
#include "nn/io/unusable_file_error.h"
#include "nn/rom/fused_map.h"
#include "nn/rom/rom_model_file.h"

namespace romp::engine {

LoadedReducedModel load_reduced_model(const std::string& path, const mpm::ParticleInit& particles) {
  const nn::rom::RomModel model = nn::rom::read_rom_model(path);
  const Index n = particles.count();
  if (model.training.particle_count != n)
    throw io::UnusableFileError(
        fmt::format("model {} was trained on snapshots of {} material points; this scene samples {}. Run "
                    "the scene (and --set values) its training sweep ran",
                    path, model.training.particle_count, n));
  // The initial positions as [1, P, 3] rows for the encoder.
  const torch::Tensor planes = torch::from_blob(const_cast<float*>(particles.x.data()), {3, n}, torch::kFloat32);
  const torch::Tensor x = planes.t().contiguous().unsqueeze(0);
  torch::NoGradGuard no_gradients;
  const torch::Tensor xhat = model.encode(x).squeeze(0).contiguous();

  LoadedReducedModel loaded;
  loaded.map = nn::rom::fused_weights(*model.map);
  loaded.xhat.assign(xhat.data_ptr<float>(), xhat.data_ptr<float>() + xhat.numel());
  loaded.description =
      fmt::format("model {}: r = {}, {} hidden layers of {}, trained {} epochs; test position error {:.3g}%", path,
                  loaded.map.latent, loaded.map.hidden_layers, loaded.map.width, model.training.epochs_done,
                  100.0 * model.training.test_errors.position);
  return loaded;
}

}  // namespace romp::engine
