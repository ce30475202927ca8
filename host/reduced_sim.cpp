// ReducedSim: samples, quadrature kinematics from g, the MPM update at the samples, and the projections.
#include "host/reduced_sim.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>

#include "host/full_order_sim.h"
#include "kernels/core/device_timer.h"
#include "kernels/core/for_each.h"
#include "kernels/core/gather_planes.h"
#include "kernels/math/cholesky_solve.h"
#include "kernels/mpm/step.h"
#include "kernels/rom/reduced_dynamics.h"

namespace romp {
namespace {

// k distinct members of `pool`, drawn uniformly (Floyd's algorithm: k draws, no pass over the pool).
std::vector<std::int32_t> draw_distinct(const std::vector<std::int32_t>& pool, std::size_t k, geometry::Random& random) {
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
            const DeviceBuffer<std::int32_t>& index, DeviceBuffer<T>& destination) {
  for_each(exec, index.size(),
           GatherPlanes<T>{source.span(), source_count, destination.span(), index.span(), components});
}

double norm(const std::vector<float>& v) {
  double sum = 0.0;
  for (const float value : v) sum += double(value) * double(value);
  return std::sqrt(sum);
}

}  // namespace

ReducedSim::ReducedSim(const Exec& exec, FullOrderConfig config, const mpm::ParticleInit& reference,
                       DeformationMapWeights map, std::vector<float> xhat, ReducedOptions options)
    : exec_(exec),
      config_(std::move(config)),
      inputs_(exec, config_),
      grid_(exec.backend, config_.dx, config_.transfer == mpm::Transfer::PicFlip),
      options_(options),
      map_(std::move(map)),
      latent_(map_.latent),
      points_(reference.count()),
      random_(options.seed) {
  const Backend backend = exec.backend;
  const Index n = points_;
  ROMP_CHECK(n > 0, "a reduced simulation needs at least one material point");
  check_particle_tables(config_, reference.material, reference.dirichlet_group);
  ROMP_CHECK(!inputs_.plastic(), "the reduced-order model covers elastic materials (ROM paper, Sec. 3.2.2)");
  ROMP_CHECK(config_.transfer == mpm::Transfer::Apic,
             "the reduced-order step transfers with MLS-MPM (quadrature points carry no affine velocity)");
  ROMP_CHECK(Index(xhat.size()) == latent_,
             fmt::format("x̂ holds {} values, the map's latent size is {}", xhat.size(), latent_));
  ROMP_CHECK(options_.samples >= 0 && options_.boundary_samples >= 0, "sample counts must be >= 0");
  ROMP_CHECK(options_.gauss_newton_iterations >= 1 && options_.gauss_newton_tolerance > 0.0,
             "Gauss–Newton needs at least one iteration and a tolerance > 0");

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

  x_ = DeviceBuffer<float>(backend, 3 * n);
  v_ = DeviceBuffer<float>(backend, 3 * n);
  F_ = DeviceBuffer<float>(backend, 9 * n);
  C_ = DeviceBuffer<float>(backend, 9 * n);
  C_.fill_zero();
  dg_dxhat_ = DeviceBuffer<float>(backend, 3 * Index(latent_) * n);
  system_ = DeviceBuffer<double>(backend, Index(latent_) * latent_ + latent_ + 1);
  xhat_ = std::move(xhat);
  xhat_device_ = DeviceBuffer<float>::from_host(backend, xhat_);

  // v̂ at t = 0: the least-squares fit of the initial velocities over every material point (Eq. 28).
  evaluate_map(Vec3Planes<const float>(X_.data(), n), {{}, {}, dg_dxhat_.span()});
  const DeviceBuffer<float> v0 = DeviceBuffer<float>::from_host(backend, reference.v);
  const std::vector<double> fit =
      solve_projection(dg_dxhat_.span(), Vec3Planes<const float>(v0.data(), n), {}).first;
  vhat_.assign(fit.begin(), fit.end());
  for (Index i = 0; i < 3 * n; ++i) max_sample_speed_ = std::max(max_sample_speed_, std::fabs(reference.v[i]));
  max_sample_speed_ *= std::sqrt(3.0f);  // a bound on |v| from its largest component
  check_latent("the initial projection");

  stage_seconds_ = {{"samples", 0.0},     {"kinematics", 0.0}, {"grid_build", 0.0}, {"p2g", 0.0},
                    {"grid_update", 0.0}, {"g2p", 0.0},        {"projection", 0.0}};
}

rom::DeformationMapView<float> ReducedSim::map_view() const {
  rom::DeformationMapView<float> view;
  view.latent = map_.latent;
  view.hidden_layers = map_.hidden_layers;
  view.width = map_.width;
  view.parameters = Span<const float>(map_parameters_.data(), map_parameters_.size());
  view.X_min = map_.X_min;
  view.X_scale = map_.X_scale;
  view.u_mean = map_.u_mean;
  view.u_std = map_.u_std;
  return view;
}

void ReducedSim::evaluate_map(Vec3Planes<const float> X, const rom::DeformationMapOutputs<float>& out) {
  rom::evaluate_deformation_map<float>(exec_, map_view(), Span<const float>(xhat_device_.data(), latent_), X, out);
}

std::pair<std::vector<double>, double> ReducedSim::solve_projection(Span<const float> dg_dxhat,
                                                                    Vec3Planes<const float> target,
                                                                    Vec3Planes<const float> reference) {
  const int r = latent_;
  rom::normal_equations(exec_, r, dg_dxhat, target, reference, system_.span());
  std::vector<double> system = system_.to_host(exec_.stream);
  std::vector<double> y(system.begin() + r * r, system.begin() + r * r + r);
  const double squared_residual = system.back();
  if (!cholesky_solve(r, system.data(), y.data()))
    throw Error(fmt::format("step {} (t = {:.6g} s): the projection's normal equations are singular (do the "
                            "samples move with the map at all?)",
                            steps_, time_));
  return {y, squared_residual};
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

float ReducedSim::stable_dt() const {
  if (config_.fixed_dt > 0.0f) return config_.fixed_dt;
  return std::min(config_.max_dt, config_.cfl * config_.dx / (inputs_.max_wave_speed() + max_sample_speed_));
}

void ReducedSim::substep(float dt) {
  ROMP_CHECK(dt > 0.0f && std::isfinite(dt), fmt::format("substep dt must be finite and > 0, got {}", dt));
  const Backend backend = exec_.backend;
  const Index n = points_;
  const int r = latent_;
  const mpm::StepParams step = inputs_.at(time_, dt);
  DeviceTimer timer(exec_);
  std::size_t stage = 0;
  auto timed = [&](auto&& run) {
    timer.start();
    run();
    stage_seconds_[stage++].second += timer.stop();
  };

  Index m = 0;
  timed([&] {
    const std::vector<std::int32_t> samples = choose_samples();
    m = Index(samples.size());
    if (sample_index_.size() != m) {
      for (DeviceBuffer<float>* planes : {&sample_X_, &sample_x_, &sample_v_})
        *planes = DeviceBuffer<float>(backend, 3 * m);
      sample_F_ = DeviceBuffer<float>(backend, 9 * m);
      sample_C_ = DeviceBuffer<float>(backend, 9 * m);
      sample_C_.fill_zero();
      sample_mass_ = DeviceBuffer<float>(backend, m);
      sample_volume0_ = DeviceBuffer<float>(backend, m);
      sample_dg_dxhat_ = DeviceBuffer<float>(backend, 3 * r * m);
      model_x_ = DeviceBuffer<float>(backend, 3 * m);
      sample_material_ = DeviceBuffer<std::int32_t>(backend, m);
      sample_group_ = DeviceBuffer<std::int32_t>(backend, m);
      sample_id_ = DeviceBuffer<std::int32_t>(backend, m);
    }
    sample_index_ = DeviceBuffer<std::int32_t>::from_host(backend, samples, exec_.stream);
  });

  // Alg. 3: the kinematics of the quadrature points (every material point) at x̂_n, v̂_n.
  timed([&] {
    xhat_device_.copy_from_host(Span<const float>(xhat_.data(), r), exec_.stream);
    vhat_device_ = DeviceBuffer<float>::from_host(backend, vhat_, exec_.stream);
    evaluate_map(Vec3Planes<const float>(X_.data(), n),
                 {Vec3Planes<float>(x_.data(), n), Mat3Planes<float>(F_.data(), n), dg_dxhat_.span()});
    rom::latent_to_point_velocity(exec_, r, dg_dxhat_.span(), vhat_device_.span(), Vec3Planes<float>(v_.data(), n));
  });
  const mpm::ParticleView quadrature{n,
                                     Vec3Planes<float>(x_.data(), n),
                                     Vec3Planes<float>(v_.data(), n),
                                     Mat3Planes<float>(C_.data(), n),
                                     Mat3Planes<float>(F_.data(), n),
                                     mass_.span(),
                                     volume0_.span(),
                                     material_.span(),
                                     dirichlet_group_.span(),
                                     id_.span()};
  // Alg. 5: P2G from the quadrature points, the grid update, G2P at the samples.
  timed([&] { grid_.rebuild(exec_, Vec3Planes<const float>(quadrature.x)); });
  const mpm::GridView grid = grid_.view();
  timed([&] { mpm::particle_to_grid(exec_, quadrature, grid, step); });
  timed([&] { mpm::update_grid(exec_, grid, step); });
  const mpm::ParticleView samples{m,
                                  Vec3Planes<float>(sample_x_.data(), m),
                                  Vec3Planes<float>(sample_v_.data(), m),
                                  Mat3Planes<float>(sample_C_.data(), m),
                                  Mat3Planes<float>(sample_F_.data(), m),
                                  sample_mass_.span(),
                                  sample_volume0_.span(),
                                  sample_material_.span(),
                                  sample_group_.span(),
                                  sample_id_.span()};
  timed([&] {
    gather(exec_, X_, n, 3, sample_index_, sample_X_);
    gather(exec_, x_, n, 3, sample_index_, sample_x_);
    gather(exec_, v_, n, 3, sample_index_, sample_v_);
    gather(exec_, F_, n, 9, sample_index_, sample_F_);
    gather(exec_, mass_, n, 1, sample_index_, sample_mass_);
    gather(exec_, volume0_, n, 1, sample_index_, sample_volume0_);
    gather(exec_, material_, n, 1, sample_index_, sample_material_);
    gather(exec_, dirichlet_group_, n, 1, sample_index_, sample_group_);
    gather(exec_, id_, n, 1, sample_index_, sample_id_);
    gather(exec_, dg_dxhat_, n, 3 * r, sample_index_, sample_dg_dxhat_);
    mpm::grid_to_particle(exec_, samples, grid, step);
  });
  check_stages();

  // Alg. 6 / 7: v̂_{n+1} from the trial velocities on the tangent space at x̂_n; then x̂_{n+1}.
  timed([&] {
    const std::vector<double> v_fit =
        solve_projection(sample_dg_dxhat_.span(), Vec3Planes<const float>(sample_v_.data(), m), {}).first;
    std::vector<float> vhat(v_fit.begin(), v_fit.end());
    std::vector<float> xhat(static_cast<std::size_t>(r));
    for (int j = 0; j < r; ++j) xhat[j] = xhat_[j] + dt * vhat[j];
    if (options_.projection == RomProjection::PositionVelocity) {
      std::vector<float> guess = xhat;  // the first step has no x̂_{n−1}: x̂_n + Δt v̂_{n+1}
      if (has_previous_)
        for (int j = 0; j < r; ++j) guess[j] = 2.0f * xhat_[j] - xhat_previous_[j];
      xhat = project_positions(guess, m);
    }
    xhat_previous_ = xhat_;
    has_previous_ = true;
    xhat_ = std::move(xhat);
    vhat_ = std::move(vhat);
  });
  check_latent("the projection");
  max_sample_speed_ = mpm::max_particle_speed(exec_, samples);
  time_ += dt;
  ++steps_;
}

std::vector<float> ReducedSim::project_positions(const std::vector<float>& guess, Index m) {
  const int r = latent_;
  const Vec3Planes<const float> X(sample_X_.data(), m), trial(sample_x_.data(), m), model(model_x_.data(), m);
  // Σ ‖x_trial − g(X; y)‖² and its Gauss–Newton system at y.
  auto linearise = [&](const std::vector<float>& y) {
    xhat_device_.copy_from_host(Span<const float>(y.data(), r), exec_.stream);
    evaluate_map(X, {Vec3Planes<float>(model_x_.data(), m), {}, sample_dg_dxhat_.span()});
    return solve_projection(sample_dg_dxhat_.span(), trial, model);
  };
  // The line search halves the step at most this often before deciding no descent is left.
  constexpr int kHalvings = 10;
  std::vector<float> y = guess;
  auto [delta, cost] = linearise(y);
  for (int iteration = 0; iteration < options_.gauss_newton_iterations; ++iteration) {
    double alpha = 1.0;
    bool descended = false;
    std::vector<float> trial_y(static_cast<std::size_t>(r));
    std::pair<std::vector<double>, double> next;
    for (int halving = 0; halving <= kHalvings && !descended; ++halving, alpha *= 0.5) {
      for (int j = 0; j < r; ++j) trial_y[j] = float(double(y[j]) + alpha * delta[j]);
      next = linearise(trial_y);
      descended = next.second <= cost;
    }
    // No descent along the Gauss–Newton direction: y is a minimum to float precision.
    if (!descended) return y;
    double step = 0.0;
    for (int j = 0; j < r; ++j) step += (double(trial_y[j]) - y[j]) * (double(trial_y[j]) - y[j]);
    y = trial_y;
    delta = std::move(next.first);
    cost = next.second;
    if (std::sqrt(step) <= options_.gauss_newton_tolerance * (1.0 + norm(y))) return y;
  }
  ++unconverged_projections_;
  return y;
}

void ReducedSim::check_stages() const {
  const std::vector<std::int64_t> failures = inputs_.failures();
  for (int s = 0; s < mpm::kStageCount; ++s) {
    if (failures[s] == mpm::kNoFailure) continue;
    const auto failed = mpm::Stage(s);
    std::int64_t index = failures[s];
    std::string what = fmt::format("material point {}", index);  // P2G runs over every material point
    if (failed == mpm::Stage::GridUpdate) {
      what = fmt::format("grid node {}", index);
    } else if (failed == mpm::Stage::G2P) {  // G2P runs over the samples: report the material point
      index = sample_index_.to_host(exec_.stream)[std::size_t(index)];
      what = fmt::format("sample material point {}", index);
    }
    throw NonFiniteError(fmt::format("reduced simulation: non-finite value at step {} (t = {:.6g} s), stage {}: {}",
                                     steps_, time_, stage_name(failed), what),
                         steps_, failed, index);
  }
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

void ReducedSim::advance_to(double t) {
  advance_clock(time_, t, [this] { return double(stable_dt()); }, [this](float dt) { substep(dt); });
}

std::vector<float> ReducedSim::decode_positions() {
  xhat_device_.copy_from_host(Span<const float>(xhat_.data(), latent_), exec_.stream);
  evaluate_map(Vec3Planes<const float>(X_.data(), points_), {Vec3Planes<float>(x_.data(), points_), {}, {}});
  return x_.to_host(exec_.stream);
}

}  // namespace romp
