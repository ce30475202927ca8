// ReducedSim: samples, quadrature kinematics from g, the MPM update at the samples, and the projections.
#include "host/engine/reduced_sim.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "host/engine/full_order_sim.h"
#include "host/engine/stage_clock.h"
#include "kernels/core/memory.h"
#include "kernels/mpm/step.h"
#include "kernels/rom/reduced_dynamics.h"

namespace romp::engine {
namespace {

// The reduced step transfers as the ROM paper's Alg. 5: PIC momentum (no affine part) with the MLS
// force, which romp's APIC kernels compute for points whose C is zero. A scene says "apic" (its
// full-order runs then carry C) or "pic-flip" with flip_alpha = 0, pure PIC, the paper's full-order
// model (Alg. 1): both run the same reduced step. FLIP would need each point's velocity history, which
// x̂ does not keep.
FullOrderConfig reduced_step_config(FullOrderConfig config) {
  if (config.transfer == mpm::Transfer::PicFlip) {
    ROMP_CHECK(config.flip_alpha == 0.0f,
               fmt::format("solver.flip_alpha = {}: the reduced-order step cannot blend in FLIP (x̂ keeps no "
                           "velocity history per point); use flip_alpha = 0 (PIC) or transfer = \"apic\"",
                           config.flip_alpha));
    config.transfer = mpm::Transfer::Apic;
  }
  return config;
}

// Whether the Lagrangian quadrature searches the samples' neighbours (see NeighbourSearch). A sample's
// neighbours have their base node within 2 of its own: at most 5³ cells' worth of points each.
bool wants_neighbour_search(const ReducedOptions& options, const mpm::ParticleInit& reference, float dx,
                            Index dirichlet_groups) {
  const Index n = reference.count();
  if (options.neighbour_search != NeighbourSearch::Auto) return options.neighbour_search == NeighbourSearch::Always;
  if (options.samples == 0 || options.samples >= n) return false;
  double volume = 0.0;
  for (const float v : reference.volume0) volume += v;
  const double points_per_cell = double(n) * double(dx) * dx * dx / volume;
  const double samples = double(options.samples + dirichlet_groups * options.boundary_samples);
  return samples * 125.0 * points_per_cell < 0.5 * double(n);
}

EulerianSettings eulerian_settings(const FullOrderConfig& config, const ReducedOptions& options) {
  EulerianSettings settings;
  settings.lattice.dx = config.dx;
  settings.lattice.points_per_cell = options.points_per_cell;
  for (int a = 0; a < 3; ++a) settings.lattice.domain_cells[a] = config.domain_cells[a];
  settings.lattice.prune = options.neighbour_search != NeighbourSearch::Never;
  settings.inversion.iterations = options.inversion_iterations;
  settings.inversion.tolerance = options.inversion_tolerance * config.dx;
  settings.warm_start = options.warm_start_inversion;
  for (const MaterialSpec& m : config.materials) settings.densities.push_back(m.density);
  return settings;
}

// The checks of the reduced step's configuration, before anything is built from it.
FullOrderConfig checked_config(FullOrderConfig config, const mpm::ParticleInit& reference,
                               const rom::DeformationMapWeights& map, const std::vector<float>& xhat,
                               const ReducedOptions& options) {
  config = reduced_step_config(std::move(config));
  // Particle domains are a full-order discretisation (they keep the snapshots a model is trained on free of
  // numerical fracture): the Lagrangian and Eulerian quadratures take the material points as plain
  // particles and ignore them, the domain quadrature transfers through them (and checks that they exist).
  for (const DirichletSpec& group : config.dirichlet)
    ROMP_CHECK(std::isinf(group.end), "dirichlet.end: a reduced run keeps its Dirichlet groups for the whole run");
  ROMP_CHECK(config.integrator == Integrator::Explicit,
             "solver.integrator = \"implicit\" is a full-order option: the reduced-order step is explicit "
             "(set solver.integrator = \"explicit\" or run the scene full-order)");
  ROMP_CHECK(reference.count() > 0, "a reduced simulation needs at least one material point");
  check_particle_tables(config, reference.material, reference.dirichlet_group);
  for (const MaterialSpec& m : config.materials) {
    ROMP_CHECK(!material::is_plastic(m.params.model),
               "the reduced-order model covers elastic materials (ROM paper, Sec. 3.2.2)");
    ROMP_CHECK(m.params.model != material::MaterialModel::Neural,
               "the reduced-order step evaluates analytic materials in its kernels; run a scene with neural laws "
               "full-order");
  }
  ROMP_CHECK(config.tractions.empty(),
             "loads.tractions act on material points the reduced step does not keep; run the scene full-order");
  ROMP_CHECK(Index(xhat.size()) == map.latent,
             fmt::format("x̂ holds {} values, the map's latent size is {}", xhat.size(), map.latent));
  ROMP_CHECK(options.samples >= 0 && options.boundary_samples >= 0, "sample counts must be >= 0");
  ROMP_CHECK(options.cfl >= 0.0 && options.cfl <= 1.0,
             fmt::format("the reduced substeps' CFL number must be in (0, 1] (0: the scene's), got {}", options.cfl));
  if (options.cfl > 0.0) config.cfl = float(options.cfl);
  ROMP_CHECK(options.gauss_newton_iterations >= 1 && options.gauss_newton_tolerance > 0.0,
             "Gauss–Newton needs at least one iteration and a tolerance > 0");
  ROMP_CHECK(
      options.points_per_cell >= 1 && options.points_per_cell <= 8,
      fmt::format("Eulerian quadrature points per cell per axis must be in [1, 8], got {}", options.points_per_cell));
  return config;
}

}  // namespace

ReducedSim::ReducedSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& reference,
                       rom::DeformationMapWeights map, std::vector<float> xhat, ReducedOptions options)
    : stream_(exec.backend),
      exec_(with_capturable_stream(exec, stream_)),
      config_(checked_config(std::move(config), reference, map, xhat, options)),
      inputs_(exec_, config_),
      grid_(exec.backend, config_.dx, /*keep_old_velocity=*/false),
      options_(options),
      map_(exec.backend, std::move(map)),
      reference_(exec.backend, reference),
      samples_(reference, Index(config_.dirichlet.size()), options.samples, options.boundary_samples, options.seed,
               map_.latent()),
      latent_(exec.backend, xhat, options.projection == RomProjection::PositionVelocity,
              {options.gauss_newton_iterations, options.gauss_newton_tolerance}),
      xhat_(std::move(xhat)),
      stage_timeline_(exec_) {
  // A row per substep: its failure slots and records, its samples' largest speed and [x̂ | v̂ | status |
  // the domains' stiffening].
  inputs_.reserve_readback(2 * map_.latent() + 2, kReadbackSlots, kMostSubstepsPerReadback);
  if (options_.quadrature == RomQuadrature::Lagrangian) {
    const bool search = wants_neighbour_search(options_, reference, config_.dx, Index(config_.dirichlet.size()));
    quadrature_ = &lagrangian_.emplace(exec_, reference_, map_.latent(), config_.dx, search);
  } else if (options_.quadrature == RomQuadrature::Domains) {
    quadrature_ = &domains_.emplace(exec_, reference_, reference.domains, reference.domain, map_.latent(),
                                    config_.enrichment_threshold);
  } else {
    quadrature_ = &eulerian_.emplace(exec_, reference, eulerian_settings(config_, options_));
  }

  // v̂ at t = 0: the least-squares fit of the initial velocities over every material point (Eq. 28).
  const Index n = reference_.count;
  DeviceBuffer<float> dg_all(exec_.backend, 3 * Index(map_.latent()) * n);
  map_.evaluate(exec_, latent_.xhat(), Vec3Planes<const float>(reference_.X.data(), n), {{}, {}, dg_all.span()});
  const DeviceBuffer<float> v0 = DeviceBuffer<float>::from_host(exec_.backend, reference.v);
  vhat_ = latent_.fit_velocity(exec_, dg_all.span(), Vec3Planes<const float>(v0.data(), n));
  if (vhat_.empty()) throw singular_projection();
  for (Index i = 0; i < 3 * n; ++i) max_sample_speed_ = std::max(max_sample_speed_, std::fabs(reference.v[i]));
  max_sample_speed_ *= std::sqrt(3.0f);  // a bound on |v| from its largest component
  last_sample_speed_ = max_sample_speed_;
  check_latent("the initial projection");

  const Index m = samples_.per_substep();
  graphs_possible_ = replays_graphs(options_.frame_graphs, exec_) &&
                     m * quadrature_->stencil_points_per_sample() <= mpm::SparseGrid::kFewPoints &&
                     quadrature_->builds_on_device(m) && latent_.projects_on_device(m);
  stages_ = {"samples", "kinematics", "grid_build", "p2g", "grid_update", "g2p", "projection"};
  if (graphs_possible_) stages_.emplace_back("frame_graphs");
}

