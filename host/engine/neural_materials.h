// NeuralMaterials: the learned constitutive laws of a scene's neural materials, evaluated on the particles each
// substep.
//
// Ma et al. 2023 run a learned law inside an ordinary MPM step: P = elastic(F) before P2G, and
// F ← plastic(F_trial) after G2P. LibTorch loads and holds the weights; this class runs both laws
// with the fused law kernels (kernels/nclaw/neural_law.h), one launch per neural material and stage,
// on the particle planes where they lie, in place. Any number of neural materials share a scene, each
// with its own law file, beside materials with analytic models.
#pragma once

#include <cstdint>
#include <vector>

#include "host/engine/sim_config.h"
#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/mpm/particle_set.h"
#include "kernels/mpm/step.h"
#include "nn/nclaw/neural_laws.h"

namespace romp::engine {

class NeuralMaterials {
 public:
  // Loads the law of every material that names one (MaterialSpec::neural_law) onto exec's device,
  // for a run of `particle_count` particles. Throws romp::Error naming the file when one is not a
  // usable law file.
  NeuralMaterials(const Exec& exec, const std::vector<MaterialSpec>& materials, Index particle_count);

  bool empty() const { return laws_.empty(); }

  // P = elastic(F) of every particle of a neural material, in the particles' current order, for
  // StepParams::host_stress; the entries of other particles are left as they were (P2G reads them
  // only for neural materials). Valid until the next call.
  Mat3Planes<const float> evaluate_stress(const Exec& exec, const mpm::ParticleView& particles);

  // F ← plastic(F) for the particles of neural materials outside Dirichlet groups (the rule of
  // mpm::project_plasticity), recording a non-finite result as the Plasticity stage's failure.
  void project_plasticity(const Exec& exec, const mpm::ParticleView& particles, const mpm::StepParams& step);

 private:
  struct MaterialLaw {
    std::int32_t material;  // index into the material table
    nn::nclaw::NeuralLaws laws;
  };
  std::vector<MaterialLaw> laws_;
  DeviceBuffer<float> stress_;  // 9 planes
};

}  // namespace romp::engine
