// SampleNeighbourhood: keys of the nodes and cells around the samples, sorted and made unique on the
// device; the Eulerian points of those cells, pruned and compacted there.
#include "kernels/rom/sample_neighbourhood.h"

#include <climits>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"
#include "kernels/core/gather_planes.h"
#include "kernels/math/mat3.h"
#include "kernels/mpm/bspline.h"
#include "kernels/rom/stencil_neighbours.h"

namespace romp::rom {
namespace {

// Sorts after every node's key (node coordinates stay below 2^21).
constexpr std::uint64_t kNoNode = UINT64_MAX;
constexpr int kNearWidth = 5;   // base nodes within 2 of the sample's, per axis
constexpr int kCellsWidth = 6;  // cells B − 2 .. B + 3, per axis

// The keys of the width³ nodes (or cells) base − 2 .. base − 3 + width per axis around each sample's
// base node, kNoNode for those outside [0, upper) on some axis; and the sample of each.
struct KeysAroundSamples {
  Vec3Planes<const float> x;
  float inverse_dx;
  int width;
  int upper[3];
  Span<std::uint64_t> keys;
  Span<std::int32_t> samples;
  ROMP_HD void operator()(Index t) const {
    const int per_sample = width * width * width;
    const Index s = t / per_sample;
    const int j = int(t % per_sample);
    const mpm::QuadraticStencil<float> stencil(x.load(s), inverse_dx);
    const int offset[3] = {j / (width * width), j / width % width, j % width};
    int at[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      at[a] = stencil.base[a] + offset[a] - 2;
      inside = inside && at[a] >= 0 && at[a] < upper[a];
    }
    keys[t] = inside ? node_key(at[0], at[1], at[2]) : kNoNode;
    samples[t] = std::int32_t(s);
  }
};

// 1 at the first of each run of equal keys (sorted), 0 elsewhere and at kNoNode.
struct FirstOfEachKey {
  Span<const std::uint64_t> keys;
  Span<std::int32_t> first;
  ROMP_HD void operator()(Index t) const {
    first[t] = keys[t] != kNoNode && (t == 0 || keys[t] != keys[t - 1]) ? 1 : 0;
  }
};

struct EulerianCandidate {
  Span<const std::uint64_t> cell_keys;    // sorted
  Span<const std::int32_t> cell_samples;  // the sample of each, the first in sample order
  Span<const std::int32_t> cells;         // the positions of the unique cells in cell_keys (a bound on them)
  Span<const std::int64_t> cell_count;    // how many there are, on the device
  Span<const std::uint64_t> near;         // empty: no pruning
  Vec3Planes<const float> X_s, x_s;
  Mat3Planes<const float> F_s;
  int l;
  float dx;
  Vec3Planes<float> x, X_guess;
  Mat3Planes<float> F_guess;
  Span<std::uint64_t> place_cell;
  Span<std::int32_t> place_sub;
  Span<std::int32_t> keep;

  ROMP_HD void operator()(Index t) const {
    const int per_cell = l * l * l;
    if (t >= cell_count[0] * per_cell) {  // past the cells found: not a point
      keep[t] = 0;
      return;
    }
    const Index at = cells[t / per_cell];
    const int sub_index = int(t % per_cell);
    const std::uint64_t key = cell_keys[at];
    const Index s = cell_samples[at];
    const int cell[3] = {int(key >> 42), int((key >> 21) & 0x1fffff), int(key & 0x1fffff)};
    const int sub[3] = {sub_index / (l * l), sub_index / l % l, sub_index % l};
    const Vec3<float> sample_x = x_s.load(s), sample_X = X_s.load(s);
    Vec3<double> offset;
    Vec3<float> point;
    for (int a = 0; a < 3; ++a) {
      const double position = (cell[a] + (sub[a] + 0.5) / l) * dx;
      point[a] = float(position);
      offset[a] = position - sample_x[a];
    }
    if (!near.empty()) {
      const mpm::QuadraticStencil<float> stencil(point, 1.0f / dx);
      const int* b = stencil.base;
      keep[t] = sorted_contains(near, node_key(b[0], b[1], b[2])) ? 1 : 0;
    } else {
      keep[t] = 1;
    }
    const Mat3<float> F = F_s.load(s);
    Mat3<double> F_d;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) F_d(r, c) = F(r, c);
    // F⁻¹ (x − x_s), or x − x_s itself where F is inverted or singular.
    Vec3<double> step = offset;
    solve_where_positive(F_d, offset, step);
    x.store(t, point);
    place_cell[t] = key;
    place_sub[t] = sub_index;
    X_guess.store(
        t, Vec3<float>(float(sample_X[0] + step[0]), float(sample_X[1] + step[1]), float(sample_X[2] + step[2])));
    F_guess.store(t, F);
  }
};

}  // namespace

Span<const std::uint64_t> SampleNeighbourhood::near_bases(const Exec& exec, Vec3Planes<const float> x,
                                                          float inverse_dx) {
  const Index n = kNearWidth * kNearWidth * kNearWidth * x.count();
  keys_.ensure_size(exec.backend, n);
  samples_.ensure_size(exec.backend, n);
  // Nodes below 0 hold no point's base: the engine keeps particles a cell inside the domain.
  for_each(exec, n,
           KeysAroundSamples{x, inverse_dx, kNearWidth, {INT_MAX, INT_MAX, INT_MAX}, keys_.span(), samples_.span()});
  return sort_near_(exec, keys_.prefix(n), samples_.prefix(n)).first;
}

