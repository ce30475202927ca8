// The cube demo and the stage table.
#include "host/demo.h"

#include <fmt/format.h>

#include <chrono>

#include "host/box_lattice.h"
#include "host/full_order_sim.h"
#include "kernels/core/error.h"

namespace romp {
namespace {

constexpr float kSide = 0.5f;
constexpr int kParticlesPerAxis = 10;
constexpr std::int32_t kGridCells = 20;
constexpr float kTimeStep = 5e-4f;

}  // namespace

DemoResult run_cube_demo(const Exec& exec, NclawMaterial material, int substeps) {
  ROMP_CHECK(substeps > 0, "demo --steps must be > 0, got " + std::to_string(substeps));
  FullOrderConfig config;
  config.dx = 1.0f / float(kGridCells);
  config.domain_cells = {kGridCells, kGridCells, kGridCells};
  config.fixed_dt = kTimeStep;
  config.materials = {nclaw_material(material)};

  const Vec3<float> center(0.5f, 0.5f, 0.5f);
  const Vec3<float> low = center - Vec3<float>::constant(0.5f * kSide);
  mpm::ParticleInit init = sample_box_lattice(low, low + Vec3<float>::constant(kSide), kSide / kParticlesPerAxis,
                                              config.materials[0].density);
  const Vec3<float> linear(1.0f, -1.5f, -2.0f), angular(4.0f, 4.0f, 4.0f);
  const Index n = init.count();
  for (Index p = 0; p < n; ++p) {
    const Vec3<float> r(init.x[p] - center[0], init.x[n + p] - center[1], init.x[2 * n + p] - center[2]);
    const Vec3<float> v = linear + cross(angular, r);
    for (int a = 0; a < 3; ++a) init.v[a * n + p] = v[a];
  }

  FullOrderSim sim(exec, config, init);
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < substeps; ++s) sim.substep(kTimeStep);
  DemoResult result;
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.particles = n;
  result.substeps = sim.steps();
  result.simulated_seconds = sim.time();
  result.stage_seconds = sim.stage_seconds();

  const std::vector<float> x = sim.particles().positions_in_initial_order(exec);
  const std::vector<float> v = sim.particles().velocities_in_initial_order(exec);
  double mass = 0.0;
  for (Index p = 0; p < n; ++p) {
    const Vec3<double> xp(x[p], x[n + p], x[2 * n + p]), vp(v[p], v[n + p], v[2 * n + p]);
    result.center_of_mass += double(init.mass[p]) * xp;
    result.kinetic_energy += 0.5 * init.mass[p] * squared_norm(vp);
    mass += init.mass[p];
  }
  result.center_of_mass *= 1.0 / mass;
  return result;
}

std::string stage_table(const std::vector<std::pair<std::string, double>>& stage_seconds) {
  double total = 0.0;
  for (const auto& [stage, seconds] : stage_seconds) total += seconds;
  std::string table = fmt::format("{:<14}{:>12}{:>9}\n", "stage", "seconds", "share");
  for (const auto& [stage, seconds] : stage_seconds)
    table += fmt::format("{:<14}{:>12.4f}{:>8.1f}%\n", stage, seconds, total > 0 ? 100.0 * seconds / total : 0.0);
  table += fmt::format("{:<14}{:>12.4f}\n", "total", total);
  return table;
}

}  // namespace romp
