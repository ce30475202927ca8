// ReducedSim: samples, quadrature kinematics from g, the MPM update at the samples, and the projections.
#include "host/engine/reduced_sim.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>

#include "host/engine/full_order_sim.h"
#include "host/engine/stage_clock.h"
#include "host/geometry/bounds.h"
#include "kernels/core/fill.h"
#include "kernels/core/gather_planes.h"
#include "kernels/math/cholesky_solve.h"
#include "kernels/mpm/step.h"
#include "kernels/rom/reduced_dynamics.h"
#include "kernels/rom/stencil_neighbours.h"

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

// k distinct members of `pool`, drawn uniformly (Floyd's algorithm: k draws, no pass over the pool).
std::vector<std::int32_t> draw_distinct(const std::vector<std::int32_t>& pool, std::size_t k,
                                        geometry::Random& random) {
  const std::size_t n = pool.size();
  if (k >= n) return pool;
  std::unordered_set<std::size_t> chosen;
  for (std::size_t j = n - k; j < n; ++j) {
    const std::size_t t = std::size_t(random.below(j + 1));
    chosen.insert(chosen.count(t) ? j : t);
  }
  std::vector<std::int32_t> members;
  for (const std::size_t i : chosen) members.push_back(pool[i]);
  return members;
}

template <class T>
void gather(const Exec& exec, const DeviceBuffer<T>& source, Index source_count, int components,
            Span<const std::int32_t> index, DeviceBuffer<T>& destination) {
  gather_planes(exec, source.span(), source_count, components, index, destination.span());
}

Vec3<float> planes_at(const std::vector<float>& planes, Index n, Index i) {
  return Vec3<float>(planes[i], planes[n + i], planes[2 * n + i]);
}

}  // namespace

void ReducedSim::Quadrature::allocate(Backend backend, Index n) {
  count = n;
  capacity = n;
  for (DeviceBuffer<float>* planes : {&x, &X, &v}) *planes = DeviceBuffer<float>(backend, 3 * n);
  F = DeviceBuffer<float>(backend, 9 * n);
  C = DeviceBuffer<float>(backend, 9 * n);
  C.fill_zero();  // quadrature points carry no affine velocity: the transfer is PIC (ROM paper, Alg. 5)
  mass = DeviceBuffer<float>(backend, n);
  volume0 = DeviceBuffer<float>(backend, n);
  for (DeviceBuffer<std::int32_t>* ints : {&material, &group, &id, &status})
    *ints = DeviceBuffer<std::int32_t>(backend, n);
}

bool ReducedSim::Quadrature::resize(Backend backend, Index n) {
  const bool grows = n > capacity;
  if (grows) allocate(backend, n + n / 4);
  count = n;
  return grows;
}

void ReducedSim::Quadrature::gather_from(const Exec& exec, const Quadrature& source, Span<const std::int32_t> index) {
  const Index n = source.count;
  resize(exec.backend, index.size());
  gather(exec, source.x, n, 3, index, x);
  gather(exec, source.X, n, 3, index, X);
  gather(exec, source.v, n, 3, index, v);
  gather(exec, source.F, n, 9, index, F);
  gather(exec, source.mass, n, 1, index, mass);
  gather(exec, source.volume0, n, 1, index, volume0);
  gather(exec, source.material, n, 1, index, material);
  gather(exec, source.group, n, 1, index, group);
  gather(exec, source.id, n, 1, index, id);
}

mpm::ParticleView ReducedSim::Quadrature::view() {
  const Index n = count;
  return mpm::ParticleView{n,
                           Vec3Planes<float>(x.data(), n),
                           Vec3Planes<float>(v.data(), n),
                           Mat3Planes<float>(C.data(), n),
                           Mat3Planes<float>(F.data(), n),
                           mass.prefix(n),
                           volume0.prefix(n),
                           material.prefix(n),
                           group.prefix(n),
                           id.prefix(n)};
}

