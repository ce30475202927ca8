// NeuralMaterials: both laws of each neural material on its particles, through LibTorch on the engine's planes.
#include "host/engine/neural_materials.h"

#include "nn/nclaw/law_file.h"
#include "nn/tensor_bridge.h"

namespace romp {
namespace {

// The [9, n] planes of F, aliased.
torch::Tensor deformation_planes(const Exec& exec, const mpm::ParticleView& particles) {
  return nn::as_tensor(Span<float>(particles.F.data(), 9 * particles.count), exec, {9, particles.count});
}

// Indices of the particles where `selected` [n] is true.
torch::Tensor indices_of(const torch::Tensor& selected) { return selected.nonzero().squeeze(1); }

}  // namespace

NeuralMaterials::NeuralMaterials(const Exec& exec, const std::vector<MaterialSpec>& materials, Index particle_count) {
  for (std::size_t m = 0; m < materials.size(); ++m) {
    if (materials[m].params.model != material::MaterialModel::Neural) continue;
    ROMP_CHECK(!materials[m].neural_law.empty(), "material " + std::to_string(m) + " is neural but names no law file");
    nn::NeuralLaws laws = nn::read_law_file(materials[m].neural_law).laws;
    // On the engine's stream, so that its kernels find the weights in place without a synchronisation.
    const nn::TorchStreamScope stream(exec);
    laws.to(nn::torch_device(exec), torch::kFloat32);
    laws_.push_back({std::int32_t(m), std::move(laws)});
  }
  if (!laws_.empty()) {
    stress_ = DeviceBuffer<float>(exec.backend, 9 * particle_count);
    stress_.fill_zero(exec.stream);
  }
}

Mat3Planes<const float> NeuralMaterials::evaluate_stress(const Exec& exec, const mpm::ParticleView& particles) {
  ROMP_CHECK(stress_.size() == 9 * particles.count, "NeuralMaterials: the particle count changed");
  const nn::TorchStreamScope stream(exec);
  const torch::NoGradGuard no_grad;
  const torch::Tensor F = deformation_planes(exec, particles);
  const torch::Tensor material = nn::as_tensor(Span<const std::int32_t>(particles.material), exec, {particles.count});
  torch::Tensor P = nn::as_tensor(stress_.span(), exec, {9, particles.count});
  for (MaterialLaw& law : laws_) {
    const torch::Tensor chosen = indices_of(material == law.material);
    if (chosen.numel() > 0) P.index_copy_(1, chosen, law.laws.elastic->forward(F.index_select(1, chosen)));
  }
  return Mat3Planes<const float>(stress_.data(), particles.count);
}

void NeuralMaterials::project_plasticity(const Exec& exec, const mpm::ParticleView& particles,
                                         const mpm::StepParams& step) {
  {
    const nn::TorchStreamScope stream(exec);
    const torch::NoGradGuard no_grad;
    torch::Tensor F = deformation_planes(exec, particles);
    const torch::Tensor material = nn::as_tensor(Span<const std::int32_t>(particles.material), exec, {particles.count});
    const torch::Tensor free =
        nn::as_tensor(Span<const std::int32_t>(particles.dirichlet_group), exec, {particles.count}) ==
        mpm::kNoDirichletGroup;
    for (MaterialLaw& law : laws_) {
      const torch::Tensor chosen = indices_of((material == law.material).logical_and(free));
      if (chosen.numel() > 0) F.index_copy_(1, chosen, law.laws.plastic->forward(F.index_select(1, chosen)));
    }
  }
  mpm::record_non_finite_deformation(exec, particles, step, mpm::Stage::Plasticity);
}

}  // namespace romp
