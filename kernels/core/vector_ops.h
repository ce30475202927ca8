// Level-1 vector operations on float spans for iterative solvers (CG): updates and dot products,
// on either backend.
#pragma once

#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/span.h"

namespace romp {

// y ← y + α x.
void axpy(const Exec& exec, float alpha, Span<const float> x, Span<float> y);
// y ← x + β y (CG's new search direction).
void xpby(const Exec& exec, Span<const float> x, float beta, Span<float> y);

// Σₖ aₖ bₖ, accumulated in double. Lane l of kLanes sums the elements k ≡ l (mod kLanes) in order
// (consecutive lanes read consecutive addresses, so GPU loads coalesce), and the host adds the lanes
// in order: the result depends on the values alone, not on thread scheduling. Owns the lane sums,
// so a solver keeps one and calls it every iteration without allocating.
class DotProduct {
 public:
  static constexpr Index kLanes = 4096;

  explicit DotProduct(Backend backend) : lanes_(backend, kLanes), host_(kLanes) {}
  // Synchronises with the host (the sum is needed there).
  double operator()(const Exec& exec, Span<const float> a, Span<const float> b);

 private:
  DeviceBuffer<double> lanes_;
  std::vector<double> host_;
};

}  // namespace romp
