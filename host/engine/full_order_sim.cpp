// FullOrderSim: composes the substep from the stages the scene needs, times them, and stops on
// the first non-finite value with the step, stage and particle.
#include "host/engine/full_order_sim.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "host/engine/neural_materials.h"
#include "kernels/core/memory.h"

namespace romp::engine {
namespace {

// A batch's substeps may be this fraction over the step planned for them, as advance_clock merges a sliver.
constexpr float kMergeFraction = 1e-3f;

}  // namespace

FullOrderSim::FullOrderSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& init)
    : stream_(std::make_unique<OwnedStream>(exec.backend)),
      exec_(with_capturable_stream(exec, *stream_)),
      config_(std::move(config)),
      particles_(exec.backend, init),
      // Domain corners always blend PIC and FLIP (the enriched-MPM paper's transfer), so their grid
      // keeps the velocity before forces whatever the other particles use.
      grid_(exec.backend, config_.dx, config_.transfer == mpm::Transfer::PicFlip || !init.domains.empty()),
      inputs_(exec_, config_),
      speed_slot_(exec.backend, 1),
      stage_timeline_(exec_) {
  check_particle_tables(config_, init.material, init.dirichlet_group);
  check_particle_domains(config_, init);
  ROMP_CHECK(config_.sort_every >= 0,
             fmt::format("sort_every must be >= 0 (0: the backend's choice), got {}", config_.sort_every));
  if (!init.domains.empty()) domains_.emplace(exec.backend, init.domains);
  released_.assign(config_.dirichlet.size(), false);
  if (config_.integrator == Integrator::Implicit) implicit_.emplace(exec.backend, config_.implicit);
  // Few particles sort every substep on CUDA too: their grid is then built from the particles, with no round
  // trip, and their substeps run in batches replayed as graphs (runs_batches).
  sort_every_ = config_.sort_every > 0                  ? config_.sort_every
                : exec.is_cuda() && !counts_on_device() ? kSortEveryOnCuda
                                                        : 1;
  // Where G2P flags a particle that left the grid built at the last sort, read back with the failure slots; a
  // row for each substep of a batch.
  inputs_.reserve_readback(sort_every_ > 1 ? 1 : 0, 0, runs_batches() ? kMostSubstepsPerBatch : 1);
  auto neural = std::make_unique<NeuralMaterials>(exec_, config_.materials, particles_.count());
  // The implicit operator needs ∂P/∂F of every material, which a learned law does not provide here.
  ROMP_CHECK(neural->empty() || !implicit_,
             "solver.integrator = \"implicit\" needs analytic materials; neural laws run with the explicit integrator");
  if (!neural->empty()) neural_ = std::move(neural);
  // Pipeline order, as substep() runs them.
  stages_ = {"sort", "grid_build"};
  if (neural_) stages_.emplace_back("neural_stress");
  stages_.emplace_back("p2g");
  if (enriching()) stages_.emplace_back("enrich");
  if (domains_) stages_.insert(stages_.end(), {"p2c", "c2g"});
  stages_.emplace_back("grid_update");
  if (implicit_) stages_.emplace_back("implicit_solve");
  stages_.emplace_back(return_map_in_g2p() ? "g2p_plasticity" : "g2p");
  if (domains_) stages_.insert(stages_.end(), {"g2c", "c2p"});
  if (inputs_.plastic() && !return_map_in_g2p()) stages_.emplace_back("plasticity");
  if (neural_) stages_.emplace_back("neural_plasticity");
  if (replays_batch_graphs()) stages_.emplace_back("batch_graphs");
}

FullOrderSim::FullOrderSim(FullOrderSim&&) = default;
FullOrderSim& FullOrderSim::operator=(FullOrderSim&&) = default;
FullOrderSim::~FullOrderSim() = default;

float FullOrderSim::particle_speed() {
  if (!last_particle_speed_)
    last_particle_speed_ = mpm::max_particle_speed(exec_, particles_.view(), speed_slot_.span());
  return *last_particle_speed_;
}

float FullOrderSim::cfl_step(float particle_speed) {
  // Deformed domains are stiffer than at rest (domain_stiffening); the last substep's state stands
  // in for this one's.
  const float wave_speed = inputs_.max_wave_speed() * (domains_ ? std::sqrt(domains_->stiffening(exec_)) : 1.0f);
  const float speed = wave_speed + particle_speed;
  // Enriched corners are nodes of elements as small as a domain, not a grid cell.
  const float length = enriching() ? std::min(config_.dx, domains_->smallest_edge()) : config_.dx;
  const float dt = std::min(config_.max_dt, config_.cfl * length / speed);
  // The implicit step lifts the elastic wave limit, not the transport one: particles still cross at
  // most one cell per step, so that each step's stencils see the motion (cfl ≤ 1 implies it).
  return implicit_ ? std::min(dt, length / particle_speed) : dt;
}