ReducedSim::ReducedSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& reference,
                       rom::DeformationMapWeights map, std::vector<float> xhat, ReducedOptions options)
    : exec_(exec),
      config_(reduced_step_config(std::move(config))),
      inputs_(exec, config_),
      grid_(exec.backend, config_.dx, /*keep_old_velocity=*/false),
      options_(options),
      map_(std::move(map)),
      latent_(map_.latent),
      points_(reference.count()),
      random_(options.seed),
      stage_timeline_(exec) {
  // Particle domains are a full-order discretisation (they keep the snapshots a model is trained on
  // free of numerical fracture); the reduced model's material points are the particles themselves,
  // so `reference.domain` and `reference.domains` are not used here.
  for (const DirichletSpec& group : config_.dirichlet)
    ROMP_CHECK(std::isinf(group.end), "dirichlet.end: a reduced run keeps its Dirichlet groups for the whole run");
  const Backend backend = exec.backend;
  const Index n = points_;
  ROMP_CHECK(config_.integrator == Integrator::Explicit,
             "solver.integrator = \"implicit\" is a full-order option: the reduced-order step is explicit "
             "(set solver.integrator = \"explicit\" or run the scene full-order)");
  ROMP_CHECK(n > 0, "a reduced simulation needs at least one material point");
  check_particle_tables(config_, reference.material, reference.dirichlet_group);
  ROMP_CHECK(!inputs_.plastic(), "the reduced-order model covers elastic materials (ROM paper, Sec. 3.2.2)");
  ROMP_CHECK(config_.tractions.empty(),
             "loads.tractions act on material points the reduced step does not keep; run the scene full-order");
  for (const MaterialSpec& m : config_.materials)
    ROMP_CHECK(
        m.params.model != material::MaterialModel::Neural,
        "the reduced-order step evaluates analytic materials in its kernels; run a scene with neural laws full-order");
  ROMP_CHECK(Index(xhat.size()) == latent_,
             fmt::format("x̂ holds {} values, the map's latent size is {}", xhat.size(), latent_));
  ROMP_CHECK(options_.samples >= 0 && options_.boundary_samples >= 0, "sample counts must be >= 0");
  ROMP_CHECK(options_.cfl >= 0.0 && options_.cfl <= 1.0,
             fmt::format("the reduced substeps' CFL number must be in (0, 1] (0: the scene's), got {}", options_.cfl));
  if (options_.cfl > 0.0) config_.cfl = float(options_.cfl);
  ROMP_CHECK(options_.gauss_newton_iterations >= 1 && options_.gauss_newton_tolerance > 0.0,
             "Gauss–Newton needs at least one iteration and a tolerance > 0");
  ROMP_CHECK(
      options_.points_per_cell >= 1 && options_.points_per_cell <= 8,
      fmt::format("Eulerian quadrature points per cell per axis must be in [1, 8], got {}", options_.points_per_cell));

  map_parameters_ = DeviceBuffer<float>::from_host(backend, map_.parameters);
  X_ = DeviceBuffer<float>::from_host(backend, reference.x);
  mass_ = DeviceBuffer<float>::from_host(backend, reference.mass);
  volume0_ = DeviceBuffer<float>::from_host(backend, reference.volume0);
  material_ = DeviceBuffer<std::int32_t>::from_host(backend, reference.material);
  dirichlet_group_ = DeviceBuffer<std::int32_t>::from_host(backend, reference.dirichlet_group);
  std::vector<std::int32_t> ids(static_cast<std::size_t>(n));
  std::iota(ids.begin(), ids.end(), 0);
  id_ = DeviceBuffer<std::int32_t>::from_host(backend, ids);
  group_members_.resize(config_.dirichlet.size());
  for (Index p = 0; p < n; ++p) {
    const std::int32_t group = reference.dirichlet_group[std::size_t(p)];
    (group == mpm::kNoDirichletGroup ? free_points_ : group_members_[std::size_t(group)]).push_back(std::int32_t(p));
  }
  system_ = DeviceBuffer<double>(backend, Index(latent_) * latent_ + latent_ + 1);
  first_outside_ = DeviceBuffer<std::int64_t>(backend, 1);
  xhat_ = std::move(xhat);
  latent_device_ = DeviceBuffer<float>(backend, 2 * Index(latent_) + 1);
  upload(backend, xhat_device(), Span<const float>(xhat_.data(), latent_), exec_.stream);
  speed_slot_ = DeviceBuffer<float>(backend, 1);
  if (options_.projection == RomProjection::PositionVelocity) {
    std::vector<float> history(xhat_);
    history.insert(history.end(), xhat_.begin(), xhat_.end());
    xhat_history_ = DeviceBuffer<float>::from_host(backend, history, exec_.stream);
    projection_state_ = DeviceBuffer<rom::GaussNewtonState>(backend, 1);
    projection_state_.fill_zero(exec_.stream);
  }

  if (options_.quadrature == RomQuadrature::Lagrangian) {
    search_neighbours_ = wants_neighbour_search(options_, reference, config_.dx, Index(group_members_.size()));
    if (search_neighbours_) {
      positions_ = DeviceBuffer<float>(backend, 3 * n);
      marked_ = DeviceBuffer<std::int32_t>(backend, n);
      quadrature_index_ = DeviceBuffer<std::int32_t>(backend, n);
    } else {
      every_point_quadrature();
    }
  } else {
    build_occupancy(reference);
    tally_ = DeviceBuffer<rom::QuadratureTally>(backend, 1);
    tally_.fill_zero(exec_.stream);
  }

  // v̂ at t = 0: the least-squares fit of the initial velocities over every material point (Eq. 28).
  DeviceBuffer<float> dg_all(backend, 3 * Index(latent_) * n);
  evaluate_map(Vec3Planes<const float>(X_.data(), n), {{}, {}, dg_all.span()});
  const DeviceBuffer<float> v0 = DeviceBuffer<float>::from_host(backend, reference.v);
  const std::vector<double> fit = solve_projection(dg_all.span(), Vec3Planes<const float>(v0.data(), n), {}).first;
  vhat_.assign(fit.begin(), fit.end());
  upload(backend, vhat_device(), Span<const float>(vhat_.data(), latent_), exec_.stream);
  for (Index i = 0; i < 3 * n; ++i) max_sample_speed_ = std::max(max_sample_speed_, std::fabs(reference.v[i]));
  max_sample_speed_ *= std::sqrt(3.0f);  // a bound on |v| from its largest component
  check_latent("the initial projection");

  stages_ = {"samples", "kinematics", "grid_build", "p2g", "grid_update", "g2p", "projection"};
}

