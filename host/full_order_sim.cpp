// FullOrderSim: composes the substep from the stages the scene needs, times them, and stops on
// the first non-finite value with the step, stage and particle.
#include "host/full_order_sim.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/core/device_timer.h"
#include "kernels/core/memory.h"
#include "kernels/math/rotation.h"

namespace romp {
namespace {

template <class T>
DeviceBuffer<T> upload(Backend backend, const std::vector<T>& host) {
  return DeviceBuffer<T>::from_host(backend, host);
}

}  // namespace

const char* stage_name(mpm::Stage stage) {
  switch (stage) {
    case mpm::Stage::P2G: return "p2g";
    case mpm::Stage::GridUpdate: return "grid_update";
    case mpm::Stage::G2P: return "g2p";
    case mpm::Stage::Plasticity: return "plasticity";
  }
  return "unknown";
}

FullOrderSim::FullOrderSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& init)
    : exec_(exec),
      config_(std::move(config)),
      particles_(exec.backend, init),
      grid_(exec.backend, config_.dx, config_.transfer == mpm::Transfer::PicFlip) {
  ROMP_CHECK(config_.dx > 0.0f, "grid spacing dx must be > 0");
  for (int a = 0; a < 3; ++a)
    ROMP_CHECK(config_.domain_cells[a] > 2 * (config_.wall_cells + 1),
               fmt::format("domain_cells[{}] = {} leaves no interior between walls of {} cells", a,
                           config_.domain_cells[a], config_.wall_cells));
  ROMP_CHECK(!config_.materials.empty(), "a simulation needs at least one material");
  ROMP_CHECK(config_.cfl > 0.0f && config_.cfl <= 1.0f, "cfl must be in (0, 1]");
  ROMP_CHECK(config_.flip_alpha >= 0.0f && config_.flip_alpha <= 1.0f, "flip_alpha must be in [0, 1]");
  for (const std::int32_t id : init.material)
    ROMP_CHECK(id >= 0 && id < std::int32_t(config_.materials.size()),
               fmt::format("particle material id {} outside [0, {})", id, config_.materials.size()));
  for (const std::int32_t group : init.dirichlet_group)
    ROMP_CHECK(group == mpm::kNoDirichletGroup || (group >= 0 && group < std::int32_t(config_.dirichlet.size())),
               fmt::format("particle Dirichlet group {} outside [0, {})", group, config_.dirichlet.size()));

  std::vector<material::MaterialParams<float>> table;
  for (const MaterialSpec& m : config_.materials) {
    ROMP_CHECK(m.density > 0.0f, "material density must be > 0");
    table.push_back(m.params);
    plastic_ = plastic_ || material::is_plastic(m.params.model);
    // Dilatational wave speed c = sqrt((λ + 2μ) / ρ).
    max_wave_speed_ = std::max(max_wave_speed_, std::sqrt((m.params.lambda + 2.0f * m.params.mu) / m.density));
  }
  materials_ = upload(exec_.backend, table);
  first_failure_ = DeviceBuffer<std::int64_t>(exec_.backend, mpm::kStageCount);

  // Pipeline order, as substep() runs them.
  stage_seconds_ = {{"sort", 0.0}, {"grid_build", 0.0}, {"p2g", 0.0}, {"grid_update", 0.0}, {"g2p", 0.0}};
  if (plastic_) stage_seconds_.emplace_back("plasticity", 0.0);
}

float FullOrderSim::stable_dt() {
  if (config_.fixed_dt > 0.0f) return config_.fixed_dt;
  const float speed = max_wave_speed_ + mpm::max_particle_speed(exec_, particles_.view());
  return std::min(config_.max_dt, config_.cfl * config_.dx / speed);
}

