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
  bool operator==(const ActiveInputs& other) const {
    return colliders == other.colliders && loads == other.loads && tractions == other.tractions;
  }
  bool operator!=(const ActiveInputs& other) const { return !(*this == other); }
};

// The entries a mask makes active (its set bits): the rows of their table that inputs_at fills.
inline Index active_entries(std::uint64_t mask) {
  Index count = 0;
  for (; mask; mask &= mask - 1) ++count;
  return count;
}

// The tables of the substep [time, time + dt]: the active colliders, moved to `time`, and the active loads
// fill the front of theirs in the schedule's order (as many as `active` has bits); every Dirichlet motion
// and traction keeps its index, an inactive traction being 0. Tables sized for the whole schedule.
struct InputTables {
  Span<ColliderState> colliders;
  Span<RigidMotion> dirichlet;
  Span<RegionLoad> loads;
  Span<Vec3<float>> tractions;
};
// The start of a substep: `time`, or where `frame_start` is given, frame_start[0] (a value on the device, so a
// CUDA graph of a frame's substeps serves every frame) plus `substep` steps of dt, summed one at a time in
// double as the host's clock sums them.
struct SubstepTime {
  double time = 0.0;
  Span<const double> frame_start;
  int substep = 0;

  SubstepTime(double t) : time(t) {}  // NOLINT(google-explicit-constructor): a time is a substep's time
  SubstepTime(Span<const double> start, int k) : frame_start(start), substep(k) {}
  ROMP_HD double at(float dt) const {
    if (frame_start.empty()) return time;
    double t = frame_start[0];
    for (int k = 0; k < substep; ++k) t += double(dt);
    return t;
  }
};

void inputs_at(const Exec& exec, const InputSchedule& schedule, const SubstepTime& time, float dt,
               const ActiveInputs& active, const InputTables& out);

}  // namespace romp::mpm
