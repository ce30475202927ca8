// The neighbours of the Lagrangian quadrature (ROM paper, Alg. 3, steps 2-3): the material points
// whose quadratic B-spline stencil reaches a grid node that some sample's stencil reaches. Only they
// add to the nodes the samples read back in G2P, so P2G over the samples and these neighbours gives
// the samples exactly what P2G over every material point gives.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"

namespace romp::rom {

// A grid node (i, j, k), each coordinate in [0, 2^21), as one sortable key.
ROMP_HD_INLINE std::uint64_t node_key(int i, int j, int k) {
  return (std::uint64_t(i) << 42) | (std::uint64_t(j) << 21) | std::uint64_t(k);
}

// Whether `sorted` (increasing, repeats allowed) holds `key`: a binary search, O(log size) per point.
ROMP_HD_INLINE bool sorted_contains(Span<const std::uint64_t> sorted, std::uint64_t key) {
  Index low = 0, high = sorted.size();
  while (low < high) {
    const Index middle = low + (high - low) / 2;
    if (sorted[middle] < key)
      low = middle + 1;
    else
      high = middle;
  }
  return low < sorted.size() && sorted[low] == key;
}

// marked[p] = 1 if point p's base node (at its current position x) is in `near_bases` (sorted: the
// nodes near the samples, SampleNeighbourhood::near_bases), else 0.
void mark_stencil_neighbours(const Exec& exec, Vec3Planes<const float> x, float inverse_dx,
                             Span<const std::uint64_t> near_bases, Span<std::int32_t> marked);

}  // namespace romp::rom
