// The free-flight demo: seeds a unit cube of particles with a spin, flies it 1 s, compares with the
// closed-form symplectic-Euler solution.
#include "host/demo.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/device_timer.h"
#include "kernels/core/error.h"
#include "kernels/particles/free_flight.h"

namespace romp {
namespace {

constexpr float kGravity[3] = {0.0f, -9.81f, 0.0f};  // SI, along -y

}  // namespace

DemoResult run_free_flight_demo(const Exec& exec, Index particles, int steps) {
  ROMP_CHECK(particles > 0, "demo --particles must be > 0, got " + std::to_string(particles));
  ROMP_CHECK(steps > 0, "demo --steps must be > 0, got " + std::to_string(steps));
  const float dt = 1.0f / float(steps);  // one simulated second

  // A cube of side 1 on a lattice, rotating about z at 1 rad/s around its centre, moving at +1 m/s in x.
  const Index side = std::max<Index>(1, Index(std::cbrt(double(particles))));
  std::vector<float> x0(3 * particles), v0(3 * particles);
  for (Index i = 0; i < particles; ++i) {
    const float p[3] = {float(i % side) / side, float(i / side % side) / side, float(i / (side * side)) / side};
    for (int a = 0; a < 3; ++a) x0[a * particles + i] = p[a];
    v0[0 * particles + i] = 1.0f - (p[1] - 0.5f);
    v0[1 * particles + i] = p[0] - 0.5f;
    v0[2 * particles + i] = 0.0f;
  }

  DeviceBuffer<float> position = DeviceBuffer<float>::from_host(exec.backend, x0, exec.stream);
  DeviceBuffer<float> velocity = DeviceBuffer<float>::from_host(exec.backend, v0, exec.stream);
  const FreeFlightState state{position.span(), velocity.span(), particles};

  DeviceTimer timer(exec);
  timer.start();
  advance_free_flight(exec, state, kGravity, dt, steps);
  DemoResult result;
  result.seconds = timer.stop();
  result.particles = particles;
  result.steps = steps;

  const std::vector<float> x = position.to_host(exec.stream);
  const double t = double(dt) * steps;
  for (Index k = 0; k < 3 * particles; ++k) {
    const int axis = int(k / particles);
    const double exact = double(x0[k]) + double(v0[k]) * t + 0.5 * kGravity[axis] * (t * t + t * dt);
    result.max_position_error = std::max(result.max_position_error, std::abs(double(x[k]) - exact));
  }
  return result;
}

}  // namespace romp
