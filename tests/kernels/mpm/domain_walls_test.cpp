// The domain walls both MPMs share: the frictionless wall mask and the clamp into the domain's band.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "kernels/mpm/contact.h"
#include "kernels/mpm/domain_walls.h"

namespace romp::mpm {
namespace {

using V = Vec3<float>;
constexpr float kDx = 0.1f;

Domain walled_box(ContactType contact) {
  Domain domain;
  for (int a = 0; a < 3; ++a) domain.cells[a] = 12;
  domain.wall_cells = 3;
  domain.wall_contact = contact;
  return domain;
}

// The rule as resolve_contact states it: each face the point is near, one after the other, at rest and
// with zero friction.
V face_by_face(const Domain& domain, const V& x, V v) {
  for (int a = 0; a < 3; ++a) {
    if (domain.near_low_wall(x[a], kDx)) v = resolve_contact(v, V::zero(), V::unit(a), domain.wall_contact, 0.0f);
    if (domain.near_high_wall(a, x[a], kDx)) v = resolve_contact(v, V::zero(), -V::unit(a), domain.wall_contact, 0.0f);
  }
  return v;
}

TEST(DomainWalls, KeepMaskIsFrictionlessContactFaceByFace) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> node(0, 12);
  std::uniform_real_distribution<float> speed(-2.0f, 2.0f);
  for (const ContactType contact : {ContactType::Sticky, ContactType::Slip, ContactType::Separate}) {
    const Domain domain = walled_box(contact);
    for (int trial = 0; trial < 2000; ++trial) {
      const V x(float(node(rng)) * kDx, float(node(rng)) * kDx, float(node(rng)) * kDx);
      const V v(speed(rng), speed(rng), speed(rng));
      const V masked = hadamard(wall_keep_mask(domain, x, kDx, v), v);
      const V expected = face_by_face(domain, x, v);
      for (int a = 0; a < 3; ++a)
        EXPECT_EQ(masked[a], expected[a]) << "contact " << int(contact) << ", trial " << trial;
    }
  }
}

TEST(DomainWalls, NodeTestsAreIndexTests) {
  const Domain domain = walled_box(ContactType::Separate);
  for (int i = 0; i <= 12; ++i) {
    EXPECT_EQ(domain.near_low_wall(float(i) * kDx, kDx), i < 3) << i;
    EXPECT_EQ(domain.near_high_wall(0, float(i) * kDx, kDx), i > 9) << i;
    EXPECT_EQ(domain.near_low_wall(double(i) * 0.1, 0.1), i < 3) << i;
  }
}

TEST(DomainWalls, ClampKeepsPositionsInTheBandAndSendsNaNToItsLowBound) {
  const Domain domain = walled_box(ContactType::Separate);
  const float low = kDomainMarginCells * kDx, high = (12.0f - kDomainMarginCells) * kDx;
  EXPECT_EQ(clamp_to_domain(domain, 0.5f, 0, kDx), 0.5f);
  EXPECT_EQ(clamp_to_domain(domain, -3.0f, 1, kDx), low);
  EXPECT_EQ(clamp_to_domain(domain, 7.0f, 2, kDx), high);
  EXPECT_EQ(clamp_to_domain(domain, std::numeric_limits<float>::infinity(), 0, kDx), high);
  EXPECT_EQ(clamp_to_domain(domain, std::numeric_limits<float>::quiet_NaN(), 0, kDx), low);
}

}  // namespace
}  // namespace romp::mpm
