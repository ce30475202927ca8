// What a scene prescribes over time (colliders moving rigidly, Dirichlet motions, loads and tractions switched
// on and off), kept on the device, and a substep's tables computed from it there by one launch whose arguments
// carry the time: a substep uploads nothing for them, so it need not wait on the host.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/vec3.h"
#include "kernels/mpm/collider.h"
#include "kernels/mpm/step.h"

namespace romp::mpm {

// At most this many colliders, loads and tractions: which of them act at a time is a bit mask.
inline constexpr int kMostScheduledInputs = 64;

// A Dirichlet group's rigid motion: v(x) = v_lin + ω × (x − pivot(t)), pivot(t) = pivot + v_lin t.
struct ScheduledMotion {
  Vec3<float> pivot, linear_velocity, angular_velocity;
};

// The schedule: each collider at t = 0 (it moves with its velocities), the motions, each load and traction.
struct InputSchedule {
  Span<const ColliderState> colliders;
  Span<const ScheduledMotion> motions;
  Span<const RegionLoad> loads;
  Span<const Vec3<float>> tractions;
};

// Which colliders, loads and tractions act in the substep: bit i for entry i (the host knows their windows).
struct ActiveInputs {
  std::uint64_t colliders = 0, loads = 0, tractions = 0;
};

// The tables of the substep [time, time + dt]: the active colliders, moved to `time`, and the active loads
// fill the front of theirs in the schedule's order (as many as `active` has bits); every Dirichlet motion
// and traction keeps its index, an inactive traction being 0. Tables sized for the whole schedule.
struct InputTables {
  Span<ColliderState> colliders;
  Span<RigidMotion> dirichlet;
  Span<RegionLoad> loads;
  Span<Vec3<float>> tractions;
};
void inputs_at(const Exec& exec, const InputSchedule& schedule, double time, float dt, const ActiveInputs& active,
               const InputTables& out);

}  // namespace romp::mpm
