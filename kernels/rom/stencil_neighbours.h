// The neighbours of the Lagrangian quadrature (ROM paper, Alg. 3, steps 2-3): the material points
// whose quadratic B-spline stencil reaches a grid node that some sample's stencil reaches. Only they
// add to the nodes the samples read back in G2P, so P2G over the samples and these neighbours gives
// the samples exactly what P2G over every material point gives.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"

namespace romp::rom {

// A grid node (i, j, k), each coordinate in [0, 2^21), as one sortable key.
ROMP_HD_INLINE std::uint64_t node_key(int i, int j, int k) {
  return (std::uint64_t(i) << 42) | (std::uint64_t(j) << 21) | std::uint64_t(k);
}

// Two 3 × 3 × 3 stencils share a node exactly when their base nodes are at most 2 apart on every axis,
// so the neighbours are the points whose base node is one of these: the sorted, unique keys of every
// node within 2 (per axis) of a sample's base node. `x`: the samples' current positions (host planes).
std::vector<std::uint64_t> bases_near_samples(const std::vector<float>& x, Index samples, float inverse_dx);

// marked[p] = 1 if point p's base node (at its current position x) is in `near_bases`, else 0.
void mark_stencil_neighbours(const Exec& exec, Vec3Planes<const float> x, float inverse_dx,
                             Span<const std::uint64_t> near_bases, Span<std::int32_t> marked);

}  // namespace romp::rom
