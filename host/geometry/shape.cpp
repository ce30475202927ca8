// Shape: validation on construction and dispatch to the held solid.
#include "host/geometry/shape.h"

#include <utility>

namespace romp::geometry {

Shape::Shape(const Box& box) : variant_(box) { box.validate(); }
Shape::Shape(const Sphere& sphere) : variant_(sphere) { sphere.validate(); }
Shape::Shape(const Cylinder& cylinder) : variant_(cylinder) { cylinder.validate(); }
Shape::Shape(const Capsule& capsule) : variant_(capsule) { capsule.validate(); }
Shape::Shape(MeshSolid mesh) : variant_(std::move(mesh)) {}

Bounds Shape::bounds() const {
  return std::visit([](const auto& shape) { return shape.bounds(); }, variant_);
}

double Shape::analytic_volume() const {
  return std::visit([](const auto& shape) { return shape.analytic_volume(); }, variant_);
}

std::string Shape::describe() const {
  return std::visit([](const auto& shape) { return shape.describe(); }, variant_);
}

}  // namespace romp::geometry