Error ReducedSim::singular_projection() const {
  return Error(
      fmt::format("step {} (t = {:.6g} s): the projection's normal equations are singular (do the samples "
                  "move with the map at all?)",
                  steps_, time_));
}

float ReducedSim::stable_dt() const {
  if (config_.fixed_dt > 0.0f) return config_.fixed_dt;
  return std::min(config_.max_dt,
                  config_.cfl * quadrature_->cfl_length(config_.dx) / (wave_speed() + max_sample_speed_));
}

float ReducedSim::wave_speed() const { return inputs_.max_wave_speed() * std::sqrt(stiffening_); }

void ReducedSim::substeps(float dt, int count) {
  ROMP_CHECK(dt > 0.0f && std::isfinite(dt), fmt::format("substep dt must be finite and > 0, got {}", dt));
  ROMP_CHECK(count >= 1 && count <= kMostSubstepsPerReadback,
             fmt::format("substeps per read-back must be in [1, {}], got {}", kMostSubstepsPerReadback, count));
  // The frame's samples go up before its first launch, if at all: none of its substeps uploads.
  samples_.draw_ahead(exec_, count);
  if (!run_frame_graph(dt, count)) {
    double time = time_;
    for (int k = 0; k < count; ++k, time += dt) run_substep(inputs_.at(time, dt), -1);
  }
  accept_substeps(dt, count);
}

