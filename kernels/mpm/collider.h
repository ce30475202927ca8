// Analytic colliders (half-space, box, sphere, cylinder), static or in rigid motion, as signed distances.
#pragma once

#include <cstdint>

#include "kernels/core/hd.h"
#include "kernels/math/mat3.h"
#include "kernels/mpm/contact.h"

namespace romp::mpm {

enum class ColliderShape : std::int32_t { HalfSpace = 0, Box = 1, Sphere = 2, Cylinder = 3 };

// A collider at one instant, as the host computes it from the scene for the current time. Shapes are
// defined in a local frame: x_local = rotationᵀ (x - center).
//   HalfSpace: the solid is local y < 0 (its surface passes through `center`, normal = rotation e_y).
//   Box: |x_local| <= half_extents per axis.   Sphere: |x_local| <= half_extents[0].
//   Cylinder: axis local y, radius half_extents[0], |y_local| <= half_extents[1].
struct ColliderState {  // trivially copyable: the host uploads an array of them each substep
  ColliderShape shape = ColliderShape::HalfSpace;
  ContactType contact = ContactType::Sticky;
  float friction = 0.0f;
  Vec3<float> center = Vec3<float>::zero();
  Mat3<float> rotation = Mat3<float>::identity();
  Vec3<float> half_extents = Vec3<float>::zero();
  Vec3<float> linear_velocity = Vec3<float>::zero();   // of the center; the default collider is static
  Vec3<float> angular_velocity = Vec3<float>::zero();  // about the center, world frame

  ROMP_HD Vec3<float> velocity_at(const Vec3<float>& x) const {
    return linear_velocity + cross(angular_velocity, x - center);
  }
};

struct SignedDistance {
  float distance;      // negative inside the solid
  Vec3<float> normal;  // outward unit normal of the solid, world frame
};

ROMP_HD inline SignedDistance local_signed_distance(ColliderShape shape, const Vec3<float>& p,
                                                    const Vec3<float>& half) {
  switch (shape) {
    case ColliderShape::HalfSpace: return {p[1], Vec3<float>(0.0f, 1.0f, 0.0f)};
    case ColliderShape::Sphere: {
      const float r = norm(p);
      return {r - half[0], r > 0.0f ? p * (1.0f / r) : Vec3<float>(0.0f, 1.0f, 0.0f)};
    }
    case ColliderShape::Box: {
      // Distance to the nearest face inside; Euclidean distance to the box outside.
      Vec3<float> q, outside = Vec3<float>::zero();
      int deepest = 0;
      for (int a = 0; a < 3; ++a) {
        q[a] = math::abs(p[a]) - half[a];
        outside[a] = math::max(q[a], 0.0f) * math::sign(p[a]);
        if (q[a] > q[deepest]) deepest = a;
      }
      const float outside_distance = norm(outside);
      if (outside_distance > 0.0f) return {outside_distance, outside * (1.0f / outside_distance)};
      return {q[deepest], Vec3<float>::unit(deepest) * math::sign(p[deepest])};
    }
    case ColliderShape::Cylinder: {
      const float radial = math::sqrt(p[0] * p[0] + p[2] * p[2]);
      const Vec3<float> radial_dir =
          radial > 0.0f ? Vec3<float>(p[0] / radial, 0.0f, p[2] / radial) : Vec3<float>(1.0f, 0.0f, 0.0f);
      const Vec3<float> axial_dir(0.0f, math::sign(p[1]), 0.0f);
      const float dr = radial - half[0], dy = math::abs(p[1]) - half[1];
      if (dr > 0.0f && dy > 0.0f) {
        const float d = math::sqrt(dr * dr + dy * dy);
        return {d, (radial_dir * dr + axial_dir * dy) * (1.0f / d)};
      }
      return dr > dy ? SignedDistance{dr, radial_dir} : SignedDistance{dy, axial_dir};
    }
  }
  return {1.0f, Vec3<float>(0.0f, 1.0f, 0.0f)};
}

ROMP_HD inline SignedDistance signed_distance(const ColliderState& c, const Vec3<float>& x) {
  const Vec3<float> local = transpose(c.rotation) * (x - c.center);
  SignedDistance sd = local_signed_distance(c.shape, local, c.half_extents);
  sd.normal = c.rotation * sd.normal;
  return sd;
}

}  // namespace romp::mpm
