// Lamé parameters (μ, λ) from Young's modulus and Poisson's ratio, as the scenes and papers give them.
#pragma once

#include "kernels/core/hd.h"

namespace romp::material {

template <class T>
struct Lame {
  T mu;      // shear modulus μ
  T lambda;  // first Lamé parameter λ
};

// μ = E / (2 (1 + ν)), λ = E ν / ((1 + ν)(1 - 2ν)) (isotropic linear elasticity).
// Valid for E > 0 and -1 < ν < 0.5: μ > 0 there, and λ diverges as ν → 0.5 (incompressibility).
// The host checks the range when it reads a scene; this function does not.
template <class T>
ROMP_HD constexpr Lame<T> lame_from_young_poisson(T young, T poisson) {
  return {young / (T(2) * (T(1) + poisson)), young * poisson / ((T(1) + poisson) * (T(1) - T(2) * poisson))};
}

}  // namespace romp::material
