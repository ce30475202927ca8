// Ballistic particle motion under constant gravity: the backend smoke test behind `romp demo`.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/span.h"

namespace romp {

// Positions and velocities as three planes each (x components, then y, then z), `count` particles.
struct FreeFlightState {
  Span<float> position;  // 3 * count
  Span<float> velocity;  // 3 * count
  Index count = 0;
};

// `steps` symplectic-Euler steps v += g dt, x += v dt. After n steps the exact discrete solution is
// x_n = x_0 + v_0 t + g (t^2 + t dt) / 2 with t = n dt, which `romp demo` checks.
void advance_free_flight(const Exec& exec, const FreeFlightState& state, const float gravity[3], float dt, int steps);

}  // namespace romp