bool ReducedSim::run_frame_graph(float dt, int count) {
  // The first substeps run eagerly: they size the buffers (an allocation cannot be captured) and set the
  // warm starts' history.
  if (!graphs_possible_ || steps_ == 0) return false;
  const std::optional<StepInputs::FrameShape> inputs = inputs_.frame_shape(time_, dt, count);
  if (!inputs) return false;
  samples_.stage_frame(exec_, count);
  inputs_.start_frame(time_);
  int captured = -1;  // the substeps a capture ran the host code of; -1: none captured
  const StreamGraph* frame = nullptr;
  try {
    frame = &frame_graphs_.get(exec_, {*inputs, samples_.staged_rows().data()}, [&] {
      // The capture runs the substeps' host code (which takes their read-back rows) and none of their launches.
      for (captured = 0; captured < count; ++captured) run_substep(inputs_.at_in_frame(*inputs, captured), captured);
    });
  } catch (const Error& error) {
    // Nothing of the frame ran: its host code's account is taken back, and this frame and every later one run
    // substep by substep (the tests count the frames run as graphs, so a capture failing on the CPU shows).
    inputs_.discard_pending_rows();
    samples_.unstage_frame(count);
    quadrature_->account_builds(-std::max(captured, 0));
    graphs_possible_ = false;
    spdlog::warn("reduced-order frames run substep by substep from step {} on: capturing them as a graph failed: {}",
                 steps_, error.what());
    return false;
  }
  if (captured < 0) {
    // What the capture's host code does for a frame, done for this one.
    inputs_.claim_rows(count);
    quadrature_->account_builds(count);
  }
  replay_as_stage(*frame, exec_, stages_.size() - 1, stage_timeline_, stage_launches_);
  ++graph_frames_;
  return true;
}