void ReducedSim::build_occupancy(const mpm::ParticleInit& reference) {
  const Index n = reference.count();
  // Cells as fine as the finest sampling: h = cbrt(the smallest particle volume).
  const float h = std::cbrt(*std::min_element(reference.volume0.begin(), reference.volume0.end()));
  const geometry::Bounds box = geometry::bounds_of_planes(reference.x, n);
  const Vec3<float> low(float(box.low[0]), float(box.low[1]), float(box.low[2]));
  const Vec3<float> high(float(box.high[0]), float(box.high[1]), float(box.high[2]));
  rom::ReferenceOccupancy occupancy;
  occupancy.inverse_h = 1.0f / h;
  // The origin on the sampling lattice (points at (i + ½) h), so a lattice point's cube is one cell.
  for (int a = 0; a < 3; ++a) {
    occupancy.origin[a] = (std::floor(low[a] / h) - 2.0f) * h;
    occupancy.cells[a] = int(std::ceil((high[a] - occupancy.origin[a]) / h)) + 3;
  }
  const Index cells = Index(occupancy.cells[0]) * occupancy.cells[1] * occupancy.cells[2];
  ROMP_CHECK(cells < (Index(1) << 31), "the reference configuration's occupancy grid would exceed 2^31 cells");
  std::vector<std::int32_t> material_plus_one(static_cast<std::size_t>(cells), 0);
  // Each point owns the cells whose centres lie in its cube of side cbrt(volume) about it.
  for (Index p = 0; p < n; ++p) {
    const float half = 0.5f * std::cbrt(reference.volume0[p]);
    int first[3], last[3];
    for (int a = 0; a < 3; ++a) {
      const float X = reference.x[a * n + p];
      first[a] = std::max(0, int(std::ceil((X - half - occupancy.origin[a]) / h - 0.5f)));
      last[a] = std::min(occupancy.cells[a] - 1, int(std::ceil((X + half - occupancy.origin[a]) / h - 0.5f)) - 1);
    }
    for (int k = first[2]; k <= last[2]; ++k)
      for (int j = first[1]; j <= last[1]; ++j)
        for (int i = first[0]; i <= last[0]; ++i)
          material_plus_one[std::size_t((Index(k) * occupancy.cells[1] + j) * occupancy.cells[0] + i)] =
              reference.material[p] + 1;
  }
  occupancy_cells_ = DeviceBuffer<std::int32_t>::from_host(exec_.backend, material_plus_one);
  occupancy.material_plus_one = Span<const std::int32_t>(occupancy_cells_.data(), occupancy_cells_.size());
  occupancy_ = occupancy;
  std::vector<float> densities;
  for (const MaterialSpec& m : config_.materials) densities.push_back(m.density);
  densities_ = DeviceBuffer<float>::from_host(exec_.backend, densities);
}

