// FullOrderSim: composes the substep from the stages the scene needs, times them, and stops on
// the first non-finite value with the step, stage and particle.
#include "host/engine/full_order_sim.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "host/engine/neural_materials.h"
#include "host/engine/stage_clock.h"
#include "kernels/core/memory.h"

namespace romp::engine {

FullOrderSim::FullOrderSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& init)
    : exec_(exec),
      config_(std::move(config)),
      particles_(exec.backend, init),
      // Domain corners always blend PIC and FLIP (the enriched-MPM paper's transfer), so their grid
      // keeps the velocity before forces whatever the other particles use.
      grid_(exec.backend, config_.dx, config_.transfer == mpm::Transfer::PicFlip || !init.domains.empty()),
      inputs_(exec, config_),
      speed_slot_(exec.backend, 1),
      stage_timeline_(exec) {
  check_particle_tables(config_, init.material, init.dirichlet_group);
  check_particle_domains(config_, init);
  ROMP_CHECK(config_.sort_every >= 0,
             fmt::format("sort_every must be >= 0 (0: the backend's choice), got {}", config_.sort_every));
  sort_every_ = config_.sort_every > 0 ? config_.sort_every : exec.is_cuda() ? kSortEveryOnCuda : 1;
  // Where G2P flags a particle that left the grid built at the last sort, read back with the failure slots.
  if (sort_every_ > 1) inputs_.reserve_readback(1, 0);
  if (!init.domains.empty()) domains_.emplace(exec.backend, init.domains);
  released_.assign(config_.dirichlet.size(), false);
  if (config_.integrator == Integrator::Implicit) implicit_.emplace(exec.backend, config_.implicit);
  auto neural = std::make_unique<NeuralMaterials>(exec, config_.materials, particles_.count());
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
  stages_.emplace_back("g2p");
  if (domains_) stages_.insert(stages_.end(), {"g2c", "c2p"});
  if (inputs_.plastic()) stages_.emplace_back("plasticity");
  if (neural_) stages_.emplace_back("neural_plasticity");
}

FullOrderSim::FullOrderSim(FullOrderSim&&) = default;
FullOrderSim& FullOrderSim::operator=(FullOrderSim&&) = default;
FullOrderSim::~FullOrderSim() = default;

float FullOrderSim::stable_dt() {
  if (config_.fixed_dt > 0.0f) return config_.fixed_dt;
  const float particle_speed = last_particle_speed_
                                   ? *last_particle_speed_
                                   : mpm::max_particle_speed(exec_, particles_.view(), speed_slot_.span());
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

void FullOrderSim::substep(float dt) {
  ROMP_CHECK(dt > 0.0f && std::isfinite(dt), fmt::format("substep dt must be finite and > 0, got {}", dt));
  release_ended_dirichlet_groups();
  if (domains_)
    for (const DomainReleaseSpec& release : config_.domain_releases)
      if (time_ >= release.start && time_ < release.end) mpm::release_domains(exec_, particles_.view(), release.region);
  mpm::StepParams step = inputs_.at(time_, dt);

  StageClock timed(stage_timeline_, stage_launches_);
  const float inverse_dx = 1.0f / config_.dx;
  // A grid that follows the sort serves until a particle's stencil leaves it: the last substep's G2P said so.
  const bool follows_sort = grid_follows_sort();
  const Span<float> left_grid_slot = inputs_.readback_row().values;  // empty when sort_every is 1
  const bool left_grid = follows_sort && sorted_ && inputs_.readback_values(0)[0] > 0.0f;
  const bool sort_now = !sorted_ || steps_ % sort_every_ == 0 || left_grid;
  // The stage runs empty between sorts, so the stage table keeps its rows.
  timed([&] {
    if (!sort_now) return;
    particles_.sort_by_block(exec_, inverse_dx);
    ++sorting_.sorts;
    if (sorted_ && steps_ % sort_every_ != 0) ++sorting_.early_sorts;
    if (follows_sort) memory::fill_zero(left_grid_slot.data(), exec_.backend, sizeof(float), exec_.stream);
  });
  sorted_ = true;
  const mpm::ParticleView particles = particles_.view();
  const mpm::DomainView domains = domains_ ? domains_->view() : mpm::DomainView{};
  timed([&] {
    if (!follows_sort)
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
  if (implicit_) timed([&] { implicit_->solve(exec_, particles, domains, grid, step, steps_ + 1); });
  timed([&] {
    mpm::grid_to_particle(
        exec_, particles, grid, step,
        follows_sort ? mpm::GridCoverage{particles_.sorted_block_keys(), left_grid_slot} : mpm::GridCoverage{});
  });
  if (domains_) {
    timed([&] { mpm::grid_to_corners(exec_, domains, grid, step); });
    timed([&] { mpm::corners_to_particles(exec_, particles, domains, step); });
  }
  if (inputs_.plastic()) timed([&] { mpm::project_plasticity(exec_, particles, step); });
  if (neural_) timed([&] { neural_->project_plasticity(exec_, particles, step); });
  if (tracers_) timed([&] { tracers_->advect(exec_, grid, step); });

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

void FullOrderSim::set_tracers(const std::vector<float>& X) {
  // Tracers embed in the domains as they are at the start, the reference configuration.
  mpm::DomainInit layout;
  if (domains_) {
    ROMP_CHECK(steps_ == 0, "tracers start with the run: they are embedded in the domains' reference configuration");
    layout.corner = domains_->corner_indices_on_host(exec_);
    layout.corner_x = domains_->corner_positions_on_host(exec_);
    layout.corner_dirichlet_group.assign(std::size_t(domains_->corner_count()), mpm::kNoDirichletGroup);
  }
  tracers_.emplace(exec_, X, layout);
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

void FullOrderSim::release_ended_dirichlet_groups() {
  for (std::size_t g = 0; g < config_.dirichlet.size(); ++g) {
    if (released_[g] || time_ < config_.dirichlet[g].end) continue;
    particles_.release_dirichlet_group(exec_, std::int32_t(g));
    if (domains_) domains_->release_dirichlet_group(exec_, std::int32_t(g));
    released_[g] = true;
  }
}

bool FullOrderSim::advance_to(double t, const std::function<bool()>& stop) {
  return advance_clock(
      time_, t, [this] { return double(stable_dt()); }, [this](float dt) { substep(dt); }, stop);
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