void ReducedSim::run_substep(const mpm::StepParams& step, Index staged_substep) {
  const StepInputs::Row row = inputs_.readback_row();
  StageClock timed = staged_substep < 0 ? StageClock(stage_timeline_, stage_launches_) : StageClock::untimed();

  timed([&] {
    if (staged_substep < 0)
      samples_.draw(exec_, reference_);
    else
      samples_.draw_staged(exec_, reference_, staged_substep);
  });
  const Index m = samples_.count();
  // Alg. 3 / 4: the kinematics at x̂_n, v̂_n of the samples and of the quadrature points.
  mpm::ParticleView quadrature;
  timed([&] {
    samples_.decode(exec_, map_, latent_.xhat(), latent_.vhat());
    const Vec3Planes<float> sample_x(samples_.points().x.data(), m);
    keep_inside_domain(sample_x, row.slots, kSampleOutside);  // before the quadrature is placed around the samples
    quadrature = quadrature_->build(exec_, map_, samples_, latent_.xhat(), latent_.vhat());
    keep_inside_domain(quadrature_->material_positions(), row.slots, kQuadratureOutside, quadrature_->live_count());
  });
  // Alg. 5: P2G from the quadrature points, the grid update, G2P at the samples, on a grid of the samples'
  // stencils alone (with domains, their corners'): G2P reads no other node and the update goes node by node,
  // so the quadrature's shares elsewhere change nothing the samples see and are dropped. (An Eulerian sample
  // is no quadrature point, ROM paper, Fig. 6: a node of its stencil may get no mass, and its velocity is then
  // 0, as on the paper's dense grid.) A few samples' grid is built without reading its block count back.
  timed([&] {
    const Vec3Planes<const float> stencil_points = quadrature_->sample_stencil_points(samples_);
    if (stencil_points.count() <= mpm::SparseGrid::kFewPoints)
      grid_.rebuild_for_few_points(exec_, stencil_points);
    else
      grid_.rebuild(exec_, stencil_points);
  });
  const mpm::GridView grid = grid_.view();
  timed([&] { quadrature_->particles_to_grid(exec_, quadrature, grid, step); });
  timed([&] { mpm::update_grid(exec_, grid, step); });
  timed([&] { quadrature_->grid_to_samples(exec_, samples_, grid, step); });
  // Alg. 6 / 7: v̂_{n+1} and x̂_{n+1}, solved where the system is, then what the read-back needs of this
  // substep copied into its row before the next substep reuses the buffers: the new state and the points
  // that the failure slots name.
  timed([&] {
    latent_.project(exec_, map_, samples_, step.dt);
    const Span<const float> state = latent_.state();
    memory::copy(row.values.data(), exec_.backend, state.data(), exec_.backend,
                 std::size_t(state.size()) * sizeof(float), exec_.stream);
    const Span<const float> stiffening = quadrature_->stiffening();
    if (!stiffening.empty())
      memory::copy(row.values.data() + state.size(), exec_.backend, stiffening.data(), exec_.backend, sizeof(float),
                   exec_.stream);
    const mpm::PointSource sample_points{samples_.x(), samples_.X(), samples_.index()};
    const mpm::PointSource quadrature_points = quadrature_->failure_source();
    auto record = [&row](FailedPointRecord r) {
      return row.slots.subspan(kFirstRecord + r * mpm::kFailedPointWords, mpm::kFailedPointWords);
    };
    const mpm::FailedPointNotes notes = {
        mpm::FailedPointNote{step.first_failure.subspan(int(mpm::Stage::P2G), 1), quadrature_points, record(kP2GPoint)},
        mpm::FailedPointNote{step.first_failure.subspan(int(mpm::Stage::G2P), 1), sample_points, record(kG2PPoint)},
        mpm::FailedPointNote{row.slots.subspan(kSampleOutside, 1), sample_points, record(kSampleOutsidePoint)},
        mpm::FailedPointNote{row.slots.subspan(kQuadratureOutside, 1), quadrature_->outside_source(),
                             record(kQuadratureOutsidePoint)}};
    mpm::note_failed_points(exec_, notes, int(notes.size()));
  });
}