rom::DeformationMapView<float> ReducedSim::map_view() const {
  return rom::map_view(map_, Span<const float>(map_parameters_.data(), map_parameters_.size()));
}

void ReducedSim::evaluate_map(Vec3Planes<const float> X, const rom::DeformationMapOutputs<float>& out) {
  rom::evaluate_deformation_map<float>(exec_, map_view(), xhat_device(), X, out);
}

std::pair<std::vector<double>, double> ReducedSim::solve_projection(Span<const float> dg_dxhat,
                                                                    Vec3Planes<const float> target,
                                                                    Vec3Planes<const float> reference) {
  const int r = latent_;
  rom::normal_equations(exec_, r, dg_dxhat, target, reference, system_.span());
  std::vector<double> system = system_.to_host(exec_.stream);
  std::vector<double> y(system.begin() + r * r, system.begin() + r * r + r);
  const double squared_residual = system.back();
  if (!cholesky_solve(r, system.data(), y.data())) throw singular_projection();
  return {y, squared_residual};
}

Error ReducedSim::singular_projection() const {
  return Error(
      fmt::format("step {} (t = {:.6g} s): the projection's normal equations are singular (do the samples "
                  "move with the map at all?)",
                  steps_, time_));
}

std::vector<std::int32_t> ReducedSim::choose_samples() {
  const Index wanted = options_.samples;
  if (wanted == 0 || wanted >= points_) {
    std::vector<std::int32_t> all(static_cast<std::size_t>(points_));
    std::iota(all.begin(), all.end(), 0);
    return all;
  }
  std::vector<std::int32_t> samples;
  for (const std::vector<std::int32_t>& members : group_members_) {
    const std::vector<std::int32_t> drawn = draw_distinct(members, std::size_t(options_.boundary_samples), random_);
    samples.insert(samples.end(), drawn.begin(), drawn.end());
  }
  const std::vector<std::int32_t> drawn = draw_distinct(free_points_, std::size_t(wanted), random_);
  samples.insert(samples.end(), drawn.begin(), drawn.end());
  // Increasing order: gathers read memory forwards, and the sums of a projection have one order.
  std::sort(samples.begin(), samples.end());
  return samples;
}

void ReducedSim::resize_samples(Index m) {
  if (samples_.count == m) return;
  samples_.allocate(exec_.backend, m);
  sample_dg_dxhat_ = DeviceBuffer<float>(exec_.backend, 3 * Index(latent_) * m);
  model_x_ = DeviceBuffer<float>(exec_.backend, 3 * m);
}

float ReducedSim::stable_dt() const {
  if (config_.fixed_dt > 0.0f) return config_.fixed_dt;
  return std::min(config_.max_dt, config_.cfl * config_.dx / (inputs_.max_wave_speed() + max_sample_speed_));
}

void ReducedSim::gather_reference(Span<const std::int32_t> index, Quadrature& points) {
  const Index n = points_;
  gather(exec_, X_, n, 3, index, points.X);
  gather(exec_, mass_, n, 1, index, points.mass);
  gather(exec_, volume0_, n, 1, index, points.volume0);
  gather(exec_, material_, n, 1, index, points.material);
  gather(exec_, dirichlet_group_, n, 1, index, points.group);
  gather(exec_, id_, n, 1, index, points.id);
}

