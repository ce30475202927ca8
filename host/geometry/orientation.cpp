// Exact-sign 2-D orientation: a filtered floating-point determinant with an exact fallback.
// Compiled with -ffp-contract=off (see CMakeLists.txt): a fused multiply-add the compiler chose on its
// own would change the roundings that the error bound and the two-sum below rely on.
#include "host/geometry/orientation.h"

#include <cmath>
#include <limits>

namespace romp::geometry {
namespace {

// Shewchuk's ccwerrboundA = (3 + 16 ε) ε with ε = 2⁻⁵³: if |det| is at least this times
// |detleft| + |detright|, the floating-point det has the sign of the exact one.
constexpr double kEpsilon = std::numeric_limits<double>::epsilon() / 2.0;
constexpr double kErrorBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;

// A non-overlapping expansion (Shewchuk §2): doubles of increasing magnitude whose exact sum is the
// value. Its sign is the sign of the largest component.
struct Expansion {
  double component[16];
  int size = 0;

  // Adds b exactly (Grow-Expansion with zero elimination).
  void add(double b) {
    double q = b;
    int kept = 0;
    for (int i = 0; i < size; ++i) {
      const double sum = q + component[i];
      const double b_virtual = sum - q;
      const double error = (q - (sum - b_virtual)) + (component[i] - b_virtual);  // Two-Sum
      q = sum;
      if (error != 0.0) component[kept++] = error;
    }
    if (q != 0.0) component[kept++] = q;
    size = kept;
  }
  // Adds x·y exactly: the product and its rounding error, which a fused multiply-add recovers.
  void add_product(double x, double y) {
    const double product = x * y;
    add(std::fma(x, y, -product));
    add(product);
  }
  double most_significant() const { return size == 0 ? 0.0 : component[size - 1]; }
};

double orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  // (a − c) × (b − c) expanded so every term is a product of two inputs (c_x c_y cancels).
  Expansion sum;
  sum.add_product(ax, by);
  sum.add_product(-ax, cy);
  sum.add_product(-cx, by);
  sum.add_product(-ay, bx);
  sum.add_product(ay, cx);
  sum.add_product(cy, bx);
  return sum.most_significant();
}

}  // namespace

double orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double left = (ax - cx) * (by - cy);
  const double right = (ay - cy) * (bx - cx);
  const double det = left - right;
  // When the two products have opposite signs (or one is zero) there is no cancellation and the
  // sign of det is already exact.
  double magnitude;
  if (left > 0.0) {
    if (right <= 0.0) return det;
    magnitude = left + right;
  } else if (left < 0.0) {
    if (right >= 0.0) return det;
    magnitude = -left - right;
  } else {
    return det;
  }
  if (std::abs(det) >= kErrorBound * magnitude) return det;
  return orient2d_exact(ax, ay, bx, by, cx, cy);
}

}  // namespace romp::geometry
