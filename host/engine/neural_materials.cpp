// NeuralMaterials: both laws of each neural material on its particles, by the fused law kernels in place.
#include "host/engine/neural_materials.h"

#include "kernels/nclaw/neural_law.h"
#include "nn/nclaw/law_file.h"
#include "nn/tensor_bridge.h"

namespace romp::engine {
namespace {

// The float weights of a law's network, where the kernels read them (exec's device).
nclaw::LawWeights<float> weights_of(const nn::nclaw::LawParameters& parameters, const Exec& exec) {
  return {nn::as_span<const float>(parameters.input, exec, "law input weight").data(),
          nn::as_span<const float>(parameters.hidden, exec, "law hidden weight").data(),
          nn::as_span<const float>(parameters.output, exec, "law output weight").data()};
}

}  // namespace

NeuralMaterials::NeuralMaterials(const Exec& exec, const std::vector<MaterialSpec>& materials, Index particle_count) {
  for (std::size_t m = 0; m < materials.size(); ++m) {
    if (materials[m].params.model != material::MaterialModel::Neural) continue;
    ROMP_CHECK(!materials[m].neural_law.empty(), "material " + std::to_string(m) + " is neural but names no law file");
    nn::nclaw::NeuralLaws laws = nn::nclaw::read_law_file(materials[m].neural_law).laws;
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
  const Mat3Planes<const float> F = particles.F;
  const Mat3Planes<float> P(stress_.data(), particles.count);
  for (const MaterialLaw& law : laws_)
    nclaw::law_forward<float>(exec, weights_of(law.laws.elastic->weights(), exec), {1.0f, false}, F, P,
                              {particles.material.data(), law.material, nullptr});
  return P;
}

void NeuralMaterials::project_plasticity(const Exec& exec, const mpm::ParticleView& particles,
                                         const mpm::StepParams& step) {
  const Mat3Planes<float> F = particles.F;
  for (const MaterialLaw& law : laws_) {
    const nn::nclaw::PlasticLaw& plastic = law.laws.plastic;
    nclaw::law_forward<float>(exec, weights_of(plastic->weights(), exec), {float(plastic->step()), true}, F, F,
                              {particles.material.data(), law.material, particles.dirichlet_group.data()});
  }
  mpm::record_non_finite_deformation(exec, particles, step, mpm::Stage::Plasticity);
}

}  // namespace romp::engine
