// The implicit step through FullOrderSim: a stiff cube dropped on the floor stays stable and loses
// energy at several times the explicit step limit, where the explicit step blows up; a CG that
// cannot converge keeps the explicit velocities and is counted. Runs on the binary's backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "host/analysis/mechanical_energy.h"
#include "host/engine/full_order_sim.h"
#include "host/engine/step_inputs.h"
#include "kernels/material/lame.h"
#include "kernels/math/rotation.h"
#include "tests/host/mpm_test_scenes.h"
#include "tests/support/test_exec.h"

namespace romp {
namespace {

constexpr float kDx = 1.0f / 32.0f;
constexpr int kCells = 32;
constexpr float kDensity = 1000.0f;
const material::Lame<float> kStiff = material::lame_from_young_poisson(1e7f, 0.3f);
// Δt over the explicit limit dx / c (cfl = 1, the most the explicit integrator accepts).
constexpr float kStepRatio = 5.0f;

float explicit_step_limit() { return kDx / std::sqrt((kStiff.lambda + 2.0f * kStiff.mu) / kDensity); }

// A stiff cube (E = 1e7 Pa, c = 116 m/s) of 4 cells a side, its base 1.8 cells above the floor's
// wall nodes, on frictionless separating walls.
engine::FullOrderConfig drop_config(engine::Integrator integrator, float dt) {
  engine::FullOrderConfig config = test::open_space_config(
      kDx, kCells, engine::MaterialSpec{material::MaterialParams<float>::fixed_corotated(kStiff), kDensity});
  config.gravity = Vec3<float>(0.0f, -9.81f, 0.0f);
  config.wall_contact = mpm::ContactType::Separate;
  config.fixed_dt = dt;
  config.integrator = integrator;
  return config;
}

mpm::ParticleInit stiff_cube() {
  return test::lattice_box({0.4375f, 0.15f, 0.4375f}, {0.5625f, 0.275f, 0.5625f}, kDx, 2, kDensity);
}

float lowest_particle(engine::FullOrderSim& sim) {
  const std::vector<float> x = sim.particles().positions_in_initial_order(sim.exec());
  const Index n = Index(x.size() / 3);
  return *std::min_element(x.begin() + n, x.begin() + 2 * n);
}

// Until t_end, every 0.01 s: the largest total energy seen (infinity once it is not finite).
double highest_energy(engine::FullOrderSim& sim, const mpm::ParticleInit& init, double t_end, float& lowest) {
  double highest = analysis::mechanical_energy(sim, init);
  lowest = lowest_particle(sim);
  while (sim.time() < t_end) {
    sim.advance_to(std::min(t_end, sim.time() + 0.01));
    const double energy = analysis::mechanical_energy(sim, init);
    highest = std::isfinite(energy) ? std::max(highest, energy) : std::numeric_limits<double>::infinity();
    lowest = std::min(lowest, lowest_particle(sim));
  }
  return highest;
}

// The stiff cube, with particle domains (no enrichment: their forces reach the implicit operator
// through the corners, implicit_solve.h) or without, and its drop configuration at kStepRatio times
// the explicit limit.
struct StiffDrop {
  mpm::ParticleInit init;
  engine::FullOrderConfig config;
};
StiffDrop stiff_drop(engine::Integrator integrator, bool domains) {
  StiffDrop drop{
      domains ? test::lattice_box_with_domains({0.4375f, 0.15f, 0.4375f}, {0.5625f, 0.275f, 0.5625f}, kDx, 2, kDensity)
              : stiff_cube(),
      drop_config(integrator, kStepRatio * explicit_step_limit())};
  drop.config.enrichment_threshold = 0.0f;
  return drop;
}

class ImplicitStepOfBodies : public ::testing::TestWithParam<bool> {};  // with domains or without
INSTANTIATE_TEST_SUITE_P(Domains, ImplicitStepOfBodies, ::testing::Values(false, true));

TEST_P(ImplicitStepOfBodies, StiffCubeBouncesStablyBeyondTheExplicitStepLimit) {
  const auto [init, config] = stiff_drop(engine::Integrator::Implicit, GetParam());
  engine::FullOrderSim sim(test::exec(), config, init);
  const double initial = analysis::mechanical_energy(sim, init);
  float lowest = 0.0f;
  // The fall takes 0.11 s; the rest is contact with the floor (measured without domains: 34 CG
  // iterations per step on average, 45 at most; the same run stays stable and dissipative up to 400
  // times the limit).
  const double highest = highest_energy(sim, init, 0.2, lowest);
  // Backward Euler dissipates: no energy is gained.
  EXPECT_LE(highest, initial + 1e-3 * std::abs(initial));
  // It reached the floor (its wall nodes end at 3 dx) and did not sink through it.
  EXPECT_LT(lowest, 4.0f * kDx);
  EXPECT_GT(lowest, 2.0f * kDx);
  const engine::ImplicitSolveTotals& totals = *sim.implicit_totals();
  EXPECT_EQ(totals.solves, sim.steps());
  EXPECT_EQ(totals.not_converged, 0);
  RecordProperty("mean_cg_iterations", std::to_string(double(totals.iterations) / double(totals.solves)));
  RecordProperty("most_cg_iterations", std::to_string(totals.most_iterations));
}

TEST_P(ImplicitStepOfBodies, ExplicitStepBlowsUpAtTheSameStep) {
  const auto [init, config] = stiff_drop(engine::Integrator::Explicit, GetParam());
  engine::FullOrderSim sim(test::exec(), config, init);
  const double initial = analysis::mechanical_energy(sim, init);
  float lowest = 0.0f;
  try {
    const double highest = highest_energy(sim, init, 0.2, lowest);
    EXPECT_GT(highest, 10.0 * std::abs(initial)) << "the explicit step stayed bounded";
  } catch (const engine::NonFiniteError&) {
    SUCCEED();  // measured: at step 6, still in free fall (float round-off in F grows every step)
  }
}

// The grid built with every 4th sort and kept between (CUDA's default) holds more, empty, nodes in another
// order: the implicit step's CG sums over them in that order and reaches the same motion into the floor
// contact (measured: 1.8e-7 m apart, 6 % of the bound below).
TEST(ImplicitStep, GridKeptBetweenSortsGivesTheSameMotion) {
  std::vector<std::vector<float>> positions;
  for (const int sort_every : {1, 4}) {
    auto [init, config] = stiff_drop(engine::Integrator::Implicit, false);
    config.sort_every = sort_every;
    // Thrown down at 1.5 m/s, it reaches the floor after 0.035 s.
    std::fill(init.v.begin() + init.count(), init.v.begin() + 2 * init.count(), -1.5f);
    engine::FullOrderSim sim(test::exec(), config, init);
    EXPECT_EQ(sim.grid_follows_sort(), sort_every > 1);
    sim.advance_to(0.05);
    positions.push_back(sim.particles().positions_in_initial_order(sim.exec()));
  }
  float largest = 0.0f;
  for (std::size_t i = 0; i < positions[0].size(); ++i)
    largest = std::max(largest, std::fabs(positions[0][i] - positions[1][i]));
  EXPECT_LT(largest, 1e-4f * kDx);
}

TEST(ImplicitStep, UnconvergedSolveKeepsTheExplicitVelocitiesAndIsCounted) {
  // A spinning, sheared cube at the implicit step: one CG iteration cannot reach 1e-6.
  mpm::ParticleInit init = stiff_cube();
  const Index n = init.count();
  const Vec3<float> center(0.5f, 0.2125f, 0.5f);
  for (Index p = 0; p < n; ++p) {
    const Vec3<float> r = test::plane_vector(init.x, n, p) - center;
    test::set_plane_vector(init.v, n, p,
                           cross(Vec3<float>(1.0f, 2.0f, -3.0f), r) + Vec3<float>(4.0f * r[1], 0.0f, 0.0f));
  }
  const float dt = kStepRatio * explicit_step_limit();
  engine::FullOrderConfig implicit_config = drop_config(engine::Integrator::Implicit, dt);
  implicit_config.implicit.max_iterations = 1;
  // One thread: P2G's float atomics then add in the same order in both runs.
  const Exec exec = test::exec_with_threads(1);
  engine::FullOrderSim implicit(exec, implicit_config, init);
  engine::FullOrderSim explicit_sim(exec, drop_config(engine::Integrator::Explicit, dt), init);
  implicit.substep(dt);
  explicit_sim.substep(dt);

  const engine::ImplicitSolveTotals& totals = *implicit.implicit_totals();
  EXPECT_EQ(totals.solves, 1);
  EXPECT_EQ(totals.not_converged, 1);
  EXPECT_EQ(totals.iterations, 1);
  const std::vector<float> v_implicit = implicit.particles().velocities_in_initial_order(exec);
  const std::vector<float> v_explicit = explicit_sim.particles().velocities_in_initial_order(exec);
  for (std::size_t k = 0; k < v_implicit.size(); ++k) ASSERT_NEAR(v_implicit[k], v_explicit[k], 1e-6f) << "entry " << k;
  EXPECT_EQ(explicit_sim.implicit_totals(), nullptr);
}

// A slip or separating collider holds only the velocity components along its normal: the stiff cube
// resting under a slip plate (still, or pressing down) at the implicit step keeps F near I. When the
// plate held whole nodes, their tangential velocities were integrated explicitly at 5x the explicit
// limit and this test stopped with a NonFiniteError.
TEST(ImplicitStep, CubeUnderASlipPlateStaysStable) {
  for (const float plate_speed : {0.0f, 0.38f}) {
    engine::FullOrderConfig config = drop_config(engine::Integrator::Implicit, kStepRatio * explicit_step_limit());
    mpm::ColliderState plate;
    plate.shape = mpm::ColliderShape::Box;
    plate.contact = mpm::ContactType::Slip;
    plate.half_extents = Vec3<float>(0.2f, 0.05f, 0.2f);
    plate.center = Vec3<float>(0.5f, 0.275f + plate.half_extents[1], 0.5f);
    plate.linear_velocity = Vec3<float>(0.0f, -plate_speed, 0.0f);
    config.colliders = {engine::ColliderSpec{plate}};
    // On the floor: the cube's base just above the wall nodes.
    const mpm::ParticleInit init =
        test::lattice_box({0.4375f, 3.5f * kDx, 0.4375f}, {0.5625f, 3.5f * kDx + 0.125f, 0.5625f}, kDx, 2, kDensity);
    config.colliders[0].initial.center[1] = 3.5f * kDx + 0.125f + plate.half_extents[1];
    engine::FullOrderSim sim(test::exec(), config, init);
    for (int step = 0; step < 20; ++step) sim.substep(config.fixed_dt);
    const std::vector<float> F = sim.particles().deformation_gradients_in_initial_order(test::exec());
    float largest = 0.0f;
    for (const float entry : F) largest = std::max(largest, std::abs(entry));
    EXPECT_LT(largest, 1.1f) << "plate speed " << plate_speed;
  }
}

// The same on an oblique normal: a stiff cube resting on a frictionless slope of 30 degrees (a slip
// half-space) slides at the implicit step, 5x the explicit limit, with F near I. The nodes inside
// the slope hold only their normal velocity; while they held every component with a share of the
// normal above 0.1 (x and y here), the slope-parallel motion of those nodes was integrated
// explicitly.
TEST(ImplicitStep, CubeOnASlipSlopeSlidesStably) {
  engine::FullOrderConfig config = drop_config(engine::Integrator::Implicit, kStepRatio * explicit_step_limit());
  const float angle = 3.14159265f / 6.0f;
  const Mat3<float> tilt = rotation_from_vector(Vec3<float>(0.0f, 0.0f, angle));
  mpm::ColliderState slope;
  slope.shape = mpm::ColliderShape::HalfSpace;
  slope.contact = mpm::ContactType::Slip;
  slope.center = Vec3<float>(0.5f, 0.4f, 0.5f);
  slope.rotation = tilt;
  config.colliders = {engine::ColliderSpec{slope}};
  // The cube of drop_config, turned with the slope and resting half a particle spacing above it.
  const float side = 0.125f, gap = 0.25f * kDx;
  mpm::ParticleInit init =
      test::lattice_box({0.4375f, 0.4f + gap, 0.4375f}, {0.5625f, 0.4f + gap + side, 0.5625f}, kDx, 2, kDensity);
  const Index n = init.count();
  for (Index p = 0; p < n; ++p) {
    const Vec3<float> x = test::plane_vector(init.x, n, p) - slope.center;
    test::set_plane_vector(init.x, n, p, slope.center + tilt * x);
  }
  engine::FullOrderSim sim(test::exec(), config, init);
  for (int step = 0; step < 60; ++step) sim.substep(config.fixed_dt);
  const std::vector<float> F = sim.particles().deformation_gradients_in_initial_order(test::exec());
  float largest = 0.0f;
  for (const float entry : F) largest = std::max(largest, std::abs(entry));
  EXPECT_LT(largest, 1.1f);
  // Downhill is −x (the slope rises with x): the body moved that way, and stayed on the slope.
  const std::vector<float> x = sim.particles().positions_in_initial_order(test::exec());
  double moved = 0.0, lowest_height = 1.0;
  const Vec3<float> normal = tilt * Vec3<float>(0.0f, 1.0f, 0.0f);
  for (Index p = 0; p < n; ++p) {
    moved += double(x[p] - init.x[p]) / double(n);
    lowest_height = std::min(lowest_height, double(dot(test::plane_vector(x, n, p) - slope.center, normal)));
  }
  std::printf("mean x displacement %.3g m, lowest particle %.3g m above the slope\n", moved, lowest_height);
  EXPECT_LT(moved, 0.0);
  EXPECT_GT(lowest_height, -0.5 * kDx);
}

}  // namespace
}  // namespace romp
