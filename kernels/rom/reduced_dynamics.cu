// Latent-to-point velocities and the projection's normal equations (see reduced_dynamics.h).
#include "kernels/rom/reduced_dynamics.h"

#include <string>

#include "kernels/core/atomic.h"
#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/math/cholesky_solve.h"
#include "kernels/rom/normal_equation_entry.h"

namespace romp::rom {
namespace {

struct LatentToPointVelocity {
  int latent;
  Span<const float> dg_dxhat;
  Span<const float> vhat;
  Vec3Planes<float> v;
  ROMP_HD void operator()(Index p) const {
    const Index n = v.count();
    Vec3<float> velocity = Vec3<float>::zero();
    for (int o = 0; o < 3; ++o)
      for (int j = 0; j < latent; ++j) velocity[o] += dg_dxhat[(o * latent + j) * n + p] * vhat[j];
    v.store(p, velocity);
  }
};

struct AdvanceLatent {
  int r;
  Span<double> system;
  float dt;
  Span<float> latent;
  ROMP_HD void operator()(Index) const {
    double* c = system.data() + r * r;
    if (!cholesky_solve(r, system.data(), c)) {
      latent[2 * r] = kLatentSingular;
      return;
    }
    for (int j = 0; j < r; ++j) {
      const float vhat = float(c[j]);
      latent[r + j] = vhat;
      latent[j] = latent[j] + dt * vhat;
    }
    latent[2 * r] = kLatentSolved;
  }
};

struct KeepPointInside {
  Vec3Planes<float> x;
  mpm::Domain domain;
  float dx;
  Span<std::int64_t> first;
  ROMP_HD void operator()(Index p) const {
    const Vec3<float> position = x.load(p);
    const Vec3<float> kept = mpm::kept_inside_domain(domain, position, dx);
    bool inside = true;
    // Written so that NaN (kept at the low bound) compares as moved.
    for (int a = 0; a < 3; ++a) inside = inside && kept[a] == position[a];
    if (inside) return;
    atomic_min(&first[0], std::int64_t(p));
    x.store(p, kept);
  }
};

}  // namespace

void keep_points_inside(const Exec& exec, Vec3Planes<float> x, const mpm::Domain& domain, float dx,
                        Span<std::int64_t> first, Span<const std::int64_t> live) {
  ROMP_CHECK(first.size() >= 1, "keep_points_inside needs one slot");
  for_each_bounded(exec, x.count(), live, KeepPointInside{x, domain, dx, first});
}

void latent_to_point_velocity(const Exec& exec, int latent, Span<const float> dg_dxhat, Span<const float> vhat,
                              Vec3Planes<float> v, Span<const std::int64_t> live) {
  ROMP_CHECK(latent >= 1 && vhat.size() == latent, "v̂ must hold r = " + std::to_string(latent) + " values");
  ROMP_CHECK(dg_dxhat.size() == 3 * latent * v.count(), "dg_dxhat must hold 3 r planes of the point count");
  for_each_bounded(exec, v.count(), live, LatentToPointVelocity{latent, dg_dxhat, vhat, v});
}

void normal_equations(const Exec& exec, int latent, Span<const float> dg_dxhat, Vec3Planes<const float> target,
                      Vec3Planes<const float> reference, Span<double> system) {
  const Index m = target.count();
  ROMP_CHECK(latent >= 1, "the latent size r must be >= 1");
  ROMP_CHECK(dg_dxhat.size() == 3 * latent * m, "dg_dxhat must hold 3 r planes of the point count");
  ROMP_CHECK(!reference.data() || reference.count() == m, "reference must hold one vector per point");
  const Index entries = Index(latent) * latent + latent + 1;
  ROMP_CHECK(system.size() == entries, "the system needs r² + r + 1 values");
  for_each(exec, entries, NormalEquationEntry{latent, dg_dxhat, target, reference, system});
}

void advance_latent(const Exec& exec, int latent_size, Span<double> system, float dt, Span<float> latent) {
  ROMP_CHECK(latent_size >= 1, "the latent size r must be >= 1");
  const Index r = latent_size;
  ROMP_CHECK(system.size() == r * r + r + 1, "the system needs r² + r + 1 values");
  ROMP_CHECK(latent.size() == 2 * r + 1, "the latent state needs x̂, v̂ and a status: 2 r + 1 values");
  for_each(exec, 1, AdvanceLatent{latent_size, system, dt, latent});
}

}  // namespace romp::rom
