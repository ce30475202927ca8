// Mechanical energy from a read-back of the particles: the frame totals of romp's outputs
// (host/run/frame_outputs.h), with heights measured from the caller's origin.
#include "host/analysis/mechanical_energy.h"

#include <utility>

#include "host/run/frame_outputs.h"
#include "nn/io/snapshot_layout.h"

namespace romp::analysis {

double mechanical_energy(engine::FullOrderSim& sim, const mpm::ParticleInit& init, const Vec3<float>& origin) {
  const Exec& exec = sim.exec();
  const mpm::ParticleSet& particles = std::as_const(sim).particles();
  io::FrameData frame;
  frame.x = particles.positions_in_initial_order(exec);
  frame.v = particles.velocities_in_initial_order(exec);
  frame.F = particles.deformation_gradients_in_initial_order(exec);
  // No C: the particles' APIC spin is momentum, not energy the totals count.
  run::FrameOutputs(io::kFieldX, sim.config(), init).add_to(frame);
  const io::FrameTotals& totals = *frame.totals;
  // The totals' potential −Σ m g·x is zero at the coordinate origin; from `origin` it is −Σ m g·(x − o).
  double mass = 0.0;
  for (const float m : init.mass) mass += m;
  const Vec3<float>& g = sim.config().gravity;
  const double shift = mass * (double(g[0]) * origin[0] + double(g[1]) * origin[1] + double(g[2]) * origin[2]);
  return totals.kinetic_energy + totals.elastic_energy + totals.gravitational_energy + shift;
}

}  // namespace romp::analysis
