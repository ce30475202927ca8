// The supervised oracle of Ma et al. 2023 (Sec. 4): the neural laws fitted directly to constitutive
// pairs, (F, P) for the elastic law and (F_trial, F_new) for the plastic law, instead of to motion.
#pragma once

#include <torch/torch.h>

#include <vector>

#include "nn/nclaw/neural_laws.h"
#include "nn/nclaw/trajectory.h"

namespace romp::nn::nclaw {

// Engine planes [9, m], m pairs.
struct ConstitutivePairs {
  torch::Tensor F, P;                  // elastic F and the true first Piola–Kirchhoff stress at it
  torch::Tensor F_trial, F_projected;  // F before and after the true plastic projection
};

// The plastic pairs of a trajectory, every particle at every substep: F_trial = (I + dt C_{k+1}) F_k
// (the trial F of Alg. 3, from the C the substep produced) and F_projected = F_{k+1}.
void add_plastic_pairs(const Trajectory& truth, double dt, ConstitutivePairs& pairs);

struct SupervisedOptions {
  int64_t epochs = 300;                // full-batch Adam steps, cosine-annealed
  double elastic_learning_rate = 1.0;  // the motion training's rates (App. D.2)
  double plastic_learning_rate = 0.1;
  double gradient_clip = 0.1;  // per network
};

struct SupervisedLosses {
  std::vector<double> elastic, plastic;  // per epoch, before its step
};

// Fits `laws` to `pairs` by relative mean squared error: |P_law − P|² / mean |P|² and
// |F_law − F_projected|² / mean |F_projected − F_trial|² (the part the plastic law must learn).
SupervisedLosses fit_supervised(NeuralLaws& laws, const ConstitutivePairs& pairs, const SupervisedOptions& options);

}  // namespace romp::nn::nclaw
