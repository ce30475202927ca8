// Free flight kernel: one functor, launched by for_each on the CPU or the GPU.
#include "kernels/particles/free_flight.h"

#include "kernels/core/for_each.h"

namespace romp {
namespace {

struct FreeFlightStep {
  Span<float> position;
  Span<float> velocity;
  Index count;
  float gx, gy, gz;
  float dt;

  ROMP_HD void operator()(Index i) const {
    const float g[3] = {gx, gy, gz};
    for (int axis = 0; axis < 3; ++axis) {
      const Index k = axis * count + i;
      velocity[k] += g[axis] * dt;
      position[k] += velocity[k] * dt;
    }
  }
};

}  // namespace

void advance_free_flight(const Exec& exec, const FreeFlightState& state, const float gravity[3], float dt, int steps) {
  const FreeFlightStep step{state.position, state.velocity, state.count, gravity[0], gravity[1], gravity[2], dt};
  for (int s = 0; s < steps; ++s) for_each(exec, state.count, step);
}

}  // namespace romp
