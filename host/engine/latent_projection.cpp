// The projections of the reduced step.
#include "host/engine/latent_projection.h"

#include "kernels/core/error.h"
#include "kernels/core/memory.h"
#include "kernels/math/cholesky_solve.h"
#include "kernels/rom/reduced_dynamics.h"

namespace romp::engine {

LatentProjection::LatentProjection(Backend backend, const std::vector<float>& initial_xhat, bool positions,
                                   rom::GaussNewtonOptions options)
    : latent_size_(int(initial_xhat.size())),
      positions_(positions),
      options_(options),
      latent_(backend, 2 * Index(latent_size_) + 1),
      system_(backend, Index(latent_size_) * latent_size_ + latent_size_ + 1) {
  // v̂ = 0 and the status "solved" until set.
  latent_.fill_zero();
  upload(backend, xhat(), Span<const float>(initial_xhat.data(), latent_size_));
  if (positions_) {
    std::vector<float> history(initial_xhat);
    history.insert(history.end(), initial_xhat.begin(), initial_xhat.end());
    history_ = DeviceBuffer<float>::from_host(backend, history);
    state_ = DeviceBuffer<rom::GaussNewtonState>(backend, 1);
    state_.fill_zero();
  }
}

std::vector<float> LatentProjection::fit_velocity(const Exec& exec, Span<const float> dg_dxhat,
                                                  Vec3Planes<const float> v) {
  const int r = latent_size_;
  rom::normal_equations(exec, r, dg_dxhat, v, {}, system_.span());
  std::vector<double> system = system_.to_host(exec.stream);
  std::vector<double> y(system.begin() + r * r, system.begin() + r * r + r);
  if (!cholesky_solve(r, system.data(), y.data())) return {};
  const std::vector<float> fit(y.begin(), y.end());
  upload(exec.backend, vhat(), Span<const float>(fit.data(), r), exec.stream);
  return fit;
}

void LatentProjection::project(const Exec& exec, const DeformationMap& map, SampleSet& samples, float dt) {
  const int r = latent_size_;
  const Index m = samples.count();
  rom::normal_equations(exec, r, samples.dg_dxhat(), Vec3Planes<const float>(samples.points().v.data(), m), {},
                        system_.span());
  rom::advance_latent(exec, r, system_.span(), dt, latent_.span());
  if (!positions_) return;
  const rom::PositionProjection projection{
      samples.X(),        samples.x(),    Vec3Planes<float>(samples.model_x().data(), m),
      samples.dg_dxhat(), system_.span(), history_.span(),
      latent_.span(),     state_.span()};
  rom::project_positions(exec, map.view(), options_, has_previous_, projection);
  has_previous_ = true;
}

rom::GaussNewtonState LatentProjection::gauss_newton_state(const Exec& exec) const {
  return state_.empty() ? rom::GaussNewtonState{} : state_.to_host(exec.stream)[0];
}

}  // namespace romp::engine