mpm::StepParams FullOrderSim::step_params(float dt) {
  const double t = time_;
  std::vector<mpm::ColliderState> colliders;
  for (const ColliderSpec& spec : config_.colliders) {
    mpm::ColliderState c = spec.initial;
    c.center = c.center + float(t) * c.linear_velocity;
    c.rotation = rotation_from_vector(float(t) * c.angular_velocity) * c.rotation;
    colliders.push_back(c);
  }
  std::vector<mpm::RigidMotion> motions;
  for (const DirichletSpec& spec : config_.dirichlet) {
    motions.push_back(mpm::RigidMotion{spec.pivot + float(t) * spec.linear_velocity, spec.linear_velocity,
                                       spec.angular_velocity, rotation_from_vector(dt * spec.angular_velocity)});
  }
  std::vector<mpm::RegionLoad> loads;
  for (const RegionLoadSpec& spec : config_.loads)
    if (t >= spec.start && t < spec.end) loads.push_back(spec.load);
  colliders_ = upload(exec_.backend, colliders);
  dirichlet_ = upload(exec_.backend, motions);
  loads_ = upload(exec_.backend, loads);

  mpm::StepParams step;
  step.dt = dt;
  step.gravity = config_.gravity;
  step.transfer = config_.transfer;
  step.flip_alpha = config_.flip_alpha;
  for (int a = 0; a < 3; ++a) step.domain_cells[a] = config_.domain_cells[a];
  step.wall_cells = config_.wall_cells;
  step.wall_contact = config_.wall_contact;
  step.wall_friction = config_.wall_friction;
  step.materials = materials_.span();
  step.colliders = colliders_.span();
  step.dirichlet = dirichlet_.span();
  step.loads = loads_.span();
  step.first_failure = first_failure_.span();
  return step;
}

void FullOrderSim::substep(float dt) {
  ROMP_CHECK(dt > 0.0f && std::isfinite(dt), fmt::format("substep dt must be finite and > 0, got {}", dt));
  std::vector<std::int64_t> no_failure(mpm::kStageCount, mpm::kNoFailure);
  first_failure_.copy_from_host(Span<const std::int64_t>(no_failure.data(), mpm::kStageCount), exec_.stream);
  const mpm::StepParams step = step_params(dt);

  DeviceTimer timer(exec_);
  std::size_t stage = 0;
  auto timed = [&](auto&& run) {
    timer.start();
    run();
    stage_seconds_[stage++].second += timer.stop();
  };
  const float inverse_dx = 1.0f / config_.dx;
  timed([&] { particles_.sort_by_block(exec_, inverse_dx); });
  const mpm::ParticleView particles = particles_.view();
  timed([&] { grid_.rebuild(exec_, Vec3Planes<const float>(particles.x)); });
  const mpm::GridView grid = grid_.view();
  timed([&] { mpm::particle_to_grid(exec_, particles, grid, step); });
  timed([&] { mpm::update_grid(exec_, grid, step); });
  timed([&] { mpm::grid_to_particle(exec_, particles, grid, step); });
  if (plastic_) timed([&] { mpm::project_plasticity(exec_, particles, step); });

  time_ += dt;
  ++steps_;
  check_finite();
}

void FullOrderSim::check_finite() {
  const std::vector<std::int64_t> failures = first_failure_.to_host(exec_.stream);
  for (int s = 0; s < mpm::kStageCount; ++s) {
    if (failures[s] == mpm::kNoFailure) continue;
    const auto stage = mpm::Stage(s);
    std::int64_t index = failures[s];
    std::string what;
    if (stage == mpm::Stage::GridUpdate) {
      what = fmt::format("grid node {}", index);
    } else {
      // Report the particle by its initial index, which is what outputs and scenes refer to.
      const mpm::ParticleView view = particles_.view();
      std::int32_t id = 0;
      memory::copy(&id, Backend::Cpu, view.id.data() + index, exec_.backend, sizeof id, exec_.stream);
      index = id;
      what = fmt::format("particle {}", index);
    }
    throw NonFiniteError(fmt::format("non-finite value at step {} (t = {:.6g} s), stage {}: {}", steps_, time_,
                                     stage_name(stage), what),
                         steps_, stage, index);
  }
}

void FullOrderSim::advance_to(double t) {
  // Substeps shorter than this fraction of the stable Δt are merged into the previous one.
  constexpr double kMergeFraction = 1e-3;
  while (time_ < t) {
    const double dt = stable_dt();
    const double remaining = t - time_;
    if (remaining >= dt * (1.0 + kMergeFraction)) {
      substep(float(dt));
      continue;
    }
    // The last substep lands on t: the clock takes t itself, not the sum with the float Δt, whose
    // rounding would leave a sliver of time for one more, needless substep.
    substep(float(remaining));
    time_ = t;
  }
}

void FullOrderSim::restore_clock(double time, std::int64_t steps) {
  ROMP_CHECK(time >= 0.0 && steps >= 0, fmt::format("restored clock must be >= 0, got t = {}, step {}", time, steps));
  time_ = time;
  steps_ = steps;
}

std::vector<std::pair<std::string, double>> FullOrderSim::stage_seconds() const { return stage_seconds_; }

}  // namespace romp
