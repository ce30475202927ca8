// The small-strain stiffness of an elastic law at rest: the Lamé parameters it behaves like near F = I.
#pragma once

#include <torch/torch.h>

#include <functional>

namespace romp::nn::nclaw {

struct RestStiffness {
  double mu = 0.0;      // μ (Pa)
  double lambda = 0.0;  // λ (Pa)
  // λ + 2μ, the P-wave modulus: ρ c² of the fastest small-amplitude wave (the CFL condition's).
  double p_wave_modulus() const { return lambda + 2.0 * mu; }
};

// μ and λ of the isotropic linear law P ≈ μ (H + Hᵀ) + λ tr(H) I that `elastic` (F [9, n] planes →
// P [9, n]) follows for F = I + H, |H| ≪ 1, from central differences of uniaxial stretches along
// each axis: (P_aa⁺ − P_aa⁻) / 2ε = λ + 2μ and the other two diagonal entries give λ, averaged over
// the axes. Exact (to rounding) for a law that is isotropic and smooth at rest, such as fixed
// corotated; for a learned law it is the rest stiffness the training produced. `elastic` is called
// once, on CPU tensors of `dtype` (float64 recommended: ε = 1e-4 then leaves ~1e-8 rounding).
RestStiffness rest_stiffness(const std::function<torch::Tensor(const torch::Tensor&)>& elastic,
                             torch::ScalarType dtype = torch::kFloat64);

}  // namespace romp::nn::nclaw
