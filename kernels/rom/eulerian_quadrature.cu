// Eulerian quadrature points: damped Newton inversion of g per point, then its kinematics (see
// eulerian_quadrature.h).
#include "kernels/rom/eulerian_quadrature.h"

#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/rom/deformation_map_point.h"

namespace romp::rom {
namespace {

// How often the Newton step is halved before the point counts as unconverged.
constexpr int kHalvings = 6;

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
  EulerianPointsOut out;

  // F⁻¹ r by Cramer's rule: the columns of det(F) F⁻¹ are the cross products of F's rows.
  ROMP_HD static bool solve(const Mat3<float>& F, const Vec3<float>& r, Vec3<float>& delta) {
    const Vec3<float> r0 = F.row(0), r1 = F.row(1), r2 = F.row(2);
    const float det = dot(r0, cross(r1, r2));
    if (!(det > 0.0f)) return false;  // an inverted or degenerate map has no usable inverse here
    delta = (r[0] * cross(r1, r2) + r[1] * cross(r2, r0) + r[2] * cross(r0, r1)) * (1.0f / det);
    return true;
  }

  ROMP_HD bool invert(const Vec3<float>& target, Vec3<float>& X, int& steps) const {
    Vec3<float> g;
    Mat3<float> F;
    evaluate_map_point(map, xhat, X, g, &F, static_cast<float*>(nullptr), 0);
    float residual = norm(g - target);
    for (int iteration = 0; iteration < options.iterations; ++iteration, ++steps) {
      if (residual <= options.tolerance) return true;
      Vec3<float> delta;
      if (!solve(F, g - target, delta)) return false;
      float alpha = 1.0f;
      bool descended = false;
      for (int halving = 0; halving <= kHalvings && !descended; ++halving, alpha *= 0.5f) {
        const Vec3<float> X_try = X - alpha * delta;
        Vec3<float> g_try;
        Mat3<float> F_try;
        evaluate_map_point(map, xhat, X_try, g_try, &F_try, static_cast<float*>(nullptr), 0);
        const float residual_try = norm(g_try - target);
        if (residual_try < residual) {
          X = X_try;
          g = g_try;
          F = F_try;
          residual = residual_try;
          descended = true;
        }
      }
      if (!descended) return residual <= options.tolerance;
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
    } else if (invert(target, X, steps)) {
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
                         Vec3Planes<const float> X_guess, const EulerianPointsOut& out) {
  const Index n = x.count();
  ROMP_CHECK(map.latent >= 1 && map.latent <= kMaxMapLatent && xhat.size() == map.latent &&
                 vhat.size() == map.latent,
             "x̂ and v̂ must hold the map's r values, r in [1, " + std::to_string(kMaxMapLatent) + "]");
  ROMP_CHECK(map.parameters.size() == deformation_map_parameter_count(map.latent, map.hidden_layers, map.width),
             "the map's parameter buffer does not match its sizes");
  ROMP_CHECK(X_guess.count() == n && out.X.count() == n && out.v.count() == n && out.F.count() == n &&
                 out.mass.size() == n && out.volume0.size() == n && out.material.size() == n &&
                 out.status.size() == n && out.iterations.size() == n,
             "every quadrature array must hold one entry per point");
  ROMP_CHECK(volume > 0.0f && options.iterations >= 1 && options.tolerance > 0.0f,
             "the quadrature volume, iteration count and tolerance must be > 0");
  if (n == 0) return;
  for_each(exec, n,
           EulerianPoint{map, xhat.data(), vhat.data(), occupancy, density, volume, options, x, X_guess, out});
}

}  // namespace romp::rom
