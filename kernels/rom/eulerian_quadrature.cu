// Eulerian quadrature points: damped Newton inversion of g per point, then its kinematics (see
// eulerian_quadrature.h).
#include "kernels/rom/eulerian_quadrature.h"

#include <string>
#include <type_traits>

#include "kernels/core/atomic.h"
#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/rom/map_evaluators.h"

namespace romp::rom {
namespace {

// How often a step is halved before the point counts as unconverged (with the true Jacobian) or before
// Broyden's estimate is replaced by the true Jacobian.
constexpr int kHalvings = 6;
constexpr int kBroydenHalvings = 2;

template <class Map>
struct EulerianPoint {
  Map map;
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

  // What the next evaluation of the map is for.
  enum class Stage { Start, Trial, Exact, Kinematics, Done };

  // Solves g(X) = x_i by Broyden's method with a backtracking line search, starting from the Jacobian
  // estimate F_guess (g linearised at the cell's sample). A step then costs one evaluation of g, where a
  // Newton step's ∇_X g costs three reverse sweeps more. Where B gives no descent it is replaced by the
  // true ∇_X g at X, so the iteration is Newton's there and converges wherever Newton's does. Then the
  // kinematics at the solution: F, v = ∂g/∂x̂ v̂, the mass and volume.
  //
  // Written as stages around one call of the map (Start: g at the guess; Trial: g at a line-search
  // point; Exact: g and ∇_X g where Broyden's estimate failed; Kinematics: the Jacobians at the
  // solution), so the kernel holds one inlined copy of the evaluator, whose registers it can keep.
  ROMP_HD void operator()(Index i) const {
    Vec3<float> X = X_guess.load(i);
    Mat3<float> B = F_guess.load(i);
    std::int32_t status = kQuadratureUnconverged;
    int material = -1;

    Stage stage = Stage::Start;
    if (!occupancy.near(X, options.outside_margin)) {
      status = kQuadratureOutside;
      stage = Stage::Done;
    }
    // The loop keeps as little as it can across the map's evaluation, whose registers it shares: the
    // trial point is X + step, the target x_i is read again where it is needed, and the kinematics go
    // straight to `out`.
    Vec3<float> g = Vec3<float>::zero(), step = Vec3<float>::zero();
    float residual = 0.0f;
    bool exact = false;              // whether B is ∇_X g at X
    int iteration = 0, halving = 0;  // iterations taken; step halvings in this line search
    int evaluations = 0, jacobian_evaluations = 0;
    while (stage != Stage::Done) {
      Vec3<float> g_eval;
      // ∇_X g, where it is evaluated, replaces Broyden's estimate B (Exact) or is the kinematics' F. The
      // kinematics' v_o = Σ_j ∂g_o/∂x̂_j v̂_j goes to `out` as each row o is done (the sink gets the j of a
      // row in order), so nothing of it stays live across the evaluation. Captures what it needs, not
      // `this`: a pointer to the functor would copy it, weights and all, to local memory.
      float v_o = 0.0f;
      const bool kinematics = stage == Stage::Kinematics, jacobian = kinematics || stage == Stage::Exact;
      ++evaluations;
      jacobian_evaluations += jacobian ? 1 : 0;
      map(xhat, X + step, g_eval, B, jacobian,
          [&v_o, kinematics, vhat = vhat, v = out.v.data(), n = out.v.count(), last = map.latent() - 1, i](
              int o, int j, float dg_dxhat) {
        v_o = (j == 0 ? 0.0f : v_o) + dg_dxhat * vhat[j];
        if (kinematics && j == last) v[o * n + i] = v_o;
      });

      bool descended = false, line_search_failed = false;
      switch (stage) {
        case Stage::Start:
          g = g_eval;
          residual = norm(g - x.load(i));
          break;
        case Stage::Trial: {
          const float residual_try = norm(g_eval - x.load(i));
          if (residual_try < residual) {
            // Broyden's update B += (y − B s) sᵀ / sᵀs, the least change to B that maps the step s to the
            // change y of g; skipped for steps at the tolerance's scale, where y is mostly float rounding.
            const float length = norm(step);
            if (length > options.tolerance)
              B += Mat3<float>::outer((g_eval - g) - B * step, step) * (1.0f / (length * length));
            X = X + step;
            g = g_eval;
            residual = residual_try;
            descended = true;
          } else if (++halving <= (exact ? kHalvings : kBroydenHalvings)) {
            step = 0.5f * step;
            continue;
          } else {
            line_search_failed = true;
          }
          break;
        }
        case Stage::Exact:
          g = g_eval;
          exact = true;
          ++iteration;
          break;
        case Stage::Kinematics: {
          const float J = determinant(B);
          if (J > 0.0f) {
            out.F.store(i, B);
            out.volume0[i] = volume / J;
            out.mass[i] = density[material] * (volume / J);
          } else {
            status = kQuadratureUnconverged;
          }
          stage = Stage::Done;
          continue;
        }
        case Stage::Done: break;
      }
      if (descended) {
        exact = false;
        ++iteration;
      }

      // The next evaluation: a line-search point, the true Jacobian, or the kinematics at the solution.
      if (!line_search_failed) {
        if (iteration >= options.iterations || residual <= options.tolerance) {
          if (residual <= options.tolerance) {
            material = occupancy.material_at(X);
            status = material >= 0 ? kQuadratureUsed : kQuadratureOutside;
          }
          stage = status == kQuadratureUsed ? Stage::Kinematics : Stage::Done;
          step = Vec3<float>::zero();
          continue;
        }
        if (solve_where_positive(B, x.load(i) - g, step)) {
          // The step's end predicts the solution far better than the first guess did: where it lies more
          // than predicted_margin cells from any material the point lands outside the body, and is dropped
          // without the evaluations that would take it there.
          if (!occupancy.near(X + step, options.predicted_margin)) {
            status = kQuadratureOutside;
            stage = Stage::Done;
            continue;
          }
          halving = 0;
          stage = Stage::Trial;
          continue;
        }
      }
      // No descent along B's step: with the true Jacobian the point is unconverged, else take it.
      if (exact) {
        stage = Stage::Done;
      } else {
        step = Vec3<float>::zero();
        stage = Stage::Exact;
      }
    }

    out.X.store(i, X);
    if (status != kQuadratureUsed) {
      out.v.store(i, Vec3<float>::zero());
      out.F.store(i, Mat3<float>::identity());
      out.mass[i] = 0.0f;
      out.volume0[i] = 0.0f;
    }
    out.material[i] = status == kQuadratureUsed ? material : 0;
    out.status[i] = status;
    out.iterations[i] = iteration;
    out.evaluations[i] = evaluations;
    out.jacobian_evaluations[i] = jacobian_evaluations;
  }
};

}  // namespace

void eulerian_quadrature(const Exec& exec, const DeformationMapView<float>& map, Span<const float> xhat,
                         Span<const float> vhat, const ReferenceOccupancy& occupancy, Span<const float> density,
                         float volume, const InversionOptions& options, Vec3Planes<const float> x,
                         Vec3Planes<const float> X_guess, Mat3Planes<const float> F_guess, const EulerianPointsOut& out,
                         MapKernel kernel, Span<const std::int64_t> count) {
  const Index n = x.count();
  ROMP_CHECK(map.latent >= 1 && map.latent <= kMaxMapLatent && xhat.size() == map.latent && vhat.size() == map.latent,
             "x̂ and v̂ must hold the map's r values, r in [1, " + std::to_string(kMaxMapLatent) + "]");
  ROMP_CHECK(map.parameters.size() == deformation_map_parameter_count(map.latent, map.hidden_layers, map.width),
             "the map's parameter buffer does not match its sizes");
  ROMP_CHECK(X_guess.count() == n && F_guess.count() == n && out.X.count() == n && out.v.count() == n &&
                 out.F.count() == n && out.mass.size() == n && out.volume0.size() == n && out.material.size() == n &&
                 out.status.size() == n && out.iterations.size() == n && out.evaluations.size() == n &&
                 out.jacobian_evaluations.size() == n,
             "every quadrature array must hold one entry per point");
  ROMP_CHECK(volume > 0.0f && options.iterations >= 1 && options.tolerance > 0.0f,
             "the quadrature volume, iteration count and tolerance must be > 0");
  if (n == 0) return;
  with_map_evaluator(map, kernel, exec.backend, [&](const auto& evaluator) {
    for_each_bounded(
        exec, n, count,
        EulerianPoint<std::decay_t<decltype(evaluator)>>{evaluator, xhat.data(), vhat.data(), occupancy, density,
                                                         volume, options, x, X_guess, F_guess, out});
  });
}

namespace {

struct ClearLastMass {
  Span<QuadratureTally> tally;
  ROMP_HD void operator()(Index) const { tally[0].last_mass = 0.0; }
};

struct TallyPoint {
  EulerianPointsOut points;
  Span<QuadratureTally> tally;
  // Warp-aggregated: every point adds to the same few totals.
  ROMP_HD void operator()(Index i) const {
    QuadratureTally& total = tally[0];
    const std::int32_t status = points.status[i];
    for (int k = 0; k < 3; ++k) atomic_add_to_total(&total.points[k], std::int64_t(status == k ? 1 : 0));
    atomic_add_to_total(&total.iterations, std::int64_t(points.iterations[i]));
    atomic_add_to_total(&total.evaluations, std::int64_t(points.evaluations[i]));
    atomic_add_to_total(&total.jacobian_evaluations, std::int64_t(points.jacobian_evaluations[i]));
    atomic_add_to_total(&total.last_mass, double(points.mass[i]));
  }
};

}  // namespace

void tally_quadrature(const Exec& exec, const EulerianPointsOut& out, Index n, Span<QuadratureTally> tally,
                      Span<const std::int64_t> count) {
  ROMP_CHECK(out.status.size() >= n && out.iterations.size() >= n && out.evaluations.size() >= n &&
                 out.jacobian_evaluations.size() >= n && out.mass.size() >= n && tally.size() == 1,
             "tally_quadrature: a status, iteration and evaluation count and mass for each of the n points, one "
             "tally");
  for_each(exec, 1, ClearLastMass{tally});
  for_each_bounded(exec, n, count, TallyPoint{out, tally});
}

}  // namespace romp::rom
