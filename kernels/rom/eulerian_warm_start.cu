// Warm starts of the Eulerian inversion: each point looks its place up among the last build's points.
#include "kernels/rom/eulerian_warm_start.h"

#include "kernels/core/atomic.h"
#include "kernels/core/error.h"
#include "kernels/core/for_each.h"

namespace romp::rom {
namespace {

struct WarmStart {
  Inversions last;
  Span<const float> xhat;
  Span<const std::uint64_t> cell;
  Span<const std::int32_t> sub;
  Vec3Planes<float> X_guess;
  Mat3Planes<float> F_guess;
  Span<QuadratureTally> tally;

  // The last build's index of the place (cell, sub), or −1: a binary search in its (cell, sub) order.
  ROMP_HD Index last_index(std::uint64_t c, std::int32_t s) const {
    const Index points = last.points();
    Index low = 0, high = points;
    while (low < high) {
      const Index middle = low + (high - low) / 2;
      const bool before = last.cell[middle] < c || (last.cell[middle] == c && last.sub[middle] < s);
      if (before)
        low = middle + 1;
      else
        high = middle;
    }
    return low < points && last.cell[low] == c && last.sub[low] == s ? low : -1;
  }

  ROMP_HD void operator()(Index i) const {
    const Index j = last_index(cell[i], sub[i]);
    const bool warm = j >= 0 && last.status[j] == kQuadratureUsed;
    atomic_add_to_total(&tally[0].warm_starts, std::int64_t(warm ? 1 : 0));
    if (!warm) return;
    // α = (x̂ − x̂_last) · v̂_last / |v̂_last|²: the same for every point, and r is a few values.
    float step_along = 0.0f, speed_squared = 0.0f;
    for (Index k = 0; k < xhat.size(); ++k) {
      step_along += (xhat[k] - last.xhat[k]) * last.vhat[k];
      speed_squared += last.vhat[k] * last.vhat[k];
    }
    const float alpha = speed_squared > 0.0f ? step_along / speed_squared : 0.0f;
    const Vec3<float> X = last.X.load(j);
    const Mat3<float> F = last.F.load(j);
    // X_last − α F⁻¹ v_last; X_last itself where F is inverted or singular.
    Vec3<float> shift = Vec3<float>::zero();
    solve_where_positive(F, alpha * last.v.load(j), shift);
    X_guess.store(i, X - shift);
    F_guess.store(i, F);
  }
};

// One point per thread (and x̂, v̂ by the first r threads).
struct KeepInversions {
  Inversions now;
  InversionsOut kept;
  ROMP_HD void operator()(Index i) const {
    if (i < now.xhat.size()) {
      kept.xhat[i] = now.xhat[i];
      kept.vhat[i] = now.vhat[i];
    }
    if (i == 0 && !now.count.empty()) kept.count[0] = now.count[0];
    if (i >= now.points()) return;
    kept.cell[i] = now.cell[i];
    kept.sub[i] = now.sub[i];
    kept.status[i] = now.status[i];
    kept.X.store(i, now.X.load(i));
    kept.v.store(i, now.v.load(i));
    kept.F.store(i, now.F.load(i));
  }
};

}  // namespace

void warm_start_inversions(const Exec& exec, const Inversions& last, Span<const float> xhat,
                           Span<const std::uint64_t> cell, Span<const std::int32_t> sub, Vec3Planes<float> X_guess,
                           Mat3Planes<float> F_guess, Span<QuadratureTally> tally, Span<const std::int64_t> count) {
  const Index n = cell.size(), m = last.cell.size();
  ROMP_CHECK(sub.size() == n && X_guess.count() == n && F_guess.count() == n,
             "warm_start_inversions: a place and a guess for each point");
  ROMP_CHECK(last.sub.size() == m && last.status.size() == m && last.X.count() == m && last.v.count() == m &&
                 last.F.count() == m,
             "warm_start_inversions: the last build's places, statuses and solutions, one each per point");
  ROMP_CHECK(xhat.size() == last.xhat.size() && last.vhat.size() == xhat.size() && tally.size() == 1,
             "warm_start_inversions: x̂ now and x̂, v̂ then of one latent size, one tally");
  if (n == 0) return;
  for_each_bounded(exec, n, count, WarmStart{last, xhat, cell, sub, X_guess, F_guess, tally});
}

void keep_inversions(const Exec& exec, const Inversions& now, const InversionsOut& kept) {
  const Index n = now.cell.size();
  ROMP_CHECK(now.sub.size() == n && now.status.size() == n && now.X.count() == n && now.v.count() == n &&
                 now.F.count() == n && kept.cell.size() == n && kept.sub.size() == n && kept.status.size() == n &&
                 kept.X.count() == n && kept.v.count() == n && kept.F.count() == n,
             "keep_inversions: a place, status and solution of each point, kept in buffers of the same count");
  ROMP_CHECK(
      now.vhat.size() == now.xhat.size() && kept.xhat.size() == now.xhat.size() && kept.vhat.size() == now.xhat.size(),
      "keep_inversions: x̂ and v̂ of the map's latent size");
  ROMP_CHECK(now.count.size() == kept.count.size(), "keep_inversions: a count kept where the points have one");
  const Index threads = n > now.xhat.size() ? n : now.xhat.size();
  if (threads > 0) for_each(exec, threads, KeepInversions{now, kept});
}

}  // namespace romp::rom