void ReducedSim::every_point_quadrature() {
  // Every material point is a quadrature point: its mass, volume and tables never change.
  const Backend backend = exec_.backend;
  quadrature_.allocate(backend, points_);
  quadrature_.X = X_.clone();
  quadrature_.mass = mass_.clone();
  quadrature_.volume0 = volume0_.clone();
  quadrature_.material = material_.clone();
  quadrature_.group = dirichlet_group_.clone();
  quadrature_.id = id_.clone();
  dg_dxhat_ = DeviceBuffer<float>(backend, 3 * Index(latent_) * points_);
}

mpm::ParticleView ReducedSim::lagrangian_quadrature(Index m) {
  if (search_neighbours_) {
    // Alg. 3, steps 2-3: the points whose stencils reach the samples' grid nodes, found from g's
    // positions at every point.
    const Index n = points_;
    const float inverse_dx = 1.0f / config_.dx;
    evaluate_map(Vec3Planes<const float>(X_.data(), n), {Vec3Planes<float>(positions_.data(), n), {}, {}});
    const Span<const std::uint64_t> near_bases =
        neighbourhood_.near_bases(exec_, Vec3Planes<const float>(samples_.x.data(), m), inverse_dx);
    rom::mark_stencil_neighbours(exec_, Vec3Planes<const float>(positions_.data(), n), inverse_dx, near_bases,
                                 marked_.span());
    // Compacted on the device, in reference order.
    const Index count = select_indices_(exec_, marked_.span(), 1, quadrature_index_.span());
    quadrature_.resize(exec_.backend, count);
    const Span<const std::int32_t> index = quadrature_index_.prefix(count);
    gather_reference(index, quadrature_);
    // The positions the search saw, so P2G bins each point exactly where it was found.
    gather(exec_, positions_, n, 3, index, quadrature_.x);
    if (dg_dxhat_.size() < 3 * Index(latent_) * quadrature_.count)
      dg_dxhat_ = DeviceBuffer<float>(exec_.backend, 3 * Index(latent_) * quadrature_.capacity);
  }
  const Index q = quadrature_.count;
  lagrangian_points_ += q;
  const Span<float> dg_dxhat(dg_dxhat_.data(), 3 * Index(latent_) * q);
  const Vec3Planes<float> x = search_neighbours_ ? Vec3Planes<float>() : Vec3Planes<float>(quadrature_.x.data(), q);
  evaluate_map(Vec3Planes<const float>(quadrature_.X.data(), q),
               {x, Mat3Planes<float>(quadrature_.F.data(), q), dg_dxhat});
  rom::latent_to_point_velocity(exec_, latent_, dg_dxhat, vhat_device(), Vec3Planes<float>(quadrature_.v.data(), q));
  return quadrature_.view();
}

