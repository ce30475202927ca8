// The labeled and system-identification oracles on a ground-truth trajectory.
#include "host/nclaw/oracles.h"

#include <fmt/format.h>

#include "host/scene/material_library.h"
#include "kernels/core/error.h"
#include "kernels/material/material.h"
#include "nn/nclaw/evaluation.h"
#include "nn/nclaw/fixed_corotated.h"

namespace romp::nclaw {
namespace {

const scene::MaterialSpecification& only_material(const GroundTruth& truth, const std::string& who) {
  ROMP_CHECK(
      truth.materials.size() == 1,
      fmt::format("{}: the ground truth's scene has {} materials; the oracles learn one", who, truth.materials.size()));
  return truth.materials.front();
}

// P of the ground truth's engine material at every column of F [9, m] (float planes on the CPU).
torch::Tensor true_stress(const material::MaterialParams<float>& params, const torch::Tensor& F) {
  const torch::Tensor planes = F.contiguous();
  const int64_t m = planes.size(1);
  torch::Tensor P = torch::empty_like(planes);
  const Mat3Planes<const float> in(planes.data_ptr<float>(), m);
  const Mat3Planes<float> out(P.data_ptr<float>(), m);
  for (int64_t i = 0; i < m; ++i) out.store(i, material::first_piola(params, in.load(i)));
  return P;
}

}  // namespace

nn::nclaw::LawFile fit_labeled_oracle(const GroundTruth& truth, const std::string& trajectory_file,
                                      const nn::nclaw::SupervisedOptions& options, int64_t stride, uint64_t seed) {
  const scene::MaterialSpecification& material = only_material(truth, "labeled oracle");
  ROMP_CHECK(material.model != material::MaterialModel::Neural,
             "labeled oracle: the ground truth's material is itself a learned law");
  ROMP_CHECK(stride >= 1, fmt::format("labeled oracle: the frame stride must be >= 1, got {}", stride));
  const nn::nclaw::Trajectory& t = truth.trajectory;
  const material::MaterialParams<float> params = scene::to_material_spec(material).params;
  const int64_t steps = t.frame_count() - 1;

  nn::nclaw::ConstitutivePairs pairs;
  pairs.F = t.F.slice(0, 0, steps, stride).permute({1, 0, 2}).reshape({9, -1}).contiguous();
  pairs.P = true_stress(params, pairs.F);
  const bool plastic = material::is_plastic(params.model);
  for (int64_t k = 0; plastic && k < steps; k += stride) {
    nn::nclaw::Trajectory substep = t;  // frames k and k + 1: one substep's trial and projected F
    for (torch::Tensor* field : {&substep.x, &substep.v, &substep.C, &substep.F}) *field = field->slice(0, k, k + 2);
    nn::nclaw::add_plastic_pairs(substep, truth.config.fixed_dt, pairs);
  }

  nn::nclaw::LawFile result{nn::nclaw::seeded_laws(seed, torch::kFloat32), {}};
  if (!plastic) {
    const torch::NoGradGuard no_grad;
    result.laws.plastic->parameters().back().zero_();  // F_new = F_trial exactly
  }
  const nn::nclaw::SupervisedLosses losses = nn::nclaw::fit_supervised(result.laws, pairs, options);
  const nn::diffmpm::DiffMpm sim(truth.config, t.mass, t.volume);
  result.training = {trajectory_file, steps, losses.elastic,
                     nn::nclaw::position_error(sim, t, result.laws.constitutive(), steps)};
  return result;
}

IdentifiedMaterial identify_material(const GroundTruth& truth, const nn::nclaw::SystemIdentificationOptions& options,
                                     const IdentificationProgress& progress) {
  const scene::MaterialSpecification& material = only_material(truth, "system identification");
  ROMP_CHECK(material.model == material::MaterialModel::FixedCorotated,
             "system identification fits fixed corotated elasticity (the jelly); the ground truth's material '" +
                 material.name + "' is another model");
  nn::nclaw::SystemIdentification fit(truth.config, truth.trajectory, options);
  IdentifiedMaterial identified;
  while (!fit.finished()) {
    identified.loss.push_back(fit.train_epoch());
    if (progress) progress(fit.epochs_done(), identified.loss.back(), fit.youngs(), fit.poisson());
  }
  identified.youngs_modulus = fit.youngs();
  identified.poissons_ratio = fit.poisson();
  const torch::Tensor youngs = torch::tensor(float(identified.youngs_modulus)),
                      poisson = torch::tensor(float(identified.poissons_ratio));
  const nn::diffmpm::ConstitutiveLaws law{
      [&](const torch::Tensor& F) { return nn::nclaw::fixed_corotated_stress(F, youngs, poisson); }, {}, {}};
  const nn::diffmpm::DiffMpm sim(truth.config, truth.trajectory.mass, truth.trajectory.volume);
  identified.reconstruction_error = nn::nclaw::position_error(sim, truth.trajectory, law, options.steps);
  return identified;
}

}  // namespace romp::nclaw