bool SampleNeighbourhood::counts_on_device(Index samples, const EulerianLattice& lattice) {
  const Index l = lattice.points_per_cell;
  return Index(kCellsWidth) * kCellsWidth * kCellsWidth * samples * l * l * l <= lattice.candidates_without_count;
}

SampleNeighbourhood::Points SampleNeighbourhood::build_eulerian_points(const Exec& exec, Vec3Planes<const float> X,
                                                                       Vec3Planes<const float> x,
                                                                       Mat3Planes<const float> F,
                                                                       const EulerianLattice& lattice) {
  const Index m = x.count();
  ROMP_CHECK(X.count() == m && F.count() == m, "the samples' X, x and F need one entry per sample");
  ROMP_CHECK(lattice.dx > 0.0f && lattice.points_per_cell >= 1, "Eulerian points need dx > 0 and ℓ >= 1");
  const float inverse_dx = 1.0f / lattice.dx;
  const Span<const std::uint64_t> near = lattice.prune ? near_bases(exec, x, inverse_dx) : Span<const std::uint64_t>();

  // The cells around each sample, sorted by key (stably: the first of a run is the first sample that
  // found the cell), and the first of each run.
  const Index pairs = kCellsWidth * kCellsWidth * kCellsWidth * m;
  keys_.ensure_size(exec.backend, pairs);
  samples_.ensure_size(exec.backend, pairs);
  const int* cells_below = lattice.domain_cells;
  for_each(
      exec, pairs,
      KeysAroundSamples{
          x, inverse_dx, kCellsWidth, {cells_below[0], cells_below[1], cells_below[2]}, keys_.span(), samples_.span()});
  const auto [cell_keys, cell_samples] = sort_cells_(exec, keys_.prefix(pairs), samples_.prefix(pairs));
  flags_.ensure_size(exec.backend, pairs);
  chosen_.ensure_size(exec.backend, pairs);
  for_each(exec, pairs, FirstOfEachKey{cell_keys, flags_.prefix(pairs)});
  const Span<const std::int64_t> cell_count =
      select_cells_.select_on_device(exec, flags_.prefix(pairs), 1, chosen_.span());

  // ℓ³ candidates per cell, then those kept, compacted. For few samples the candidates' storage and launch
  // cover every cell the samples could have found (their pairs), so the cells' count stays on the device;
  // for many, whose bound would be far above the cells they share, it is read back.
  const int l = lattice.points_per_cell;
  const Index cells = counts_on_device(m, lattice) ? pairs : Index(download(exec.backend, cell_count, exec.stream)[0]);
  const Index candidates = cells * Index(l) * l * l;
  candidates_.ensure_size(exec.backend, 15 * candidates);
  candidate_cells_.ensure_size(exec.backend, candidates);
  candidate_subs_.ensure_size(exec.backend, candidates);
  flags_.ensure_size(exec.backend, candidates);
  kept_.ensure_size(exec.backend, candidates);
  float* base = candidates_.data();
  for_each(exec, candidates,
           EulerianCandidate{cell_keys, cell_samples, chosen_.prefix(cells), cell_count, near, X, x, F, l, lattice.dx,
                             Vec3Planes<float>(base, candidates), Vec3Planes<float>(base + 3 * candidates, candidates),
                             Mat3Planes<float>(base + 6 * candidates, candidates), candidate_cells_.prefix(candidates),
                             candidate_subs_.prefix(candidates), flags_.prefix(candidates)});
  candidate_count_ = candidates;
  kept_count_ = select_kept_.select_on_device(exec, flags_.prefix(candidates), 1, kept_.span());
  return {candidates, kept_count_};
}

void SampleNeighbourhood::write_eulerian_points(const Exec& exec, Vec3Planes<float> x, Vec3Planes<float> X_guess,
                                                Mat3Planes<float> F_guess, Span<std::uint64_t> place_cell,
                                                Span<std::int32_t> place_sub) const {
  const Index c = candidate_count_;
  ROMP_CHECK(
      x.count() == c && X_guess.count() == c && F_guess.count() == c && place_cell.size() == c && place_sub.size() == c,
      "write_eulerian_points: room for the last build's bound on its points");
  const float* base = candidates_.data();
  const Span<const std::int32_t> kept = kept_.prefix(c);
  const Span<const std::int64_t> n = kept_count_;
  GatheredArrays arrays;
  arrays.add(Span<const float>(base, 3 * c), Span<float>(x.data(), 3 * c), 3);
  arrays.add(Span<const float>(base + 3 * c, 3 * c), Span<float>(X_guess.data(), 3 * c), 3);
  arrays.add(Span<const float>(base + 6 * c, 9 * c), Span<float>(F_guess.data(), 9 * c), 9);
  arrays.add(candidate_cells_.prefix(c), place_cell, 1).add(candidate_subs_.prefix(c), place_sub, 1);
  gather_arrays(exec, arrays, c, kept, n);
}

}  // namespace romp::rom
