// Velocity of a grid node in contact with a boundary: sticky, slip, or separating slip with Coulomb friction.
#pragma once

#include <cstdint>

#include "kernels/core/hd.h"
#include "kernels/math/vec3.h"

namespace romp::mpm {

enum class ContactType : std::int32_t {
  Sticky = 0,    // the node moves with the boundary
  Slip = 1,      // the normal relative velocity is removed both ways; tangential motion is free
  Separate = 2,  // only approach is removed; the tangential velocity loses up to friction x approach speed
};

// `normal` is the unit normal pointing away from the boundary into the material; `body` is the
// boundary's velocity at the node.
template <class T>
ROMP_HD Vec3<T> resolve_contact(const Vec3<T>& v, const Vec3<T>& body, const Vec3<T>& normal, ContactType type,
                                T friction) {
  if (type == ContactType::Sticky) return body;
  const Vec3<T> relative = v - body;
  const T approach = dot(relative, normal);
  if (type == ContactType::Separate && approach >= T(0)) return v;
  Vec3<T> tangential = relative - approach * normal;
  if (type == ContactType::Separate) {
    // Coulomb: the tangential speed drops by friction times the normal speed that was removed.
    const T speed = norm(tangential);
    const T kept = speed > T(0) ? math::max(T(0), T(1) + friction * approach / speed) : T(0);
    tangential *= kept;
  }
  return body + tangential;
}

}  // namespace romp::mpm
