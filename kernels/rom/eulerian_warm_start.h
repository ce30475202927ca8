// Warm starts of the Eulerian inversion (ROM paper, Alg. 4). An Eulerian point has a fixed place in the
// current configuration: its cell of the grid and its index among the cell's ℓ³ points. A point at a place
// that was also inverted in the last build starts from where that inversion ended, moved by how x̂ moved
// since: g(X_last; x̂) ≈ x + (∂g/∂x̂)(x̂ − x̂_last), and (∂g/∂x̂) v̂_last is the point's velocity v_last then,
// so with x̂ − x̂_last ≈ α v̂_last (α the step's projection on v̂_last; α = Δt for the velocity-only
// projection at a steady v̂) the first guess is X_last − α F_last⁻¹ v_last with ∇_X g ≈ F_last: off by the
// change of v̂ over a substep, where the guess from the cell's sample (g linearised up to three cells away)
// is off by g's curvature over that distance. A point seen for the first time keeps the sample's guess.
#pragma once

#include <cstdint>

#include "kernels/core/exec.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"
#include "kernels/rom/eulerian_quadrature.h"

namespace romp::rom {

// The inverted points of a build, in SampleNeighbourhood's order (increasing (cell, sub)), and its x̂ and v̂:
// read (Inversions) and written (InversionsOut).
struct Inversions {
  Span<const std::uint64_t> cell;   // node_key of the point's cell
  Span<const std::int32_t> sub;     // its index among the cell's ℓ³ points
  Span<const std::int32_t> status;  // QuadratureStatus: only kQuadratureUsed points are starts
  Vec3Planes<const float> X, v;
  Mat3Planes<const float> F;
  Span<const float> xhat, vhat;  // the build's x̂ and v̂ (r values each)
  // Where given, a count on the device: only the first count[0] entries are points (the spans' size is a bound).
  Span<const std::int64_t> count;
  ROMP_HD Index points() const { return count.empty() ? cell.size() : count[0]; }
};
struct InversionsOut {
  Span<std::uint64_t> cell;
  Span<std::int32_t> sub, status;
  Vec3Planes<float> X, v;
  Mat3Planes<float> F;
  Span<float> xhat, vhat;
  Span<std::int64_t> count;  // given where the Inversions' count is: receives it
};

// For each point i at (cell[i], sub[i]) that `last` holds as used, replaces X_guess[i] and F_guess[i] with
// the warm start above (x̂: this build's), and adds their number to tally[0].warm_starts. `count`, where
// given, is a count on the device: only the first count[0] points (cell.size() a bound) are looked up.
void warm_start_inversions(const Exec& exec, const Inversions& last, Span<const float> xhat,
                           Span<const std::uint64_t> cell, Span<const std::int32_t> sub, Vec3Planes<float> X_guess,
                           Mat3Planes<float> F_guess, Span<QuadratureTally> tally, Span<const std::int64_t> count = {});

// Copies this build's points and x̂, v̂ (`now`) to `kept`, of the same sizes, in one launch: the points'
// buffers are refilled by the next build before its warm starts read the last one's. With now.count, only
// the counted points are copied, and the count with them.
void keep_inversions(const Exec& exec, const Inversions& now, const InversionsOut& kept);

}  // namespace romp::rom
