// Eulerian quadrature points: damped Newton inversion of g per point, then its kinematics (see
// eulerian_quadrature.h).
#include "kernels/rom/eulerian_quadrature.h"

#include <string>

#include "kernels/core/atomic.h"
#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/rom/deformation_map_point.h"

namespace romp::rom {
namespace {

// How often a step is halved before the point counts as unconverged (with the true Jacobian) or before
// Broyden's estimate is replaced by the true Jacobian.
constexpr int kHalvings = 6;
constexpr int kBroydenHalvings = 2;

struct EulerianPoint {
  DeformationMapView<float> map;
  const float* xhat;
  const float* vhat;
  ReferenceOccupancy occupancy;
  Span<const float> density;
  float volume;
  InversionOptions options;
  Vec3Planes<const float> x;
  Vec3Planes<const float> X_guess;
  Mat3Planes<const float> F_guess;
  EulerianPointsOut out;

  ROMP_HD Vec3<float> g_at(const Vec3<float>& X) const {
    Vec3<float> g;
    evaluate_map_point(map, xhat, X, g, static_cast<Mat3<float>*>(nullptr), static_cast<float*>(nullptr), 0);
    return g;
  }

  // Solves g(X) = target from X by Broyden's method with a backtracking line search, starting from the
  // Jacobian estimate B (g linearised at the cell's sample). A step then costs one evaluation of g, where
  // a Newton step's ∇_X g costs three reverse sweeps more. Where B gives no descent it is replaced by the
  // true ∇_X g at X, so the iteration is Newton's there and converges wherever Newton's does.
  ROMP_HD bool invert(const Vec3<float>& target, Mat3<float> B, Vec3<float>& X, int& steps) const {
    Vec3<float> g = g_at(X);
    float residual = norm(g - target);
    bool exact = false;  // whether B is ∇_X g at X
    for (int iteration = 0; iteration < options.iterations; ++iteration, ++steps) {
      if (residual <= options.tolerance) return true;
      Vec3<float> delta;
      bool descended = false;
      if (solve_where_positive(B, g - target, delta)) {
        float alpha = 1.0f;
        for (int halving = 0; halving <= (exact ? kHalvings : kBroydenHalvings) && !descended;
             ++halving, alpha *= 0.5f) {
          const Vec3<float> step = -alpha * delta;
          const Vec3<float> g_try = g_at(X + step);
          const float residual_try = norm(g_try - target);
          if (residual_try < residual) {
            // Broyden's update B += (y − B s) sᵀ / sᵀs, the least change to B that maps the step s to the
            // change y of g; skipped for steps at the tolerance's scale, where y is mostly float rounding.
            const float length = norm(step);
            if (length > options.tolerance)
              B += Mat3<float>::outer((g_try - g) - B * step, step) * (1.0f / (length * length));
            X = X + step;
            g = g_try;
            residual = residual_try;
            descended = true;
          }
        }
      }
      if (descended) {
        exact = false;
      } else if (exact) {
        return false;
      } else {
        Mat3<float> F;
        evaluate_map_point(map, xhat, X, g, &F, static_cast<float*>(nullptr), 0);
        B = F;
        exact = true;
      }
    }
    return residual <= options.tolerance;
  }

  ROMP_HD void operator()(Index i) const {
    const Vec3<float> target = x.load(i);
    Vec3<float> X = X_guess.load(i);
    std::int32_t status = kQuadratureUnconverged;
    int material = -1, steps = 0;
    if (!occupancy.near(X, options.outside_margin)) {
      status = kQuadratureOutside;
    } else if (invert(target, F_guess.load(i), X, steps)) {
      material = occupancy.material_at(X);
      status = material >= 0 ? kQuadratureUsed : kQuadratureOutside;
    }
    Vec3<float> g, v = Vec3<float>::zero();
    Mat3<float> F = Mat3<float>::identity();
    float mass = 0.0f, volume0 = 0.0f;
    if (status == kQuadratureUsed) {
      float dg[3 * kMaxMapLatent];
      evaluate_map_point(map, xhat, X, g, &F, dg, 1);
      const float J = determinant(F);
      if (J > 0.0f) {
        for (int o = 0; o < 3; ++o)
          for (int j = 0; j < map.latent; ++j) v[o] += dg[o * map.latent + j] * vhat[j];
        volume0 = volume / J;
        mass = density[material] * volume0;
      } else {
        status = kQuadratureUnconverged;
        F = Mat3<float>::identity();
      }
    }
    out.X.store(i, X);
    out.v.store(i, v);
    out.F.store(i, F);
    out.mass[i] = mass;
    out.volume0[i] = volume0;
    out.material[i] = status == kQuadratureUsed ? material : 0;
    out.status[i] = status;
    out.iterations[i] = steps;
  }
};

}  // namespace

void eulerian_quadrature(const Exec& exec, const DeformationMapView<float>& map, Span<const float> xhat,
                         Span<const float> vhat, const ReferenceOccupancy& occupancy, Span<const float> density,
                         float volume, const InversionOptions& options, Vec3Planes<const float> x,
                         Vec3Planes<const float> X_guess, Mat3Planes<const float> F_guess,
                         const EulerianPointsOut& out) {
  const Index n = x.count();
  ROMP_CHECK(map.latent >= 1 && map.latent <= kMaxMapLatent && xhat.size() == map.latent &&
                 vhat.size() == map.latent,
             "x̂ and v̂ must hold the map's r values, r in [1, " + std::to_string(kMaxMapLatent) + "]");
  ROMP_CHECK(map.parameters.size() == deformation_map_parameter_count(map.latent, map.hidden_layers, map.width),
             "the map's parameter buffer does not match its sizes");
  ROMP_CHECK(X_guess.count() == n && F_guess.count() == n && out.X.count() == n && out.v.count() == n && out.F.count() == n &&
                 out.mass.size() == n && out.volume0.size() == n && out.material.size() == n &&
                 out.status.size() == n && out.iterations.size() == n,
             "every quadrature array must hold one entry per point");
  ROMP_CHECK(volume > 0.0f && options.iterations >= 1 && options.tolerance > 0.0f,
             "the quadrature volume, iteration count and tolerance must be > 0");
  if (n == 0) return;
  for_each(exec, n,
           EulerianPoint{map, xhat.data(), vhat.data(), occupancy, density, volume, options, x, X_guess, F_guess,
                         out});
}

namespace {

struct ClearLastMass {
  Span<QuadratureTally> tally;
  ROMP_HD void operator()(Index) const { tally[0].last_mass = 0.0; }
};

struct TallyPoint {
  Span<const std::int32_t> status, iterations;
  Span<const float> mass;
  Span<QuadratureTally> tally;
  ROMP_HD void operator()(Index i) const {
    QuadratureTally& total = tally[0];
    atomic_add(&total.points[status[i]], std::int64_t(1));
    atomic_add(&total.iterations, std::int64_t(iterations[i]));
    atomic_add(&total.last_mass, double(mass[i]));
  }
};

}  // namespace

void tally_quadrature(const Exec& exec, Span<const std::int32_t> status, Span<const std::int32_t> iterations,
                      Span<const float> mass, Span<QuadratureTally> tally) {
  const Index n = status.size();
  ROMP_CHECK(iterations.size() == n && mass.size() == n && tally.size() == 1,
             "tally_quadrature: one status, iteration count and mass per point, one tally");
  for_each(exec, 1, ClearLastMass{tally});
  for_each(exec, n, TallyPoint{status, iterations, mass, tally});
}

}  // namespace romp::rom