float FullOrderSim::stable_dt() { return config_.fixed_dt > 0.0f ? config_.fixed_dt : cfl_step(particle_speed()); }

float FullOrderSim::batch_step() {
  if (config_.fixed_dt > 0.0f) return config_.fixed_dt;
  // A quarter more than the speed now, and what gravity adds over a batch at that step: a batch whose
  // particles outrun it anyway (a collider strikes) goes back and runs substep by substep.
  const float speed = 1.25f * particle_speed();
  const float gravity = norm(config_.gravity);
  return cfl_step(speed + gravity * float(kMostSubstepsPerBatch) * cfl_step(speed));
}

void FullOrderSim::substep(float dt) {
  ROMP_CHECK(dt > 0.0f && std::isfinite(dt), fmt::format("substep dt must be finite and > 0, got {}", dt));
  release_ended_dirichlet_groups(time_);
  if (domains_)
    for (const DomainReleaseSpec& release : config_.domain_releases)
      if (time_ >= release.start && time_ < release.end) mpm::release_domains(exec_, particles_.view(), release.region);
  StageClock timed(stage_timeline_, stage_launches_);
  const bool was_sorted = sorted_;
  if (run_substep(inputs_.at(time_, dt), steps_, timed)) {
    ++sorting_.sorts;
    if (was_sorted && steps_ % sort_every_ != 0) ++sorting_.early_sorts;
  }
  time_ += dt;
  ++steps_;
  if (enriching()) {
    // One host read per substep, only in scenes that enrich.
    last_enriched_share_ = domains_->enriched_share(exec_);
    ++enrichment_.substeps;
    enrichment_.share_sum += last_enriched_share_;
    if (last_enriched_share_ > enrichment_.largest_share) {
      enrichment_.largest_share = last_enriched_share_;
      enrichment_.largest_share_step = steps_;
    }
  }
  // The failure slots come back with the particles' largest speed, the next CFL step's, and (with a kept grid)
  // whether a particle left it: one download.
  inputs_.read_back();
  last_particle_speed_ = inputs_.largest_speed(0);
  inputs_.check_stages(0, "", steps_, time_, [this](mpm::Stage, std::int64_t slot) {
    // Report the particle by its initial index, which is what outputs and scenes refer to.
    const std::int32_t id = download(exec_.backend, particles_.view().id.subspan(slot, 1), exec_.stream)[0];
    return std::pair<std::int64_t, std::string>(id, fmt::format("particle {}", id));
  });
}

bool FullOrderSim::run_substep(const mpm::StepParams& step_params, std::int64_t step_number, StageClock& timed) {
  mpm::StepParams step = step_params;
  const float inverse_dx = 1.0f / config_.dx;
  // A grid that follows the sort serves until a particle's stencil leaves it: the last substep's G2P said so.
  const bool follows_sort = grid_follows_sort();
  const Span<float> left_grid_slot = inputs_.readback_row().values;  // empty when sort_every is 1
  const bool left_grid = follows_sort && sorted_ && inputs_.readback_values(0)[0] > 0.0f;
  const bool sort_now = !sorted_ || step_number % sort_every_ == 0 || left_grid;
  // The stage runs empty between sorts, so the stage table keeps its rows.
  timed([&] {
    if (!sort_now) return;
    particles_.sort_by_block(
        exec_, inverse_dx,
        counts_on_device() ? mpm::ParticleSet::RunCount::OnDevice : mpm::ParticleSet::RunCount::ReadBack);
    if (follows_sort) memory::fill_zero(left_grid_slot.data(), exec_.backend, sizeof(float), exec_.stream);
  });
  sorted_ = true;
  const mpm::ParticleView particles = particles_.view();
  const mpm::DomainView domains = domains_ ? domains_->view() : mpm::DomainView{};
  timed([&] {
    if (!follows_sort && counts_on_device())
      grid_.rebuild_for_few_points(exec_, Vec3Planes<const float>(particles.x));
    else if (!follows_sort)
      grid_.rebuild(exec_, Vec3Planes<const float>(particles.x), Vec3Planes<const float>(domains.x));
    else if (sort_now)
      grid_.rebuild_around_blocks(exec_, particles_.block_starts(), particles_.sorted_block_keys());
    else
      grid_.clear_nodes(exec_);
  });
  const mpm::GridView grid = grid_.view();
  if (neural_) timed([&] { step.host_stress = neural_->evaluate_stress(exec_, particles); });
  timed([&] {
    if (config_.p2g == P2GKernel::Tiled)
      mpm::particle_to_grid_tiled(exec_, particles, grid, step, particles_.block_starts(),
                                  particles_.sorted_block_keys(), sort_now);
    else
      mpm::particle_to_grid(exec_, particles, grid, step);
  });
  if (enriching()) timed([&] { mpm::mark_enrichment(exec_, particles, domains, step, config_.enrichment_threshold); });
  if (domains_) {
    timed([&] { mpm::particles_to_corners(exec_, particles, domains, step); });
    timed([&] { mpm::corners_to_grid(exec_, domains, grid, step); });
  }
  timed([&] { mpm::update_grid(exec_, grid, step); });
  if (implicit_) timed([&] { implicit_->solve(exec_, particles, domains, grid, step, step_number + 1); });
  timed([&] {
    mpm::grid_to_particle(
        exec_, particles, grid, step,
        follows_sort ? mpm::GridCoverage{particles_.sorted_block_keys(), left_grid_slot} : mpm::GridCoverage{},
        return_map_in_g2p());
  });
  if (domains_) {
    timed([&] { mpm::grid_to_corners(exec_, domains, grid, step); });
    timed([&] { mpm::corners_to_particles(exec_, particles, domains, step); });
  }
  if (inputs_.plastic() && !return_map_in_g2p()) timed([&] { mpm::project_plasticity(exec_, particles, step); });
  if (neural_) timed([&] { neural_->project_plasticity(exec_, particles, step); });
  if (tracers_) timed([&] { tracers_->advect(exec_, grid, step); });
  buffers_sized_ = true;
  return sort_now;
}

