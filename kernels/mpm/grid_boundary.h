// The domain walls and the colliders as the grid update imposes them on one node, shared by the
// explicit grid update and the implicit solve (which holds the velocity components they constrain).
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/collider.h"
#include "kernels/mpm/contact.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

// Whether a point at coordinate x along `axis` lies within wall_cells cells of the low face (inward
// normal +e_axis) or of the high face (inward normal −e_axis). For a grid node (x = index × dx) this
// is the test index < wall_cells exactly: float products of integers by one dx keep their order.
ROMP_HD_INLINE bool near_low_wall(const StepParams& step, float x, float dx) { return x < float(step.wall_cells) * dx; }
ROMP_HD_INLINE bool near_high_wall(const StepParams& step, int axis, float x, float dx) {
  return x > float(step.domain_cells[axis] - step.wall_cells) * dx;
}

// Node n of the sparse grid: its integer coordinates (in cells) and its position.
struct GridNode {
  int index[3];
  Vec3<float> position;
  float dx;

  ROMP_HD GridNode(const GridView& grid, Index n) {
    const std::uint64_t key = grid.table.block_keys[n / kNodesPerBlock];
    const int local = int(n % kNodesPerBlock);
    index[0] = block_coordinate(key, 0) * kBlockSide + local / (kBlockSide * kBlockSide);
    index[1] = block_coordinate(key, 1) * kBlockSide + local / kBlockSide % kBlockSide;
    index[2] = block_coordinate(key, 2) * kBlockSide + local % kBlockSide;
    position = Vec3<float>(index[0] * grid.dx, index[1] * grid.dx, index[2] * grid.dx);
    dx = grid.dx;
  }
};

// v after the walls (at rest) and then each collider that contains x: the grid update's rule at a
// node, and an enriched domain corner's at the corner.
ROMP_HD inline Vec3<float> resolve_boundaries(const StepParams& step, const Vec3<float>& x, float dx, Vec3<float> v) {
  const Vec3<float> at_rest = Vec3<float>::zero();
  for (int a = 0; a < 3; ++a) {
    if (near_low_wall(step, x[a], dx))
      v = resolve_contact(v, at_rest, Vec3<float>::unit(a), step.wall_contact, step.wall_friction);
    if (near_high_wall(step, a, x[a], dx))
      v = resolve_contact(v, at_rest, -Vec3<float>::unit(a), step.wall_contact, step.wall_friction);
  }
  for (Index c = 0; c < step.colliders.size(); ++c) {
    const ColliderState& collider = step.colliders[c];
    const SignedDistance sd = signed_distance(collider, x);
    if (sd.distance < 0.0f) v = resolve_contact(v, collider.velocity_at(x), sd.normal, collider.contact, collider.friction);
  }
  return v;
}

ROMP_HD inline Vec3<float> resolve_boundaries(const StepParams& step, const GridNode& node, Vec3<float> v) {
  return resolve_boundaries(step, node.position, node.dx, v);
}

}  // namespace romp::mpm
