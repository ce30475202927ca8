// Mechanical energy from a read-back of the particles, summed in double.
#include "host/analysis/mechanical_energy.h"

#include <vector>

namespace romp::analysis {

double mechanical_energy(engine::FullOrderSim& sim, const mpm::ParticleInit& init, const Vec3<float>& origin) {
  const Exec& exec = sim.exec();
  const std::vector<float> x = sim.particles().positions_in_initial_order(exec);
  const std::vector<float> v = sim.particles().velocities_in_initial_order(exec);
  const std::vector<float> F = sim.particles().deformation_gradients_in_initial_order(exec);
  const Vec3<float> gravity = sim.config().gravity;
  const std::size_t n = std::size_t(init.count());
  double energy = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    Vec3<float> height, velocity;
    Mat3<float> Fp;
    for (int a = 0; a < 3; ++a) {
      height[a] = x[a * n + p] - origin[a];
      velocity[a] = v[a * n + p];
    }
    for (int k = 0; k < 9; ++k) Fp(k / 3, k % 3) = F[k * n + p];
    const material::MaterialParams<float>& params = sim.config().materials[std::size_t(init.material[p])].params;
    const double mass = init.mass[p];
    energy += 0.5 * mass * double(squared_norm(velocity)) - mass * double(dot(gravity, height)) +
              double(init.volume0[p]) * double(material::energy_density(params, Fp));
  }
  return energy;
}

}  // namespace romp::analysis
