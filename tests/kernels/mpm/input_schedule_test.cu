// inputs_at: the substep's colliders, Dirichlet motions, loads and tractions computed on the device from the
// scene's schedule, against the same formulas on the host.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/memory.h"
#include "kernels/math/rotation.h"
#include "kernels/mpm/input_schedule.h"
#include "tests/support/test_exec.h"

namespace romp::mpm {
namespace {

ColliderState spinning_box(float offset) {
  ColliderState c;
  c.shape = ColliderShape::Box;
  c.center = Vec3<float>(0.5f + offset, 0.3f, 0.5f);
  c.half_extents = Vec3<float>(0.2f, 0.05f, 0.2f);
  c.linear_velocity = Vec3<float>(0.1f, -0.2f, 0.05f + offset);
  c.angular_velocity = Vec3<float>(0.0f, 3.0f, 1.0f - offset);
  return c;
}

RegionLoad load(float acceleration) {
  RegionLoad l;
  l.acceleration = Vec3<float>(acceleration, 0.0f, 0.0f);
  return l;
}

void expect_equal(const Vec3<float>& a, const Vec3<float>& b) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a[i], b[i]) << i;
}

TEST(InputsAt, MovesTheActiveCollidersAndKeepsEveryMotionAndTraction) {
  const Exec& exec = test::exec();
  const Backend backend = exec.backend;
  const std::vector<ColliderState> colliders = {spinning_box(0.0f), spinning_box(0.1f), spinning_box(0.2f)};
  const std::vector<ScheduledMotion> motions = {
      {Vec3<float>(0.1f, 0.2f, 0.3f), Vec3<float>(0.0f, 1.0f, 0.0f), Vec3<float>(2.0f, 0.0f, 0.5f)}};
  const std::vector<RegionLoad> loads = {load(1.0f), load(2.0f), load(3.0f)};
  const std::vector<Vec3<float>> tractions = {Vec3<float>(1.0f, 0.0f, 0.0f), Vec3<float>(0.0f, 2.0f, 0.0f)};
  const auto collider_schedule = DeviceBuffer<ColliderState>::from_host(backend, colliders);
  const auto motion_schedule = DeviceBuffer<ScheduledMotion>::from_host(backend, motions);
  const auto load_schedule = DeviceBuffer<RegionLoad>::from_host(backend, loads);
  const auto traction_schedule = DeviceBuffer<Vec3<float>>::from_host(backend, tractions);
  DeviceBuffer<ColliderState> collider_table(backend, 3);
  DeviceBuffer<RigidMotion> motion_table(backend, 1);
  DeviceBuffer<RegionLoad> load_table(backend, 3);
  DeviceBuffer<Vec3<float>> traction_table(backend, 2);

  // Colliders 0 and 2, load 1 and traction 1 act.
  const ActiveInputs active{0b101, 0b010, 0b10};
  const double time = 0.37;
  const float dt = 1e-3f;
  const memory::Traffic before = memory::traffic();
  inputs_at(exec, {collider_schedule.span(), motion_schedule.span(), load_schedule.span(), traction_schedule.span()},
            time, dt, active,
            {collider_table.prefix(2), motion_table.span(), load_table.prefix(1), traction_table.span()});
  EXPECT_EQ(memory::traffic().uploads, before.uploads);

  const std::vector<ColliderState> moved = download(backend, collider_table.prefix(2));
  const float t = float(time);
  for (int k = 0; k < 2; ++k) {
    const ColliderState& c = colliders[std::size_t(2 * k)];
    expect_equal(moved[std::size_t(k)].center, c.center + t * c.linear_velocity);
    const Mat3<float> rotation = rotation_from_vector(t * c.angular_velocity) * c.rotation;
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) EXPECT_FLOAT_EQ(moved[std::size_t(k)].rotation(r, col), rotation(r, col));
    expect_equal(moved[std::size_t(k)].half_extents, c.half_extents);
  }
  const RigidMotion motion = download(backend, motion_table.span())[0];
  expect_equal(motion.pivot, motions[0].pivot + t * motions[0].linear_velocity);
  expect_equal(motion.angular_velocity, motions[0].angular_velocity);
  const Mat3<float> step_rotation = rotation_from_vector(dt * motions[0].angular_velocity);
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col) EXPECT_FLOAT_EQ(motion.step_rotation(r, col), step_rotation(r, col));
  expect_equal(download(backend, load_table.prefix(1))[0].acceleration, loads[1].acceleration);
  const std::vector<Vec3<float>> acting = traction_table.to_host();
  expect_equal(acting[0], Vec3<float>::zero());
  expect_equal(acting[1], tractions[1]);
}

TEST(InputsAt, TablesThatDoNotMatchTheActiveEntriesAreRefused) {
  const Exec& exec = test::exec();
  const auto colliders = DeviceBuffer<ColliderState>::from_host(exec.backend, {spinning_box(0.0f)});
  DeviceBuffer<ColliderState> table(exec.backend, 1);
  // One collider active, a table for none; and an active bit past the schedule.
  EXPECT_THROW(inputs_at(exec, {colliders.span(), {}, {}, {}}, 0.0, 1e-3f, {1, 0, 0}, {table.prefix(0), {}, {}, {}}),
               Error);
  EXPECT_THROW(inputs_at(exec, {colliders.span(), {}, {}, {}}, 0.0, 1e-3f, {2, 0, 0}, {table.span(), {}, {}, {}}),
               Error);
}

}  // namespace
}  // namespace romp::mpm
