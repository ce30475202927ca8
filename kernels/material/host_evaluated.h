// HostEvaluated: the model record of a material whose stress and return map the host computes (neural laws).
//
// A learned constitutive law (Ma et al. 2023) is a LibTorch network, which kernels cannot call. Its
// particles get their first Piola stress from StepParams::host_stress, filled by the host before P2G,
// and their plastic projection from the host after G2P (host/neural_materials.h). The material
// table still needs a record for them, and the dispatchers a model struct: this one. Its functions
// are never the ones a correct run uses, so they return NaN: a path that reaches them anyway (a
// stage that forgot the host's stress) stops as non-finite with the stage and particle instead of
// running on a made-up stress.
#pragma once

#include <limits>

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::material {

template <class T>
struct HostEvaluated {
  static constexpr bool kPlastic = false;  // the host's plastic law runs as its own stage

  static constexpr T not_here() { return std::numeric_limits<T>::quiet_NaN(); }

  ROMP_HD T energy_density(const Mat3<T>&) const { return not_here(); }
  ROMP_HD Mat3<T> first_piola(const Mat3<T>&) const { return Mat3<T>::diag(not_here(), not_here(), not_here()); }
  ROMP_HD Mat3<T> first_piola_differential(const Mat3<T>& F, const Mat3<T>&) const { return first_piola(F); }
  ROMP_HD Vec3<T> principal_stress(const Vec3<T>&) const { return Vec3<T>::constant(not_here()); }
  ROMP_HD Mat3<T> principal_stress_derivative(const Vec3<T>&) const {
    return Mat3<T>::diag(not_here(), not_here(), not_here());
  }
};

}  // namespace romp::material
