// SampleNeighbourhood: the grid nodes and cells around the hyper-reduction samples, found on the
// device from the samples' state there, so that a reduced substep reads none of it back to the host.
//
// near_bases: the nodes within 2 (per axis) of a sample's base node. Two quadratic B-spline stencils
// share a node exactly when their base nodes are at most 2 apart on every axis, so a point whose base
// node is one of these reaches a grid node some sample reads (stencil_neighbours.h).
//
// Eulerian points (ROM paper, Alg. 4, step 3): a point in cell c has its stencil's base node at c − 1
// or c, so it reaches nodes c − 1 .. c + 2; the nodes of a sample with base node B are B .. B + 2,
// reached from cells B − 2 .. B + 3. Each such cell (once, with the first sample in sample order that
// finds it) gets ℓ³ points at (c + (i + ½)/ℓ) dx; with pruning, only those whose base node is near a
// sample are kept (the others add only to nodes no sample reads, about 40 % of them at ℓ = 2). Each
// keeps, as the first guess of its inversion, the linearisation of g at its cell's sample:
// X_s + F_s⁻¹ (x − x_s) (x − x_s itself if F_s is singular or inverted) and ∇_X g ≈ F_s.
#pragma once

#include <cstdint>

#include "kernels/core/device_buffer.h"
#include "kernels/core/exec.h"
#include "kernels/core/index_select.h"
#include "kernels/core/pair_sort.h"
#include "kernels/core/span.h"
#include "kernels/math/mat3_planes.h"

namespace romp::rom {

struct EulerianLattice {
  float dx = 0.0f;
  int points_per_cell = 2;          // ℓ, per axis
  int domain_cells[3] = {0, 0, 0};  // cells outside [0, domain_cells) get no points
  bool prune = true;                // keep only the points whose base node is near a sample
  // Candidates up to which build_eulerian_points sizes them by the cells the samples could find, not by the
  // cells they found, so that the cells' count stays on the device: 216 ℓ³ per sample, 1,728 at ℓ = 2 (≈ 110 kB
  // each in the candidates' 64 B), so up to ≈ 600 samples at ℓ = 2 (the paper's 10 or 50, and 5 per
  // kinematic boundary). Above it the count is read back.
  Index candidates_without_count = Index(1) << 20;
};

class SampleNeighbourhood {
 public:
  // The keys (node_key) of the nodes near the samples at x, sorted; duplicates and keys that match no
  // node (UINT64_MAX, for nodes below 0) may be among them. Valid until the next call.
  Span<const std::uint64_t> near_bases(const Exec& exec, Vec3Planes<const float> x, float inverse_dx);

  // Builds the Eulerian points around the samples (reference X, current x, ∇_X g at F, m of each): their
  // count, on the device, and a bound on it for the launches that stop there (for_each_bounded). No download
  // for up to ≈ 600 samples at ℓ = 2 (the bound is then every cell the samples could find); above, the cells'
  // count is read back to size the candidates.
  struct Points {
    Index bound = 0;
    Span<const std::int64_t> count;  // valid until the next build
  };
  // Whether a build for `samples` samples keeps its count on the device (no download).
  static bool counts_on_device(Index samples, const EulerianLattice& lattice);
  Points build_eulerian_points(const Exec& exec, Vec3Planes<const float> X, Vec3Planes<const float> x,
                               Mat3Planes<const float> F, const EulerianLattice& lattice);
  // Writes the points of the last build, the first count of `bound` slots of each: positions, first guesses
  // of X and of ∇_X g, and each point's place (its cell's key and its index among the cell's ℓ³ points),
  // which increase together: (cell, sub) in lexicographic order.
  void write_eulerian_points(const Exec& exec, Vec3Planes<float> x, Vec3Planes<float> X_guess,
                             Mat3Planes<float> F_guess, Span<std::uint64_t> place_cell,
                             Span<std::int32_t> place_sub) const;

 private:
  PairSorter sort_near_, sort_cells_;
  IndexSelector select_cells_, select_kept_;  // each keeps its count on the device until its next call
  DeviceBuffer<std::uint64_t> keys_;
  DeviceBuffer<std::int32_t> samples_, flags_, chosen_, kept_;
  DeviceBuffer<float> candidates_;               // per candidate point: x (3 planes), X guess (3), F guess (9)
  DeviceBuffer<std::uint64_t> candidate_cells_;  // and its place: cell key and index in the cell
  DeviceBuffer<std::int32_t> candidate_subs_;
  Index candidate_count_ = 0;            // the candidates' slots, and the bound on the points
  Span<const std::int64_t> kept_count_;  // the points, on the device
};

}  // namespace romp::rom
