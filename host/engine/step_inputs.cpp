// StepInputs: validation of a scene's solver configuration, its time-dependent boundary conditions and
// loads computed on the device for each substep, and the substeps' read-back rows.
#include "host/engine/step_inputs.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "kernels/core/fill.h"
#include "kernels/core/memory.h"

namespace romp::engine {

StepInputs::StepInputs(const Exec& exec, const FullOrderConfig& config) : exec_(exec), config_(config) {
  ROMP_CHECK(config.dx > 0.0f, "grid spacing dx must be > 0");
  for (int a = 0; a < 3; ++a)
    ROMP_CHECK(config.domain_cells[a] > 2 * (config.wall_cells + 1),
               fmt::format("domain_cells[{}] = {} leaves no interior between walls of {} cells", a,
                           config.domain_cells[a], config.wall_cells));
  ROMP_CHECK(!config.materials.empty(), "a simulation needs at least one material");
  const bool implicit = config.integrator == Integrator::Implicit;
  const float most_cfl = implicit ? kImplicitMaxCfl : 1.0f;
  ROMP_CHECK(config.cfl > 0.0f && config.cfl <= most_cfl, fmt::format("cfl must be in (0, {}] with the {} integrator",
                                                                      most_cfl, implicit ? "implicit" : "explicit"));
  ROMP_CHECK(config.flip_alpha >= 0.0f && config.flip_alpha <= 1.0f, "flip_alpha must be in [0, 1]");

  for (const MaterialSpec& m : config.materials) {
    ROMP_CHECK(m.density > 0.0f, "material density must be > 0");
    const bool window = m.strength_off_until > m.strength_off_from;
    ROMP_CHECK(!window || m.params.model == material::MaterialModel::FixedCorotated ||
                   m.params.model == material::MaterialModel::NeoHookean ||
                   m.params.model == material::MaterialModel::HenckyStVK,
               "strength_off is for the hyperelastic models (fixed corotated, Neo-Hookean, Hencky)");
    plastic_ = plastic_ || material::is_plastic(m.params.model);
    // At full strength: the CFL step stays safe when the strength returns.
    max_wave_speed_ = std::max(max_wave_speed_, std::sqrt((m.params.lambda + 2.0f * m.params.mu) / m.density));
  }
  upload_materials(0.0);
  for (const auto& [what, count] : {std::pair<const char*, std::size_t>{"colliders", config.colliders.size()},
                                    {"loads.pokes", config.loads.size()},
                                    {"loads.tractions", config.tractions.size()}})
    ROMP_CHECK(count <= std::size_t(mpm::kMostScheduledInputs),
               fmt::format("{}: at most {} in a scene, got {}", what, mpm::kMostScheduledInputs, count));
  // The schedule goes up once; the tables are sized for all of it, so a substep computes them in place.
  std::vector<mpm::ColliderState> colliders;
  for (const ColliderSpec& spec : config.colliders) colliders.push_back(spec.initial);
  std::vector<mpm::ScheduledMotion> motions;
  for (const DirichletSpec& spec : config.dirichlet)
    motions.push_back({spec.pivot, spec.linear_velocity, spec.angular_velocity});
  std::vector<mpm::RegionLoad> loads;
  for (const RegionLoadSpec& spec : config.loads) loads.push_back(spec.load);
  std::vector<Vec3<float>> tractions;
  for (const TractionSpec& spec : config.tractions) tractions.push_back(spec.traction);
  collider_schedule_ = DeviceBuffer<mpm::ColliderState>::from_host(exec.backend, colliders);
  motion_schedule_ = DeviceBuffer<mpm::ScheduledMotion>::from_host(exec.backend, motions);
  load_schedule_ = DeviceBuffer<mpm::RegionLoad>::from_host(exec.backend, loads);
  traction_schedule_ = DeviceBuffer<Vec3<float>>::from_host(exec.backend, tractions);
  colliders_ = DeviceBuffer<mpm::ColliderState>(exec.backend, Index(config.colliders.size()));
  dirichlet_ = DeviceBuffer<mpm::RigidMotion>(exec.backend, Index(config.dirichlet.size()));
  loads_ = DeviceBuffer<mpm::RegionLoad>(exec.backend, Index(config.loads.size()));
  tractions_ = DeviceBuffer<Vec3<float>>(exec.backend, Index(config.tractions.size()));
  rows_ = DeviceBuffer<std::int64_t>(exec.backend, row_words());
}

std::vector<bool> StepInputs::strength_off_at(double time) const {
  std::vector<bool> off;
  for (const MaterialSpec& m : config_.materials) off.push_back(m.strength_off_at(time));
  return off;
}

void StepInputs::upload_materials(double time) {
  std::vector<bool> off = strength_off_at(time);
  if (!materials_.empty() && off == strength_off_) return;
  std::vector<material::MaterialParams<float>> table;
  for (std::size_t i = 0; i < config_.materials.size(); ++i) {
    material::MaterialParams<float> params = config_.materials[i].params;
    if (off[i]) params.mu = params.lambda = 0.0f;
    table.push_back(params);
  }
  materials_ = DeviceBuffer<material::MaterialParams<float>>::from_host(exec_.backend, table, exec_.stream);
  strength_off_ = std::move(off);
}

mpm::ActiveInputs StepInputs::active_at(double time) const {
  const FullOrderConfig& config = config_;
  mpm::ActiveInputs active;
  for (std::size_t i = 0; i < config.colliders.size(); ++i)
    if (time < config.colliders[i].end) active.colliders |= std::uint64_t(1) << i;
  for (std::size_t i = 0; i < config.loads.size(); ++i)
    if (time >= config.loads[i].start && time < config.loads[i].end) active.loads |= std::uint64_t(1) << i;
  // Every traction keeps its index (the particles name it): an inactive one is 0.
  for (std::size_t i = 0; i < config.tractions.size(); ++i)
    if (time >= config.tractions[i].start && time < config.tractions[i].end) active.tractions |= std::uint64_t(1) << i;
  return active;
}

mpm::StepParams StepInputs::at(double time, float dt) {
  upload_materials(time);
  return params(time, dt, active_at(time));
}

bool StepInputs::FrameShape::operator==(const FrameShape& other) const {
  return dt == other.dt && count == other.count && active == other.active && materials == other.materials;
}

std::optional<StepInputs::FrameShape> StepInputs::frame_shape(double time, float dt, int count) {
  upload_materials(time);
  FrameShape frame{dt, count, active_at(time), materials_.data()};
  const std::vector<bool> off = strength_off_at(time);
  // The substeps' times as the host's clock sums them.
  double t = time;
  for (int k = 1; k < count; ++k) {
    t += dt;
    if (active_at(t) != frame.active || strength_off_at(t) != off) return std::nullopt;
  }
  return frame;
}

void StepInputs::start_frame(double time) {
  if (frame_start_.empty()) frame_start_ = DeviceBuffer<double>(exec_.backend, 1);
  upload(exec_.backend, frame_start_.span(), Span<const double>(&time, 1), exec_.stream);
}

mpm::StepParams StepInputs::at_in_frame(const FrameShape& frame, int substep) {
  ROMP_CHECK(!frame_start_.empty() && substep >= 0 && substep < frame.count,
             "at_in_frame: a substep of a frame after start_frame");
  return params(mpm::SubstepTime(frame_start_.span(), substep), frame.dt, frame.active);
}

void StepInputs::claim_rows(int count) {
  ROMP_CHECK(
      pending_rows_ + count <= most_rows_,
      fmt::format("{} substeps without a read-back: at most {} were reserved", pending_rows_ + count, most_rows_));
  pending_rows_ += count;
}

mpm::StepParams StepInputs::params(const mpm::SubstepTime& time, float dt, const mpm::ActiveInputs& active) {
  const FullOrderConfig& config = config_;
  const mpm::InputTables tables{colliders_.prefix(mpm::active_entries(active.colliders)), dirichlet_.span(),
                                loads_.prefix(mpm::active_entries(active.loads)), tractions_.span()};
  mpm::inputs_at(exec_,
                 {collider_schedule_.span(), motion_schedule_.span(), load_schedule_.span(), traction_schedule_.span()},
                 time, dt, active, tables);
  ROMP_CHECK(pending_rows_ < most_rows_,
             fmt::format("{} substeps without a read-back: at most {} were reserved", pending_rows_ + 1, most_rows_));
  const Span<std::int64_t> row = rows_.span().subspan(Index(pending_rows_++) * row_words(), row_words());
  fill(exec_, row.subspan(0, speed_word()), mpm::kNoFailure);
  memory::fill_zero(row.data() + speed_word(), exec_.backend, sizeof(float), exec_.stream);

  mpm::StepParams step;
  step.dt = dt;
  step.gravity = config.gravity;
  step.transfer = config.transfer;
  step.flip_alpha = config.flip_alpha;
  step.domain = config.domain();
  step.wall_friction = config.wall_friction;
  step.materials = materials_.span();
  step.colliders = tables.colliders;
  step.dirichlet = tables.dirichlet;
  step.loads = tables.loads;
  step.tractions = tables.tractions;
  step.first_failure = row.subspan(0, mpm::kStageCount);
  step.largest_speed = Span<float>(reinterpret_cast<float*>(row.data() + speed_word()), 1);
  return step;
}

const char* stage_name(mpm::Stage stage) {
  switch (stage) {
    case mpm::Stage::P2G: return "p2g";
    case mpm::Stage::GridUpdate: return "grid_update";
    case mpm::Stage::G2P: return "g2p";
    case mpm::Stage::Plasticity: return "plasticity";
  }
  return "unknown";
}

void StepInputs::reserve_readback(int floats, int slots, int rows) {
  ROMP_CHECK(floats >= 0 && slots >= 0 && rows >= 1 && !reserved_ && pending_rows_ == 0,
             "reserve_readback: once, before the first substep, for at least one row");
  reserved_ = true;
  floats_ = floats;
  slots_ = slots;
  most_rows_ = rows;
  rows_ = DeviceBuffer<std::int64_t>(exec_.backend, Index(rows) * row_words());
}

StepInputs::Row StepInputs::readback_row() {
  ROMP_CHECK(pending_rows_ > 0, "readback_row: after `at`");
  std::int64_t* row = rows_.data() + Index(pending_rows_ - 1) * row_words();
  return {Span<std::int64_t>(row + mpm::kStageCount, slots_),
          Span<float>(reinterpret_cast<float*>(row + speed_word() + 1), floats_)};
}

int StepInputs::read_back() {
  read_ = download(exec_.backend, rows_.span().subspan(0, Index(pending_rows_) * row_words()), exec_.stream);
  const int rows = pending_rows_;
  pending_rows_ = 0;
  return rows;
}

const std::int64_t* StepInputs::read_row(int row) const {
  ROMP_CHECK(row >= 0 && Index(row + 1) * row_words() <= Index(read_.size()),
             fmt::format("read-back row {} was not read", row));
  return read_.data() + Index(row) * row_words();
}

float StepInputs::largest_speed(int row) const {
  float speed;
  std::memcpy(&speed, read_row(row) + speed_word(), sizeof speed);
  return speed;
}

Span<const std::int64_t> StepInputs::readback_slots(int row) const {
  return Span<const std::int64_t>(read_row(row) + mpm::kStageCount, slots_);
}

Span<const float> StepInputs::readback_values(int row) const {
  return Span<const float>(reinterpret_cast<const float*>(read_row(row) + speed_word() + 1), floats_);
}

void StepInputs::check_stages(int row, const std::string& who, std::int64_t step, double time,
                              const FailureDescriber& describe) const {
  const std::int64_t* failures = read_row(row);
  for (int s = 0; s < mpm::kStageCount; ++s) {
    const std::int64_t failure = failures[s];
    if (failure == mpm::kNoFailure) continue;
    const auto stage = mpm::Stage(s);
    const auto [index, what] = stage == mpm::Stage::GridUpdate
                                   ? std::pair<std::int64_t, std::string>(failure, fmt::format("grid node {}", failure))
                                   : describe(stage, failure);
    throw NonFiniteError(fmt::format("{}non-finite value at step {} (t = {:.6g} s), stage {}: {}", who, step, time,
                                     stage_name(stage), what),
                         step, stage, index);
  }
}

bool StepInputs::failed(int row) const {
  const std::int64_t* failures = read_row(row);
  return std::any_of(failures, failures + mpm::kStageCount,
                     [](std::int64_t failure) { return failure != mpm::kNoFailure; });
}

bool advance_clock(double& time, double t, const std::function<double()>& stable_dt,
                   const std::function<void(float)>& substep, const std::function<bool()>& stop) {
  // Substeps shorter than this fraction of the stable Δt are merged into the previous one.
  constexpr double kMergeFraction = 1e-3;
  while (time < t) {
    if (stop && stop()) return false;
    const double dt = stable_dt();
    const double remaining = t - time;
    if (remaining >= dt * (1.0 + kMergeFraction)) {
      substep(float(dt));
      continue;
    }
    // The last substep lands on t: the clock takes t itself, not the sum with the float Δt, whose
    // rounding would leave a sliver of time for one more, needless substep.
    substep(float(remaining));
    time = t;
  }
  return true;
}

void check_dirichlet_groups(const FullOrderConfig& config, const std::vector<std::int32_t>& groups,
                            const std::string& what) {
  for (const std::int32_t group : groups)
    ROMP_CHECK(group == mpm::kNoDirichletGroup || (group >= 0 && group < std::int32_t(config.dirichlet.size())),
               fmt::format("{} Dirichlet group {} outside [0, {})", what, group, config.dirichlet.size()));
}

void check_particle_tables(const FullOrderConfig& config, const std::vector<std::int32_t>& material,
                           const std::vector<std::int32_t>& dirichlet_group) {
  for (const std::int32_t id : material)
    ROMP_CHECK(id >= 0 && id < std::int32_t(config.materials.size()),
               fmt::format("particle material id {} outside [0, {})", id, config.materials.size()));
  check_dirichlet_groups(config, dirichlet_group, "particle");
}

void check_particle_domains(const FullOrderConfig& config, const mpm::ParticleInit& init) {
  const Index domains = init.domains.count();
  for (const std::int32_t d : init.domain)
    ROMP_CHECK(d == mpm::kNoDomain || (d >= 0 && d < domains),
               fmt::format("particle domain {} outside [0, {})", d, domains));
  check_dirichlet_groups(config, init.domains.corner_dirichlet_group, "domain corner");
}

}  // namespace romp::engine
