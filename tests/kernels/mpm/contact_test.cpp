// Boundary conditions at grid nodes: contact types and the colliders' signed distances.
#include <gtest/gtest.h>

#include <cmath>

#include "kernels/math/rotation.h"
#include "kernels/mpm/collider.h"
#include "kernels/mpm/contact.h"

namespace romp::mpm {
namespace {

using V = Vec3<float>;
const V kUp(0.0f, 1.0f, 0.0f);

void expect_near(const V& a, const V& b, float tolerance = 1e-6f) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], tolerance) << "component " << k;
}

TEST(Contact, StickyNodeMovesWithTheBoundary) {
  expect_near(resolve_contact(V(1, -2, 3), V(0.5f, 0, 0), kUp, ContactType::Sticky, 0.0f), V(0.5f, 0, 0));
}

TEST(Contact, SlipRemovesTheNormalVelocityBothWays) {
  expect_near(resolve_contact(V(1, -2, 3), V::zero(), kUp, ContactType::Slip, 0.0f), V(1, 0, 3));
  expect_near(resolve_contact(V(1, 2, 3), V::zero(), kUp, ContactType::Slip, 0.0f), V(1, 0, 3));
}

TEST(Contact, SeparatingNodeIsLeftAlone) {
  expect_near(resolve_contact(V(1, 2, 3), V::zero(), kUp, ContactType::Separate, 0.5f), V(1, 2, 3));
}

TEST(Contact, ApproachIsRemovedAndCoulombFrictionSlowsTheSlide) {
  // Approach speed 1, tangential speed 5, μ = 0.4: the slide loses 0.4.
  expect_near(resolve_contact(V(3, -1, 4), V::zero(), kUp, ContactType::Separate, 0.4f), V(3, -0, 4) * (4.6f / 5.0f));
  // Friction strong enough to stop the slide stops it, and never reverses it.
  expect_near(resolve_contact(V(0.3f, -1, 0.4f), V::zero(), kUp, ContactType::Separate, 2.0f), V::zero());
}

TEST(Contact, RelativeVelocityIsWhatCounts) {
  // A floor moving up at 2 m/s meets a node falling at 1 m/s: the node leaves with the floor.
  expect_near(resolve_contact(V(0, -1, 0), V(0, 2, 0), kUp, ContactType::Separate, 0.0f), V(0, 2, 0));
}

ColliderState collider(ColliderShape shape, const V& half) {
  ColliderState c;
  c.shape = shape;
  c.center = V(0.5f, 0.5f, 0.5f);
  c.half_extents = half;
  return c;
}

TEST(Collider, SignedDistancesOfEachShape) {
  const ColliderState sphere = collider(ColliderShape::Sphere, V(0.2f, 0, 0));
  EXPECT_NEAR(signed_distance(sphere, V(0.5f, 0.9f, 0.5f)).distance, 0.2f, 1e-6f);
  EXPECT_NEAR(signed_distance(sphere, V(0.5f, 0.6f, 0.5f)).distance, -0.1f, 1e-6f);
  expect_near(signed_distance(sphere, V(0.5f, 0.9f, 0.5f)).normal, kUp);

  const ColliderState box = collider(ColliderShape::Box, V(0.1f, 0.2f, 0.3f));
  EXPECT_NEAR(signed_distance(box, V(0.5f, 0.75f, 0.5f)).distance, 0.05f, 1e-6f);
  EXPECT_NEAR(signed_distance(box, V(0.45f, 0.5f, 0.5f)).distance, -0.05f, 1e-6f);  // nearest face: x
  expect_near(signed_distance(box, V(0.45f, 0.5f, 0.5f)).normal, V(-1, 0, 0));
  EXPECT_NEAR(signed_distance(box, V(0.63f, 0.74f, 0.5f)).distance, 0.05f, 1e-6f);  // off the edge: 3-4-5

  const ColliderState cylinder = collider(ColliderShape::Cylinder, V(0.1f, 0.2f, 0));
  EXPECT_NEAR(signed_distance(cylinder, V(0.65f, 0.5f, 0.5f)).distance, 0.05f, 1e-6f);
  EXPECT_NEAR(signed_distance(cylinder, V(0.5f, 0.65f, 0.5f)).distance, -0.05f, 1e-6f);
  expect_near(signed_distance(cylinder, V(0.5f, 0.65f, 0.5f)).normal, kUp);
}

TEST(Collider, TiltedHalfSpaceUsesItsRotatedNormal) {
  ColliderState ground = collider(ColliderShape::HalfSpace, V::zero());
  ground.rotation = rotation_from_vector(V(0, 0, 0.5235987756f));  // 30° about z
  const SignedDistance sd = signed_distance(ground, V(0.5f, 0.6f, 0.5f));
  expect_near(sd.normal, V(-0.5f, 0.8660254f, 0.0f));
  EXPECT_NEAR(sd.distance, 0.1f * 0.8660254f, 1e-6f);
}

TEST(Collider, RigidMotionGivesTheVelocityOfEachPoint) {
  ColliderState spinning = collider(ColliderShape::Box, V(0.1f, 0.1f, 0.1f));
  spinning.linear_velocity = V(1, 0, 0);
  spinning.angular_velocity = V(0, 0, 2);
  expect_near(spinning.velocity_at(V(0.5f, 0.6f, 0.5f)), V(1.0f - 0.2f, 0, 0));
}

}  // namespace
}  // namespace romp::mpm
