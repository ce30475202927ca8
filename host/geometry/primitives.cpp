// Inside tests, bounds, volumes and validation of the analytic primitives.
#include "host/geometry/primitives.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "kernels/core/error.h"

namespace romp::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;
// How far RᵀR may be from I: rotations typed into a scene file with 7 significant digits pass,
// a shear or a scaled matrix does not.
constexpr double kOrthonormalTolerance = 1e-6;

void check_positive(double value, const char* parameter, const std::string& shape) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw Error(fmt::format("{}: {} must be finite and > 0, got {}", shape, parameter, value));
}

void check_finite(const Vec3<double>& v, const char* parameter, const std::string& shape) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(v[a]))
      throw Error(fmt::format("{}: {} must be finite, got {}", shape, parameter, describe_point(v)));
}

Bounds ball_bounds(const Vec3<double>& center, double radius) {
  return {center - Vec3<double>::constant(radius), center + Vec3<double>::constant(radius)};
}

}  // namespace

std::string describe_point(const Vec3<double>& p) { return fmt::format("({}, {}, {})", p[0], p[1], p[2]); }

bool Box::contains(const Vec3<double>& p) const {
  const Vec3<double> local = transpose(rotation) * (p - center);
  for (int a = 0; a < 3; ++a)
    if (std::abs(local[a]) > half_extents[a]) return false;
  return true;
}

Bounds Box::bounds() const {
  Vec3<double> reach = Vec3<double>::zero();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) reach[r] += std::abs(rotation(r, c)) * half_extents[c];
  return {center - reach, center + reach};
}

double Box::analytic_volume() const { return 8.0 * half_extents[0] * half_extents[1] * half_extents[2]; }

void Box::validate() const {
  const std::string shape = describe();
  check_finite(center, "center", shape);
  check_positive(half_extents[0], "half extent x", shape);
  check_positive(half_extents[1], "half extent y", shape);
  check_positive(half_extents[2], "half extent z", shape);
  const double error = max_abs(transpose_times(rotation, rotation) - Mat3<double>::identity());
  if (!(error <= kOrthonormalTolerance) || !(determinant(rotation) > 0.0))
    throw Error(
        fmt::format("{}: rotation is not a rotation matrix (max |RᵀR − I| = {:.3g}, det R = {:.6g}); "
                    "it must be orthonormal with determinant +1",
                    shape, error, determinant(rotation)));
}

std::string Box::describe() const {
  return fmt::format("box of half extents {} at {}", describe_point(half_extents), describe_point(center));
}

bool Sphere::contains(const Vec3<double>& p) const { return squared_norm(p - center) <= radius * radius; }

Bounds Sphere::bounds() const { return ball_bounds(center, radius); }

double Sphere::analytic_volume() const { return 4.0 / 3.0 * kPi * radius * radius * radius; }

void Sphere::validate() const {
  check_finite(center, "center", describe());
  check_positive(radius, "radius", describe());
}

std::string Sphere::describe() const {
  return fmt::format("sphere of radius {} at {}", radius, describe_point(center));
}

bool Cylinder::contains(const Vec3<double>& p) const {
  const Vec3<double> d = p - center;
  const double along = dot(d, axis);
  return std::abs(along) <= half_height && squared_norm(d - along * axis) <= radius * radius;
}

Bounds Cylinder::bounds() const {
  // Along world axis k the end discs reach radius·sin(angle between the axis and e_k) beyond the
  // end centres, which sit half_height·|axis_k| from the centre.
  Vec3<double> reach;
  for (int k = 0; k < 3; ++k)
    reach[k] = half_height * std::abs(axis[k]) + radius * std::sqrt(std::max(0.0, 1.0 - axis[k] * axis[k]));
  return {center - reach, center + reach};
}

double Cylinder::analytic_volume() const { return kPi * radius * radius * 2.0 * half_height; }

void Cylinder::validate() const {
  const std::string shape = describe();
  check_finite(center, "center", shape);
  check_finite(axis, "axis", shape);
  check_positive(radius, "radius", shape);
  check_positive(half_height, "half height", shape);
  if (!(std::abs(norm(axis) - 1.0) <= kOrthonormalTolerance))
    throw Error(fmt::format("{}: axis must be a unit vector, its length is {}", shape, norm(axis)));
}

std::string Cylinder::describe() const {
  return fmt::format("cylinder of radius {} and height {} along {} at {}", radius, 2.0 * half_height,
                     describe_point(axis), describe_point(center));
}

bool Capsule::contains(const Vec3<double>& p) const {
  const Vec3<double> segment = b - a;
  const double length2 = squared_norm(segment);
  const double t = length2 > 0.0 ? std::clamp(dot(p - a, segment) / length2, 0.0, 1.0) : 0.0;
  return squared_norm(p - (a + t * segment)) <= radius * radius;
}

Bounds Capsule::bounds() const {
  Bounds around_a = ball_bounds(a, radius), around_b = ball_bounds(b, radius);
  for (int k = 0; k < 3; ++k) {
    around_a.low[k] = std::min(around_a.low[k], around_b.low[k]);
    around_a.high[k] = std::max(around_a.high[k], around_b.high[k]);
  }
  return around_a;
}

double Capsule::analytic_volume() const { return kPi * radius * radius * (norm(b - a) + 4.0 / 3.0 * radius); }

void Capsule::validate() const {
  check_finite(a, "end a", describe());
  check_finite(b, "end b", describe());
  check_positive(radius, "radius", describe());
}

std::string Capsule::describe() const {
  return fmt::format("capsule of radius {} from {} to {}", radius, describe_point(a), describe_point(b));
}

}  // namespace romp::geometry
