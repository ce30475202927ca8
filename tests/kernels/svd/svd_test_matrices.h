// Seeded generators of the 3x3 input classes the svd3 tests cover: rotations and matrices with chosen singular values.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::test {

class MatrixSampler {
 public:
  explicit MatrixSampler(std::uint64_t seed) : rng_(seed) {}

  double uniform(double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng_); }
  double log_uniform(double low, double high) { return std::exp(uniform(std::log(low), std::log(high))); }
  // -1 or +1 with equal probability.
  double random_sign() { return uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0; }

  // Uniform on SO(3): the rotation of a normalised Gaussian quaternion.
  Mat3<double> rotation() {
    std::normal_distribution<double> normal;
    double w = normal(rng_), x = normal(rng_), y = normal(rng_), z = normal(rng_);
    const double scale = 1.0 / std::sqrt(w * w + x * x + y * y + z * z);
    w *= scale, x *= scale, y *= scale, z *= scale;
    return Mat3<double>(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
                        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),  //
                        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y));
  }

  // R₁ diag(s₀, s₁, s₂) R₂ᵀ with random rotations: any values, in any order and of any sign.
  Mat3<double> with_singular_values(double s0, double s1, double s2) {
    return times_transpose(rotation() * Mat3<double>::diag(s0, s1, s2), rotation());
  }

  // Independent standard-normal entries.
  Mat3<double> gaussian() {
    std::normal_distribution<double> normal;
    Mat3<double> a;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a(r, c) = normal(rng_);
    return a;
  }

 private:
  std::mt19937_64 rng_;
};

}  // namespace romp::test
