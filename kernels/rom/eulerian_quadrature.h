// Eulerian quadrature for the ROM (ROM paper, Alg. 4): quadrature points fixed in the current
// configuration (ℓ per grid cell per axis) get their reference positions by inverting the deformation
// map, X = g⁻¹(x; x̂), and from there F = ∇_X g, v = (∂g/∂x̂) v̂ and the mass ρ₀ V / J.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/hd.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/math/vec3.h"
#include "kernels/rom/deformation_map_eval.h"

namespace romp::rom {

// Where the reference configuration has material: cells of side h over a box from `origin`, each
// holding 1 + the material index of the material point sampled in it, or 0 where there is none. With
// lattice sampling (a point at the centre of every cell of side h inside the body) the union of the
// occupied cells is exactly the sampled body.
struct ReferenceOccupancy {
  Vec3<float> origin = Vec3<float>::zero();
  float inverse_h = 0.0f;
  int cells[3] = {0, 0, 0};
  Span<const std::int32_t> material_plus_one;

  // The material at X, or −1 outside the body.
  ROMP_HD int material_at(const Vec3<float>& X) const {
    int cell[3];
    for (int a = 0; a < 3; ++a) {
      const float c = (X[a] - origin[a]) * inverse_h;
      if (!(c >= 0.0f && c < float(cells[a]))) return -1;  // also rejects NaN
      cell[a] = int(c);
    }
    return material_plus_one[(Index(cell[2]) * cells[1] + cell[1]) * cells[0] + cell[0]] - 1;
  }

  // Whether any cell within `margin` cells of X (per axis) holds material.
  ROMP_HD bool near(const Vec3<float>& X, int margin) const {
    int low[3], high[3];
    for (int a = 0; a < 3; ++a) {
      const float c = (X[a] - origin[a]) * inverse_h;
      if (!(c > -float(margin) && c < float(cells[a] + margin))) return false;  // also rejects NaN
      const int cell = int(c < 0.0f ? c - 1.0f : c);                            // floor
      low[a] = cell - margin < 0 ? 0 : cell - margin;
      high[a] = cell + margin >= cells[a] ? cells[a] - 1 : cell + margin;
    }
    for (int k = low[2]; k <= high[2]; ++k)
      for (int j = low[1]; j <= high[1]; ++j)
        for (int i = low[0]; i <= high[0]; ++i)
          if (material_plus_one[(Index(k) * cells[1] + j) * cells[0] + i] != 0) return true;
    return false;
  }
};

// How g is inverted: X ← X − α B⁻¹ (g(X) − x), α halved until the residual falls, with B Broyden's
// running estimate of ∇_X g from a first guess, replaced by the true ∇_X g where it gives no descent.
struct InversionOptions {
  int iterations = 20;
  float tolerance = 0.0f;  // m: converged when |g(X) − x| ≤ tolerance
  // A point whose first guess lies farther than this many occupancy cells from any material is dropped
  // without inverting g: most points of the cells around a sample lie outside the body, and the guess
  // (g linearised at the sample) is off by far less than this near it. On the tower's trained map the
  // guesses of the points used were off by at most 0.72 cells (700 substeps), and margins of 1, 2 and 3
  // kept exactly the same points (504 substeps), 2 with a fifth less inversion time than 3.
  int outside_margin = 2;
  // A point whose quasi-Newton step ends farther than this many occupancy cells from any material is dropped
  // then: the step's end is within a small fraction of a cell of where the point converges (its error is
  // the square of the guess's, relative to g's curvature), so such a point would end outside the body.
  int predicted_margin = 1;
};

// What happened to each quadrature point.
enum QuadratureStatus : std::int32_t { kQuadratureUsed = 0, kQuadratureOutside = 1, kQuadratureUnconverged = 2 };

struct EulerianPointsOut {
  Vec3Planes<float> X, v;
  Mat3Planes<float> F;
  Span<float> mass, volume0;  // ρ₀ V / J and V / J; 0 for dropped points
  Span<std::int32_t> material, status;
  Span<std::int32_t> iterations;  // iterations taken (0 for a guess already converged or not inverted)
  // Evaluations of g at the point, and those of them that also gave the Jacobians (three reverse sweeps
  // more each): the inversion's cost, which the tally sums (0 for a point not inverted).
  Span<std::int32_t> evaluations, jacobian_evaluations;
};

// For n points at x (current configuration) with first guesses X_guess and F_guess of X and of ∇_X g
// there (g linearised at a nearby point gives both): inverts g, looks the result up in `occupancy`, and
// writes the kinematics. Points that do not converge or land outside the body are dropped: mass and
// volume 0, F = I, v = 0, so they add nothing to a P2G. `density` holds ρ₀ per material; `volume` is
// each point's share of the current configuration (dx³ / ℓ³). xhat, vhat: r values on exec's backend.
// `kernel` chooses the map's evaluator (deformation_map_eval.h). `count`, where given, is a count on the
// device: only the first count[0] of the n points are inverted (n is then a bound), the rest left as they were.
void eulerian_quadrature(const Exec& exec, const DeformationMapView<float>& map, Span<const float> xhat,
                         Span<const float> vhat, const ReferenceOccupancy& occupancy, Span<const float> density,
                         float volume, const InversionOptions& options, Vec3Planes<const float> x,
                         Vec3Planes<const float> X_guess, Mat3Planes<const float> F_guess, const EulerianPointsOut& out,
                         MapKernel kernel = MapKernel::Fastest, Span<const std::int64_t> count = {});

// Running totals of the Eulerian quadrature, kept on the device so that a substep reads nothing back
// for them: the points by status (QuadratureStatus) and their inversion iterations since the run
// began, and the mass of the last call's points.
struct QuadratureTally {
  std::int64_t points[3] = {0, 0, 0};
  std::int64_t iterations = 0;
  std::int64_t evaluations = 0, jacobian_evaluations = 0;
  std::int64_t warm_starts = 0;  // points that started from their place's last inversion (eulerian_warm_start.h)
  double last_mass = 0.0;
};

// Adds the statuses, iterations and evaluations of the n points `out` holds to tally[0] and sets its
// last_mass to their mass. `count`, where given, is a count on the device: only the first count[0] add.
void tally_quadrature(const Exec& exec, const EulerianPointsOut& out, Index n, Span<QuadratureTally> tally,
                      Span<const std::int64_t> count = {});

}  // namespace romp::rom
