// PlasticReturn: what a return map gives, the elastic F and the plastic strain it removed.
#pragma once

#include "kernels/math/mat3.h"

namespace romp::material {

template <class T>
struct PlasticReturn {
  Mat3<T> F;        // the elastic deformation gradient on or inside the yield surface
  T strain = T(0);  // ‖Δε‖: the Euclidean norm of the principal Hencky strain the return map removed
};

}  // namespace romp::material
