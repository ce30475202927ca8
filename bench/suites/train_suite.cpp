// train suite: one epoch of neural-law training (Ma et al. 2023, App. D.2) on the paper's training
// scene: 1000 substeps forward and backward through the differentiable MPM with both neural laws,
// 1000 particles, against a jelly trajectory simulated with the true law.
#include <fmt/format.h>
#include <omp.h>

#include <string>

#include "bench/suites/suites.h"
#include "host/nclaw/ground_truth.h"
#include "host/scene/scene_parser.h"
#include "host/scene/scene_setup.h"
#include "nn/nclaw/fixed_corotated.h"
#include "nn/nclaw/law_trainer.h"
#include "nn/tensor_bridge.h"

namespace romp::bench {
namespace {

constexpr Index kEpochSteps = 1000;  // substeps of one training rollout (App. D.2)

torch::Tensor tensor_of(const std::vector<float>& values, int64_t planes) {
  return torch::tensor(c10::ArrayRef<float>(values), torch::kFloat32).reshape({planes, -1});
}

}  // namespace

void run_train_suite(Context& context) {
  const scene::Scene scene = scene::load_scene(ROMP_SCENES_DIR "/nclaw/cube_jelly.toml");
  const scene::SceneSetup setup = scene::build_scene(scene);
  const mpm::ParticleInit& p = setup.particles;
  const Index steps = context.scaled(kEpochSteps, 10);
  const int64_t n = p.count();

  const nn::diffmpm::DiffMpmConfig config = nclaw::differentiable_config(scene, "bench train");
  const torch::Tensor mass = tensor_of(p.mass, 1).flatten(), volume = tensor_of(p.volume0, 1).flatten();
  const nn::diffmpm::MpmState initial{tensor_of(p.x, 3), tensor_of(p.v, 3), torch::zeros({9, n}),
                                      torch::eye(3).reshape({9, 1}).expand({9, n}).contiguous()};
  const scene::MaterialSpecification& jelly = scene.materials.front();
  const torch::Tensor youngs = torch::tensor(float(jelly.youngs_modulus)),
                      poisson = torch::tensor(float(jelly.poissons_ratio));
  const nn::diffmpm::ConstitutiveLaws truth_law{
      [&](const torch::Tensor& F) { return nn::nclaw::fixed_corotated_stress(F, youngs, poisson); }, {}, {}};
  const nn::nclaw::Trajectory truth =
      nn::nclaw::simulate(nn::diffmpm::DiffMpm(config, mass, volume), initial, truth_law, steps);

  for (const Exec& exec : context.execs()) {
    if (exec.is_cuda() && !torch::cuda::is_available()) {
      fmt::print("train: skipped on cuda, this LibTorch has no CUDA device\n");
      continue;
    }
    if (!exec.is_cuda()) {
      // LibTorch's ops and the romp kernels behind the autograd functions share the threads.
      omp_set_num_threads(exec.threads);
      torch::set_num_threads(exec.threads);
    }
    nn::nclaw::TrainingOptions options;
    options.steps = steps;
    nn::nclaw::LawTrainer trainer(config, truth.to(nn::torch_device(exec), torch::kFloat32), options);
    nn::nclaw::EpochReport last;
    const Measurement epoch = context.time(
        "train", "epoch_jelly_cube", exec, steps, "substep (forward + backward)", [&] { last = trainer.train_epoch(); },
        0.0, fmt::format("{} particles, {} substeps per epoch, both neural laws", n, steps));
    // Where the last epoch's time went (each phase waited for on the device).
    const double update = last.seconds - last.forward_seconds - last.backward_seconds;
    fmt::print("train: last epoch {:.3f} s: rollouts {:.3f} s, backward passes {:.3f} s, clipping and Adam {:.3f} s\n",
               last.seconds, last.forward_seconds, last.backward_seconds, update);
    const std::string key = fmt::format("train.epoch_jelly_cube.{}{}", epoch.backend, epoch.threads);
    context.record(key + ".forward_share", last.forward_seconds / last.seconds);
    context.record(key + ".backward_share", last.backward_seconds / last.seconds);
  }
}

}  // namespace romp::bench