mpm::ParticleView ReducedSim::eulerian_quadrature(Index m) {
  // Alg. 4, step 3: ℓ³ points in each cell whose points may reach a sample's grid nodes, of which only
  // those whose stencils reach them (NeighbourSearch::Never keeps them all), built on the device.
  rom::EulerianLattice lattice;
  lattice.dx = config_.dx;
  lattice.points_per_cell = options_.points_per_cell;
  for (int a = 0; a < 3; ++a) lattice.domain_cells[a] = config_.domain_cells[a];
  lattice.prune = options_.neighbour_search != NeighbourSearch::Never;
  const Index count = neighbourhood_.build_eulerian_points(exec_, Vec3Planes<const float>(samples_.X.data(), m),
                                                           Vec3Planes<const float>(samples_.x.data(), m),
                                                           Mat3Planes<const float>(samples_.F.data(), m), lattice);
  // The count changes nearly every substep: the buffers grow with headroom and are otherwise reused.
  if (quadrature_.resize(exec_.backend, count)) {
    // No Eulerian point is a material point or in a Dirichlet group; set once for the whole capacity.
    const Index capacity = quadrature_.capacity;
    std::vector<std::int32_t> none(static_cast<std::size_t>(capacity), mpm::kNoDirichletGroup), ids(none.size());
    std::iota(ids.begin(), ids.end(), 0);
    quadrature_.group.copy_from_host(Span<const std::int32_t>(none.data(), capacity), exec_.stream);
    quadrature_.id.copy_from_host(Span<const std::int32_t>(ids.data(), capacity), exec_.stream);
  }
  inversion_iterations_.ensure_size(exec_.backend, count);
  map_evaluations_.ensure_size(exec_.backend, count);
  jacobian_evaluations_.ensure_size(exec_.backend, count);
  guesses_.ensure_size(exec_.backend, 3 * count);
  guess_jacobians_.ensure_size(exec_.backend, 9 * count);
  const Vec3Planes<float> guess(guesses_.data(), count);
  const Mat3Planes<float> guess_jacobian(guess_jacobians_.data(), count);
  neighbourhood_.write_eulerian_points(exec_, Vec3Planes<float>(quadrature_.x.data(), count), guess, guess_jacobian);
  const float dx = config_.dx;
  const int l = options_.points_per_cell;
  rom::InversionOptions inversion;
  inversion.iterations = options_.inversion_iterations;
  inversion.tolerance = options_.inversion_tolerance * dx;
  const rom::EulerianPointsOut points{Vec3Planes<float>(quadrature_.X.data(), count),
                                      Vec3Planes<float>(quadrature_.v.data(), count),
                                      Mat3Planes<float>(quadrature_.F.data(), count),
                                      quadrature_.mass.prefix(count),
                                      quadrature_.volume0.prefix(count),
                                      quadrature_.material.prefix(count),
                                      quadrature_.status.prefix(count),
                                      inversion_iterations_.prefix(count),
                                      map_evaluations_.prefix(count),
                                      jacobian_evaluations_.prefix(count)};
  rom::eulerian_quadrature(exec_, map_view(), xhat_device(), vhat_device(), occupancy_, densities_.span(),
                           dx * dx * dx / float(l * l * l), inversion,
                           Vec3Planes<const float>(quadrature_.x.data(), count), Vec3Planes<const float>(guess),
                           Mat3Planes<const float>(guess_jacobian), points);
  rom::tally_quadrature(exec_, points, count, tally_.span());
  const Span<const std::int32_t> status = quadrature_.status.prefix(count);
  // Points outside the body (or unconverged) carry no mass; P2G would evaluate a stress and activate
  // grid blocks for each of them, so the used points are gathered into a set of their own, P2G's.
  used_index_.ensure_size(exec_.backend, count);
  const Index used = select_indices_(exec_, status, rom::kQuadratureUsed, used_index_.span());
  used_quadrature_.gather_from(exec_, quadrature_, used_index_.prefix(used));
  return used_quadrature_.view();
}

