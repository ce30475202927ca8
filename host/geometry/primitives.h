// Analytic solids for scene bodies: box, sphere, cylinder and capsule (double precision, host only).
#pragma once

#include <string>

#include "host/geometry/bounds.h"
#include "kernels/math/mat3.h"
#include "kernels/math/vec3.h"

namespace romp::geometry {

// Every primitive answers the same three questions: is a point inside (boundary included), which
// axis-aligned box encloses it, and what is its exact volume. validate() throws romp::Error naming
// the offending parameter; Shape calls it, so code holding a Shape never sees an invalid primitive.

// The box centre + rotation · [−half_extents, half_extents].
struct Box {
  Vec3<double> center = Vec3<double>::zero();
  Vec3<double> half_extents = Vec3<double>::zero();
  Mat3<double> rotation = Mat3<double>::identity();  // local-to-world, orthonormal with determinant +1

  bool contains(const Vec3<double>& p) const;
  Bounds bounds() const;
  double analytic_volume() const;
  void validate() const;
  std::string describe() const;
};

struct Sphere {
  Vec3<double> center = Vec3<double>::zero();
  double radius = 0.0;

  bool contains(const Vec3<double>& p) const;
  Bounds bounds() const;
  double analytic_volume() const;
  void validate() const;
  std::string describe() const;
};

// A solid circular cylinder: the points within `radius` of the axis, at most half_height from the
// centre along it.
struct Cylinder {
  Vec3<double> center = Vec3<double>::zero();
  Vec3<double> axis = Vec3<double>(0.0, 0.0, 1.0);  // unit length
  double radius = 0.0;
  double half_height = 0.0;

  bool contains(const Vec3<double>& p) const;
  Bounds bounds() const;
  double analytic_volume() const;
  void validate() const;
  std::string describe() const;
};

// The points within `radius` of the segment [a, b] (a sphere when a = b).
struct Capsule {
  Vec3<double> a = Vec3<double>::zero();
  Vec3<double> b = Vec3<double>::zero();
  double radius = 0.0;

  bool contains(const Vec3<double>& p) const;
  Bounds bounds() const;
  double analytic_volume() const;
  void validate() const;
  std::string describe() const;
};

// "(x, y, z)" with the shortest round-trip digits, for messages.
std::string describe_point(const Vec3<double>& p);

}  // namespace romp::geometry
