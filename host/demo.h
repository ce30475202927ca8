// `romp demo`: a particle cloud in free flight on the selected backend, checked against the exact answer.
#pragma once

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"

namespace romp {

struct DemoResult {
  Index particles = 0;
  int steps = 0;
  double seconds = 0.0;           // kernel time, measured with a DeviceTimer
  double max_position_error = 0;  // largest |x - x_exact| over all particles and axes, in metres
  double particle_steps_per_second() const { return double(particles) * steps / seconds; }
};

DemoResult run_free_flight_demo(const Exec& exec, Index particles, int steps);

}  // namespace romp