bool FullOrderSim::run_batch(float dt, int count) {
  release_ended_dirichlet_groups(time_);
  const std::vector<bool> released = released_;
  const float speed = particle_speed();
  if (!replay_batch(dt, count)) {
    particles_.save(exec_, batch_start_);
    double time = time_;
    for (int k = 0; k < count; ++k, time += dt) {
      release_ended_dirichlet_groups(time);  // a group whose end comes within the batch
      StageClock timed(stage_timeline_, stage_launches_);
      run_substep(inputs_.at(time, dt), steps_ + k, timed);
    }
  }
  return accept_batch(dt, count, speed, released);
}

bool FullOrderSim::replay_batch(float dt, int count) {
  // The first batch runs eagerly: it sizes the buffers (an allocation cannot be captured). A Dirichlet group
  // that ends within the batch would be freed between its substeps by the host.
  if (!replays_batch_graphs() || !buffers_sized_) return false;
  const double end = time_ + double(count) * double(dt);
  for (std::size_t g = 0; g < config_.dirichlet.size(); ++g)
    if (!released_[g] && config_.dirichlet[g].end < end) return false;
  const std::optional<StepInputs::FrameShape> inputs = inputs_.frame_shape(time_, dt, count);
  if (!inputs) return false;
  inputs_.start_frame(time_);
  bool captured = false;
  const StreamGraph* graph = nullptr;
  try {
    graph = &batch_graphs_.get(exec_, *inputs, [&] {
      // The capture runs the substeps' host code (which takes their read-back rows) and none of their launches.
      particles_.save(exec_, batch_start_);
      StageClock untimed = StageClock::untimed();
      for (int k = 0; k < count; ++k) run_substep(inputs_.at_in_frame(*inputs, k), steps_ + k, untimed);
      captured = true;
    });
  } catch (const Error& error) {
    // Nothing of the batch ran: this batch and every later one run substep by substep (the tests count the
    // batches replayed, so a capture failing on the CPU shows).
    inputs_.discard_pending_rows();
    graphs_failed_ = true;
    spdlog::warn("full-order batches run substep by substep from step {} on: capturing them as a graph failed: {}",
                 steps_, error.what());
    return false;
  }
  if (!captured) inputs_.claim_rows(count);
  replay_as_stage(*graph, exec_, stages_.size() - 1, stage_timeline_, stage_launches_);
  ++graph_batches_;
  return true;
}