void ReducedSim::substep(float dt) {
  ROMP_CHECK(dt > 0.0f && std::isfinite(dt), fmt::format("substep dt must be finite and > 0, got {}", dt));
  const Index n = points_;
  const int r = latent_;
  const mpm::StepParams step = inputs_.at(time_, dt);
  StageClock timed(stage_timeline_);

  Index m = 0;
  timed([&] {
    const std::vector<std::int32_t> chosen = choose_samples();
    m = Index(chosen.size());
    resize_samples(m);
    gather_reference(sample_index_.upload_front(exec_.backend, chosen, exec_.stream), samples_);
  });

  // Alg. 3 / 4: the kinematics at x̂_n, v̂_n of the samples and of the quadrature points.
  mpm::ParticleView quadrature;
  timed([&] {
    evaluate_map(
        Vec3Planes<const float>(samples_.X.data(), m),
        {Vec3Planes<float>(samples_.x.data(), m), Mat3Planes<float>(samples_.F.data(), m), sample_dg_dxhat_.span()});
    rom::latent_to_point_velocity(exec_, r, sample_dg_dxhat_.span(), vhat_device(),
                                  Vec3Planes<float>(samples_.v.data(), m));
    quadrature = options_.quadrature == RomQuadrature::Lagrangian ? lagrangian_quadrature(m) : eulerian_quadrature(m);
  });
  check_inside_domain(samples_.x, m, sample_index_.prefix(m));
  if (options_.quadrature == RomQuadrature::Lagrangian)
    check_inside_domain(quadrature_.x, quadrature_.count,
                        search_neighbours_ ? quadrature_index_.prefix(quadrature_.count) : Span<const std::int32_t>());
  // Alg. 5: P2G from the quadrature points, the grid update, G2P at the samples. The grid is built from
  // the samples too: an Eulerian sample is not a quadrature point (ROM paper, Fig. 6), and near the body's
  // surface its stencil can reach a block no quadrature point touches. G2P must find that block active
  // (an inactive one has no node storage to read); its nodes carry no mass, so their velocity is 0, as
  // on the paper's dense grid.
  timed([&] {
    grid_.rebuild(exec_, Vec3Planes<const float>(quadrature.x), Vec3Planes<const float>(samples_.x.data(), m));
  });
  const mpm::GridView grid = grid_.view();
  timed([&] { mpm::particle_to_grid(exec_, quadrature, grid, step); });
  timed([&] { mpm::update_grid(exec_, grid, step); });
  const mpm::ParticleView samples = samples_.view();
  timed([&] { mpm::grid_to_particle(exec_, samples, grid, step); });
  inputs_.check_stages("reduced simulation: ", steps_, time_, [this, m](mpm::Stage stage, std::int64_t slot) {
    // G2P runs over the samples and P2G over the quadrature points, reported as their material points;
    // an Eulerian quadrature point is none (index -1), so it is named by where it is.
    if (stage == mpm::Stage::G2P) {
      const std::int64_t point = download(exec_.backend, sample_index_.prefix(m).subspan(slot, 1), exec_.stream)[0];
      return std::pair<std::int64_t, std::string>(point, fmt::format("sample material point {}", point));
    }
    if (options_.quadrature == RomQuadrature::Eulerian) {
      const Vec3<float> x = planes_at(used_quadrature_.x.to_host(exec_.stream), used_quadrature_.count, slot),
                        X = planes_at(used_quadrature_.X.to_host(exec_.stream), used_quadrature_.count, slot);
      return std::pair<std::int64_t, std::string>(
          -1, fmt::format("the Eulerian quadrature point at x = ({:.4g}, {:.4g}, {:.4g}) m, reference X = ({:.4g}, "
                          "{:.4g}, {:.4g}) m",
                          x[0], x[1], x[2], X[0], X[1], X[2]));
    }
    const std::int64_t point =
        search_neighbours_
            ? download(exec_.backend, quadrature_index_.prefix(quadrature_.count).subspan(slot, 1), exec_.stream)[0]
            : slot;
    return std::pair<std::int64_t, std::string>(point, fmt::format("material point {} (a quadrature point)", point));
  });

  // Alg. 6 / 7: v̂_{n+1} from the trial velocities on the tangent space at x̂_n; then x̂_{n+1}, solved
  // where the system is (Gauss–Newton too), so that only the new state comes back: one round trip.
  timed([&] {
    rom::normal_equations(exec_, r, sample_dg_dxhat_.span(), Vec3Planes<const float>(samples_.v.data(), m), {},
                          system_.span());
    rom::advance_latent(exec_, r, system_.span(), dt, latent_device_.span());
    if (options_.projection == RomProjection::PositionVelocity) {
      // From 2 x̂_n − x̂_{n−1}; the first step has no x̂_{n−1}: from x̂_n + Δt v̂_{n+1}.
      const rom::PositionProjection projection{Vec3Planes<const float>(samples_.X.data(), m),
                                               Vec3Planes<const float>(samples_.x.data(), m),
                                               Vec3Planes<float>(model_x_.data(), m),
                                               sample_dg_dxhat_.span(),
                                               system_.span(),
                                               xhat_history_.span(),
                                               latent_device_.span(),
                                               projection_state_.span()};
      rom::project_positions(exec_, map_view(), {options_.gauss_newton_iterations, options_.gauss_newton_tolerance},
                             has_previous_, projection);
    }
    const std::vector<float> latent = latent_device_.to_host(exec_.stream);
    if (latent[2 * r] != rom::kLatentSolved) throw singular_projection();
    xhat_.assign(latent.begin(), latent.begin() + r);
    vhat_.assign(latent.begin() + r, latent.begin() + 2 * r);
    has_previous_ = true;
  });
  check_latent("the projection");
  max_sample_speed_ = mpm::max_particle_speed(exec_, samples, speed_slot_.span());
  time_ += dt;
  ++steps_;
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

void ReducedSim::check_inside_domain(const DeviceBuffer<float>& x, Index count, Span<const std::int32_t> index) {
  // The band the full-order step keeps particles in (mpm::kept_inside_domain).
  const mpm::Domain domain = config_.domain();
  Vec3<float> low, high;
  for (int a = 0; a < 3; ++a) {
    low[a] = domain.low_bound(config_.dx);
    high[a] = domain.high_bound(a, config_.dx);
  }
  fill(exec_, first_outside_.span(), rom::kNoPointOutside);
  rom::find_point_outside(exec_, Vec3Planes<const float>(x.data(), count), low, high, first_outside_.span());
  const std::int64_t slot = first_outside_.to_host(exec_.stream)[0];
  if (slot == rom::kNoPointOutside) return;
  const std::int64_t point = index.empty() ? slot : download(exec_.backend, index.subspan(slot, 1), exec_.stream)[0];
  const std::vector<float> positions = x.to_host(exec_.stream);
  throw NonFiniteError(
      fmt::format(
          "reduced simulation: material point {} decodes to ({:.4g}, {:.4g}, {:.4g}) m at step {} (t = {:.6g} "
          "s), outside the domain's interior [{:.4g}, {:.4g}] x [{:.4g}, {:.4g}] x [{:.4g}, {:.4g}] m: x̂ = [{}] "
          "has left the states the map describes (the reduced dynamics diverged)",
          point, positions[slot], positions[count + slot], positions[2 * count + slot], steps_, time_, low[0], high[0],
          low[1], high[1], low[2], high[2], fmt::join(xhat_, ", ")),
      steps_, mpm::Stage::P2G, point);
}

std::vector<std::pair<std::string, double>> ReducedSim::stage_seconds() const {
  return stage_table(stages_, stage_timeline_);
}

rom::GaussNewtonState ReducedSim::gauss_newton_state() const {
  return projection_state_.empty() ? rom::GaussNewtonState{} : projection_state_.to_host(exec_.stream)[0];
}

std::int64_t ReducedSim::unconverged_projections() const { return gauss_newton_state().unconverged_total; }

std::int64_t ReducedSim::gauss_newton_linearisations() const { return gauss_newton_state().linearisations_total; }

rom::QuadratureTally ReducedSim::quadrature_tally() const {
  return tally_.empty() ? rom::QuadratureTally{} : tally_.to_host(exec_.stream)[0];
}

bool ReducedSim::advance_to(double t, const std::function<bool()>& stop) {
  return advance_clock(
      time_, t, [this] { return double(stable_dt()); }, [this](float dt) { substep(dt); }, stop);
}

ReducedSim::DecodedState ReducedSim::decode(const std::vector<float>& X_host) {
  ROMP_CHECK(X_host.size() % 3 == 0, "reference points come as 3 planes");
  const Index n = Index(X_host.size() / 3);
  if (n == 0) return {};
  const Backend backend = exec_.backend;
  const DeviceBuffer<float> X = DeviceBuffer<float>::from_host(backend, X_host, exec_.stream);
  DeviceBuffer<float> x(backend, 3 * n), F(backend, 9 * n), v(backend, 3 * n), dg(backend, 3 * Index(latent_) * n);
  evaluate_map(Vec3Planes<const float>(X.data(), n),
               {Vec3Planes<float>(x.data(), n), Mat3Planes<float>(F.data(), n), dg.span()});
  rom::latent_to_point_velocity(exec_, latent_, dg.span(), vhat_device(), Vec3Planes<float>(v.data(), n));
  return {x.to_host(exec_.stream), F.to_host(exec_.stream), v.to_host(exec_.stream)};
}

std::vector<float> ReducedSim::decode_positions() {
  DeviceBuffer<float> x(exec_.backend, 3 * points_);
  evaluate_map(Vec3Planes<const float>(X_.data(), points_), {Vec3Planes<float>(x.data(), points_), {}, {}});
  return x.to_host(exec_.stream);
}

}  // namespace romp::engine
