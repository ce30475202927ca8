// The neural-law paper's two oracles (Ma et al. 2023, Sec. 4), which know more than the motion: the
// comparison points a law learned from motion alone is measured against.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "host/nclaw/ground_truth.h"
#include "nn/nclaw/law_file.h"
#include "nn/nclaw/supervised_fit.h"
#include "nn/nclaw/system_identification.h"

namespace romp::nclaw {

// "labeled": both laws fitted to constitutive pairs of the trajectory instead of to its motion: the
// elastic law to (F, P) with P the ground-truth material's stress at every particle's F of every
// `stride`-th frame, the plastic law to (F_trial, F_new) of the substeps that start there. For a
// purely elastic material the plastic law is the identity (its output layer zero), which is what
// it should learn. The trajectory must come from a scene of one material. The record's loss is the
// elastic fit's, and its reconstruction error is the free rollout's on the trajectory.
nn::nclaw::LawFile fit_labeled_oracle(const GroundTruth& truth, const std::string& trajectory_file,
                                      const nn::nclaw::SupervisedOptions& options, int64_t stride, uint64_t seed);

struct IdentifiedMaterial {
  double youngs_modulus = 0.0;  // Pa
  double poissons_ratio = 0.0;
  std::vector<double> loss;           // per epoch
  double reconstruction_error = 0.0;  // mean position MSE every 5 frames of a free rollout (m²)
};

// "sys-id": Young's modulus and Poisson's ratio of fixed corotated elasticity learned through the
// same differentiable simulation and loss as the neural laws. Throws romp::Error unless the
// trajectory's one material is fixed corotated (the jelly), the only model this oracle fits.
// `progress`, when given, hears each epoch's loss and the parameters after its step.
using IdentificationProgress = std::function<void(int64_t epoch, double loss, double youngs, double poisson)>;
IdentifiedMaterial identify_material(const GroundTruth& truth, const nn::nclaw::SystemIdentificationOptions& options,
                                     const IdentificationProgress& progress = {});

}  // namespace romp::nclaw
