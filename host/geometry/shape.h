// Shape: any solid a scene body can be made of (a primitive or a closed mesh), always valid.
#pragma once

#include <string>
#include <variant>

#include "host/geometry/bounds.h"
#include "host/geometry/mesh_solid.h"
#include "host/geometry/primitives.h"

namespace romp::geometry {

class Shape {
 public:
  using Variant = std::variant<Box, Sphere, Cylinder, Capsule, MeshSolid>;

  // Implicit, so a primitive can be passed wherever a Shape is expected. The primitives are
  // validated here (romp::Error on a bad parameter); a MeshSolid validated itself when built.
  Shape(const Box& box);
  Shape(const Sphere& sphere);
  Shape(const Cylinder& cylinder);
  Shape(const Capsule& capsule);
  Shape(MeshSolid mesh);

  bool contains(const Vec3<double>& p) const {
    return std::visit([&p](const auto& shape) { return shape.contains(p); }, variant_);
  }
  Bounds bounds() const;
  double analytic_volume() const;
  std::string describe() const;
  const Variant& variant() const { return variant_; }

 private:
  Variant variant_;
};

}  // namespace romp::geometry
