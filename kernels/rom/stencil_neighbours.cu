// Neighbours of the samples' grid support (see stencil_neighbours.h).
#include "kernels/rom/stencil_neighbours.h"

#include <algorithm>

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
    // Binary search: the key set is small (at most 125 per sample) and sorted.
    Index low = 0, high = near_bases.size();
    while (low < high) {
      const Index middle = low + (high - low) / 2;
      if (near_bases[middle] < key)
        low = middle + 1;
      else
        high = middle;
    }
    marked[p] = low < near_bases.size() && near_bases[low] == key ? 1 : 0;
  }
};

}  // namespace

std::vector<std::uint64_t> bases_near_samples(const std::vector<float>& x, Index samples, float inverse_dx) {
  std::vector<std::uint64_t> keys;
  keys.reserve(static_cast<std::size_t>(125 * samples));
  for (Index s = 0; s < samples; ++s) {
    const Vec3<float> position(x[s], x[samples + s], x[2 * samples + s]);
    const mpm::QuadraticStencil<float> stencil(position, inverse_dx);
    const int* b = stencil.base;
    // Nodes below 0 hold no point's base: the engine keeps particles a cell inside the domain.
    for (int i = std::max(0, b[0] - 2); i <= b[0] + 2; ++i)
      for (int j = std::max(0, b[1] - 2); j <= b[1] + 2; ++j)
        for (int k = std::max(0, b[2] - 2); k <= b[2] + 2; ++k) keys.push_back(node_key(i, j, k));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

void mark_stencil_neighbours(const Exec& exec, Vec3Planes<const float> x, float inverse_dx,
                             Span<const std::uint64_t> near_bases, Span<std::int32_t> marked) {
  for_each(exec, x.count(), MarkStencilNeighbours{x, inverse_dx, near_bases, marked});
}

}  // namespace romp::rom
