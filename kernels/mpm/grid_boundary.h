// The domain walls and the colliders as the grid update imposes them on one node, shared by the
// explicit grid update and the implicit solve (which holds the velocity components they constrain).
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/collider.h"
#include "kernels/mpm/contact.h"
#include "kernels/mpm/domain_walls.h"
#include "kernels/mpm/sparse_grid.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

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

// v after the domain walls (at rest): the frictionless rule of both MPMs (wall_keep_mask), or, on
// Separate walls with friction, resolve_contact face by face, whose Coulomb term scales the tangential
// velocity each face leaves to the next.
ROMP_HD inline Vec3<float> resolve_walls(const StepParams& step, const Vec3<float>& x, float dx, Vec3<float> v) {
  const Domain& domain = step.domain;
  if (step.wall_friction == 0.0f || domain.wall_contact != ContactType::Separate)
    return hadamard(wall_keep_mask(domain, x, dx, v), v);
  const Vec3<float> at_rest = Vec3<float>::zero();
  for (int a = 0; a < 3; ++a) {
    if (domain.near_low_wall(x[a], dx))
      v = resolve_contact(v, at_rest, Vec3<float>::unit(a), ContactType::Separate, step.wall_friction);
    if (domain.near_high_wall(a, x[a], dx))
      v = resolve_contact(v, at_rest, -Vec3<float>::unit(a), ContactType::Separate, step.wall_friction);
  }
  return v;
}

// v after the walls and then each collider that contains x: the grid update's rule at a node, and an
// enriched domain corner's at the corner.
ROMP_HD inline Vec3<float> resolve_boundaries(const StepParams& step, const Vec3<float>& x, float dx, Vec3<float> v) {
  v = resolve_walls(step, x, dx, v);
  for (Index c = 0; c < step.colliders.size(); ++c) {
    const ColliderState& collider = step.colliders[c];
    const SignedDistance sd = signed_distance(collider, x);
    if (sd.distance < 0.0f)
      v = resolve_contact(v, collider.velocity_at(x), sd.normal, collider.contact, collider.friction);
  }
  return v;
}

ROMP_HD inline Vec3<float> resolve_boundaries(const StepParams& step, const GridNode& node, Vec3<float> v) {
  return resolve_boundaries(step, node.position, node.dx, v);
}

}  // namespace romp::mpm