void ReducedSim::accept_substeps(float dt, int count) {
  const int r = map_.latent();
  // One round trip for all the substeps.
  ROMP_CHECK(inputs_.read_back() == count, "a read-back per accept_substeps");
  float speed = 0.0f;
  const double wave_speed = this->wave_speed();
  const double cfl_length = quadrature_->cfl_length(config_.dx);
  const bool stiffens = !quadrature_->stiffening().empty();
  float stiffening = 1.0f;
  for (int k = 0; k < count; ++k) {
    // The points outside the domain and the stages' failure slots (reported in this order, and before the
    // projection's result: each later stage ran on what the earlier one found), then the new state. A
    // failure leaves xhat_, vhat_, time_ and steps_ as they were before the substep.
    throw_if_outside_domain(k);
    inputs_.check_stages(k, "reduced simulation: ", steps_, time_, [this, k](mpm::Stage stage, std::int64_t) {
      // P2G runs over the quadrature points and G2P over the samples, reported as their material points (a
      // reduced step has no plasticity: its materials are elastic).
      if (stage == mpm::Stage::P2G) {
        const mpm::FailedPoint point = failed_point(k, kP2GPoint);
        return std::pair<std::int64_t, std::string>(point.particle, quadrature_->describe(point));
      }
      const std::int64_t point = failed_point(k, kG2PPoint).particle;
      return std::pair<std::int64_t, std::string>(point, fmt::format("sample material point {}", point));
    });
    const Span<const float> latent = inputs_.readback_values(k);
    if (latent[2 * r] != rom::kLatentSolved) throw singular_projection();
    xhat_.assign(latent.begin(), latent.begin() + r);
    vhat_.assign(latent.begin() + r, latent.begin() + 2 * r);
    if (stiffens) stiffening = std::max(stiffening, latent[2 * r + 1]);
    check_latent("the projection");
    largest_cfl_ = std::max(largest_cfl_, double(dt) * (wave_speed + last_sample_speed_) / cfl_length);
    last_sample_speed_ = inputs_.largest_speed(k);
    speed = std::max(speed, last_sample_speed_);
    time_ += dt;
    ++steps_;
  }
  // The next substeps' CFL step holds for the fastest the samples went in these, and the stiffest their domains
  // were.
  max_sample_speed_ = speed;
  stiffening_ = stiffening;
}

mpm::FailedPoint ReducedSim::failed_point(int row, FailedPointRecord record) const {
  return mpm::read_failed_point(
      inputs_.readback_slots(row).subspan(kFirstRecord + record * mpm::kFailedPointWords, mpm::kFailedPointWords));
}

void ReducedSim::check_latent(const char* stage) const {
  auto finite = [](const std::vector<float>& v) {
    return std::all_of(v.begin(), v.end(), [](float value) { return std::isfinite(value); });
  };
  if (!finite(xhat_) || !finite(vhat_))
    throw NonFiniteError(fmt::format("reduced simulation: x̂ or v̂ is not finite after {} at step {} (t = {:.6g} s)",
                                     stage, steps_, time_),
                         steps_, mpm::Stage::G2P, -1);
}

void ReducedSim::keep_inside_domain(Vec3Planes<float> x, Span<std::int64_t> row_slots, ReadbackSlot slot,
                                    Span<const std::int64_t> live) {
  rom::keep_points_inside(exec_, x, config_.domain(), config_.dx, row_slots.subspan(slot, 1), live);
}

