// inputs_at: one thread per entry of the four tables.
#include "kernels/mpm/input_schedule.h"

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/math/rotation.h"

namespace romp::mpm {
namespace {

// The index of the k-th set bit of `mask` (k from 0; the mask has more than k).
ROMP_HD_INLINE int set_bit(std::uint64_t mask, int k) {
  for (int i = 0; i < kMostScheduledInputs; ++i) {
    if (!((mask >> i) & 1u)) continue;
    if (k-- == 0) return i;
  }
  return -1;
}

struct InputsAt {
  InputSchedule schedule;
  SubstepTime start;
  float dt;
  ActiveInputs active;
  InputTables out;

  ROMP_HD void operator()(Index t) const {
    // Positions as the host computed them: time rounded to float first, then the products.
    const float time = float(start.at(dt));
    if (t < out.colliders.size()) {
      ColliderState c = schedule.colliders[set_bit(active.colliders, int(t))];
      c.center = c.center + time * c.linear_velocity;
      c.rotation = rotation_from_vector(time * c.angular_velocity) * c.rotation;
      out.colliders[t] = c;
      return;
    }
    t -= out.colliders.size();
    if (t < out.dirichlet.size()) {
      const ScheduledMotion& m = schedule.motions[t];
      out.dirichlet[t] = RigidMotion{m.pivot + time * m.linear_velocity, m.linear_velocity, m.angular_velocity,
                                     rotation_from_vector(dt * m.angular_velocity)};
      return;
    }
    t -= out.dirichlet.size();
    if (t < out.loads.size()) {
      out.loads[t] = schedule.loads[set_bit(active.loads, int(t))];
      return;
    }
    t -= out.loads.size();
    out.tractions[t] = (active.tractions >> t) & 1u ? schedule.tractions[t] : Vec3<float>::zero();
  }
};

}  // namespace

void inputs_at(const Exec& exec, const InputSchedule& schedule, const SubstepTime& time, float dt,
               const ActiveInputs& active, const InputTables& out) {
  ROMP_CHECK(schedule.colliders.size() <= kMostScheduledInputs && schedule.loads.size() <= kMostScheduledInputs &&
                 schedule.tractions.size() <= kMostScheduledInputs,
             "inputs_at: at most 64 colliders, loads and tractions");
  ROMP_CHECK(out.colliders.size() == active_entries(active.colliders) &&
                 out.loads.size() == active_entries(active.loads) && out.dirichlet.size() == schedule.motions.size() &&
                 out.tractions.size() == schedule.tractions.size(),
             "inputs_at: a table entry for each active collider and load, each motion and each traction");
  const auto within = [](std::uint64_t mask, Index entries) {
    return entries == kMostScheduledInputs || (mask >> entries) == 0;
  };
  ROMP_CHECK(within(active.colliders, schedule.colliders.size()) && within(active.loads, schedule.loads.size()) &&
                 within(active.tractions, schedule.tractions.size()),
             "inputs_at: an active entry the schedule lacks");
  const Index entries = out.colliders.size() + out.dirichlet.size() + out.loads.size() + out.tractions.size();
  for_each(exec, entries, InputsAt{schedule, time, dt, active, out});
}

}  // namespace romp::mpm