bool FullOrderSim::accept_batch(float dt, int count, float speed, const std::vector<bool>& released) {
  ROMP_CHECK(inputs_.read_back() == count, "a read-back per batch");
  // Each substep ran with the step planned at the batch's start: it must be one the CFL condition allows for
  // the speed the substep before it left, as a substep run alone would have had.
  bool kept = true;
  for (int k = 0; k < count && kept; ++k) {
    kept = !inputs_.failed(k) && (config_.fixed_dt > 0.0f || dt <= cfl_step(speed) * (1.0f + kMergeFraction));
    speed = inputs_.largest_speed(k);
  }
  if (!kept) {
    particles_.restore(exec_, batch_start_);
    released_ = released;
    last_particle_speed_.reset();  // the start's: reduced afresh
    ++rolled_back_batches_;
    return false;
  }
  for (int k = 0; k < count; ++k) time_ += dt;  // as the substeps' own times were summed
  steps_ += count;
  sorting_.sorts += count;  // a batch sorts every substep (runs_batches: sort_every is 1)
  last_particle_speed_ = speed;
  return true;
}

void FullOrderSim::set_tracers(const std::vector<float>& X, TracerCarrier carrier) {
  // Tracers embed in the domains as they are at the start, the reference configuration.
  mpm::DomainInit layout;
  if (domains_ && carrier == TracerCarrier::Material) {
    ROMP_CHECK(steps_ == 0, "tracers start with the run: they are embedded in the domains' reference configuration");
    layout.corner = domains_->corner_indices_on_host(exec_);
    layout.corner_x = domains_->corner_positions_on_host(exec_);
    layout.corner_dirichlet_group.assign(std::size_t(domains_->corner_count()), mpm::kNoDirichletGroup);
  }
  tracers_.emplace(exec_, X, layout);
  // Tracers end the batches (runs_batches), whose replays have the table's last row.
  if (stages_.back() == "batch_graphs") {
    ROMP_CHECK(graph_batches_ == 0, "tracers start before the first batch of substeps replayed as a graph");
    stages_.pop_back();
  }
  // Last in the substep: the grid's velocities stay as the update left them until the next rebuild.
  if (stages_.back() != "tracers") stages_.emplace_back("tracers");
}

std::vector<float> FullOrderSim::tracer_positions_on_host() const {
  ROMP_CHECK(tracers_.has_value(), "tracer positions asked for before set_tracers");
  return tracers_->positions(exec_, domains_ ? &*domains_ : nullptr);
}

std::vector<float> FullOrderSim::tracer_velocities_on_host() const {
  ROMP_CHECK(tracers_.has_value(), "tracer velocities asked for before set_tracers");
  return tracers_->velocities(exec_, domains_ ? &*domains_ : nullptr);
}

void FullOrderSim::release_ended_dirichlet_groups(double time) {
  for (std::size_t g = 0; g < config_.dirichlet.size(); ++g) {
    if (released_[g] || time < config_.dirichlet[g].end) continue;
    particles_.release_dirichlet_group(exec_, std::int32_t(g));
    if (domains_) domains_->release_dirichlet_group(exec_, std::int32_t(g));
    released_[g] = true;
  }
}

bool FullOrderSim::advance_to(double t, const std::function<bool()>& stop) {
  const std::function<double()> stable = [this] { return double(stable_dt()); };
  const std::function<void(float)> one = [this](float dt) { substep(dt); };
  if (!runs_batches()) return advance_clock(time_, t, stable, one, stop);
  if (time_ >= t) return true;
  float dt = 0.0f;
  std::int64_t left = 0;  // substeps of dt still to go to t
  do {
    if (stop && stop()) return false;
    // The step holds from batch to batch (and so do their graphs) while the plan allows it.
    const float allowed = batch_step();
    if (left == 0 || dt > allowed * (1.0f + kMergeFraction)) {
      const double remaining = t - time_;
      left = std::int64_t(std::ceil(remaining / (double(allowed) * (1.0 + double(kMergeFraction)))));
      dt = float(remaining / double(left));
    }
    const int count = int(std::min<std::int64_t>(left, kMostSubstepsPerBatch));
    if (!run_batch(dt, count)) return advance_clock(time_, t, stable, one, stop);
    left -= count;
    // The clock takes t itself, not the sum of the float substeps.
    if (left == 0) time_ = t;
  } while (left > 0);
  return true;
}

void FullOrderSim::restore_clock(double time, std::int64_t steps) {
  ROMP_CHECK(time >= 0.0 && steps >= 0, fmt::format("restored clock must be >= 0, got t = {}, step {}", time, steps));
  time_ = time;
  steps_ = steps;
}

std::vector<std::pair<std::string, double>> FullOrderSim::stage_seconds() const {
  return stage_table(stages_, stage_timeline_);
}

std::vector<std::pair<std::string, std::int64_t>> FullOrderSim::stage_launches() const {
  return stage_launch_table(stages_, stage_launches_);
}

}  // namespace romp::engine
