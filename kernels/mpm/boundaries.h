// The velocity constraints of the domain walls and colliders at a point: what the grid update applies
// to every node, and enriched domain corners (which move on their own) to themselves.
#pragma once

#include "kernels/core/hd.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/contact.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

// v after the walls (points within wall_cells cells of a domain face) and the colliders that
// contain x. For a grid node x = index × dx, so the wall test is the node-index test exactly (float
// products of integers by one dx keep their order).
ROMP_HD_INLINE Vec3<float> apply_boundaries(const StepParams& step, const Vec3<float>& x, float dx, Vec3<float> v) {
  const Vec3<float> at_rest = Vec3<float>::zero();
  for (int a = 0; a < 3; ++a) {
    if (x[a] < float(step.wall_cells) * dx)
      v = resolve_contact(v, at_rest, Vec3<float>::unit(a), step.wall_contact, step.wall_friction);
    if (x[a] > float(step.domain_cells[a] - step.wall_cells) * dx)
      v = resolve_contact(v, at_rest, -Vec3<float>::unit(a), step.wall_contact, step.wall_friction);
  }
  for (Index c = 0; c < step.colliders.size(); ++c) {
    const ColliderState& collider = step.colliders[c];
    const SignedDistance sd = signed_distance(collider, x);
    if (sd.distance < 0.0f) v = resolve_contact(v, collider.velocity_at(x), sd.normal, collider.contact, collider.friction);
  }
  return v;
}

}  // namespace romp::mpm