void ReducedSim::throw_if_outside_domain(int row) {
  const Span<const std::int64_t> slots = inputs_.readback_slots(row);
  const bool sample = slots[kSampleOutside] != rom::kNoPointOutside;
  if (!sample && slots[kQuadratureOutside] == rom::kNoPointOutside) return;
  const mpm::FailedPoint failed = failed_point(row, sample ? kSampleOutsidePoint : kQuadratureOutsidePoint);
  const std::int64_t point = failed.particle;
  // g at the point's reference position and the substep's x̂ (xhat_ until the substep succeeds).
  const std::vector<float> X_host = {failed.X[0], failed.X[1], failed.X[2]};
  const DeviceBuffer<float> X = DeviceBuffer<float>::from_host(exec_.backend, X_host, exec_.stream);
  const DeviceBuffer<float> xhat = DeviceBuffer<float>::from_host(exec_.backend, xhat_, exec_.stream);
  DeviceBuffer<float> x(exec_.backend, 3);
  map_.evaluate(exec_, xhat.span(), Vec3Planes<const float>(X.data(), 1), {Vec3Planes<float>(x.data(), 1), {}, {}});
  const std::vector<float> position = x.to_host(exec_.stream);
  const mpm::Domain domain = config_.domain();
  Vec3<float> low, high;
  for (int a = 0; a < 3; ++a) {
    low[a] = domain.low_bound(config_.dx);
    high[a] = domain.high_bound(a, config_.dx);
  }
  const std::string name = sample ? fmt::format("material point {}", point) : quadrature_->describe_outside(point);
  throw NonFiniteError(
      fmt::format(
          "reduced simulation: {} decodes to ({:.4g}, {:.4g}, {:.4g}) m at step {} (t = {:.6g} "
          "s), outside the domain's interior [{:.4g}, {:.4g}] x [{:.4g}, {:.4g}] x [{:.4g}, {:.4g}] m: x̂ = [{}] "
          "has left the states the map describes (the reduced dynamics diverged)",
          name, position[0], position[1], position[2], steps_, time_, low[0], high[0], low[1], high[1], low[2], high[2],
          fmt::join(xhat_, ", ")),
      steps_, mpm::Stage::P2G, point);
}

std::vector<std::pair<std::string, double>> ReducedSim::stage_seconds() const {
  return stage_table(stages_, stage_timeline_);
}

std::vector<std::pair<std::string, std::int64_t>> ReducedSim::stage_launches() const {
  return stage_launch_table(stages_, stage_launches_);
}

std::int64_t ReducedSim::unconverged_projections() const { return latent_.gauss_newton_state(exec_).unconverged_total; }

std::int64_t ReducedSim::gauss_newton_linearisations() const {
  return latent_.gauss_newton_state(exec_).linearisations_total;
}

rom::QuadratureTally ReducedSim::quadrature_tally() const {
  return eulerian_ ? eulerian_->tally(exec_) : rom::QuadratureTally{};
}

bool ReducedSim::advance_to(double t, const std::function<bool()>& stop) {
  // Substeps within this fraction over the stable step are allowed, as advance_clock merges a sliver.
  constexpr double kMergeFraction = 1e-3;
  while (time_ < t) {
    if (stop && stop()) return false;
    const double dt = stable_dt(), remaining = t - time_;
    const double needed = std::ceil(remaining / (dt * (1.0 + kMergeFraction)));
    if (needed > kMostSubstepsPerReadback) {
      substeps(float(dt), kMostSubstepsPerReadback);
      continue;
    }
    substeps(float(remaining / needed), int(needed));
    // The clock takes t itself, not the sum of the float substeps.
    time_ = t;
  }
  return true;
}

ReducedSim::DecodedState ReducedSim::decode(const std::vector<float>& X_host) {
  ROMP_CHECK(X_host.size() % 3 == 0, "reference points come as 3 planes");
  const Index n = Index(X_host.size() / 3);
  if (n == 0) return {};
  const Backend backend = exec_.backend;
  const DeviceBuffer<float> X = DeviceBuffer<float>::from_host(backend, X_host, exec_.stream);
  const int r = map_.latent();
  DeviceBuffer<float> x(backend, 3 * n), F(backend, 9 * n), v(backend, 3 * n), dg(backend, 3 * Index(r) * n);
  map_.evaluate(exec_, latent_.xhat(), Vec3Planes<const float>(X.data(), n),
                {Vec3Planes<float>(x.data(), n), Mat3Planes<float>(F.data(), n), dg.span()});
  rom::latent_to_point_velocity(exec_, r, dg.span(), latent_.vhat(), Vec3Planes<float>(v.data(), n));
  return {x.to_host(exec_.stream), F.to_host(exec_.stream), v.to_host(exec_.stream)};
}

std::vector<float> ReducedSim::decode_positions() {
  const Index n = reference_.count;
  DeviceBuffer<float> x(exec_.backend, 3 * n);
  map_.evaluate(exec_, latent_.xhat(), Vec3Planes<const float>(reference_.X.data(), n),
                {Vec3Planes<float>(x.data(), n), {}, {}});
  return x.to_host(exec_.stream);
}

}  // namespace romp::engine
