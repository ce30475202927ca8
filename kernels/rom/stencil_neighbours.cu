// Neighbours of the samples' grid support (see stencil_neighbours.h).
#include "kernels/rom/stencil_neighbours.h"

#include "kernels/core/for_each.h"
#include "kernels/mpm/bspline.h"

namespace romp::rom {
namespace {

struct MarkStencilNeighbours {
  Vec3Planes<const float> x;
  float inverse_dx;
  Span<const std::uint64_t> near_bases;
  Span<std::int32_t> marked;

  ROMP_HD void operator()(Index p) const {
    const mpm::QuadraticStencil<float> stencil(x.load(p), inverse_dx);
    const std::uint64_t key = node_key(stencil.base[0], stencil.base[1], stencil.base[2]);
    marked[p] = sorted_contains(near_bases, key) ? 1 : 0;
  }
};

}  // namespace

void mark_stencil_neighbours(const Exec& exec, Vec3Planes<const float> x, float inverse_dx,
                             Span<const std::uint64_t> near_bases, Span<std::int32_t> marked) {
  for_each(exec, x.count(), MarkStencilNeighbours{x, inverse_dx, near_bases, marked});
}

}  // namespace romp::rom
