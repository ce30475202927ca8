// SampleNeighbourhood against a plain host reference of ROM paper's Alg. 4, step 3: the cells around
// each sample (once each, with the first sample that finds it), ℓ³ points per cell pruned to those whose
// base node lies within 2 of a sample's, and each point's first guess from its cell's sample. The
// device builds the same points (as a set: its order is the cells' key order) on the test backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "kernels/core/device_buffer.h"
#include "kernels/core/memory.h"
#include "kernels/math/mat3.h"
#include "kernels/mpm/bspline.h"
#include "kernels/rom/sample_neighbourhood.h"
#include "kernels/rom/stencil_neighbours.h"
#include "tests/support/test_exec.h"

namespace romp::rom {
namespace {

constexpr float kDx = 0.05f;

// One point: position, guess of X, guess of ∇_X g (15 floats), compared exactly.
using Point = std::array<float, 15>;

struct Samples {
  Index m = 0;
  std::vector<float> X, x, F;  // 3, 3, 9 planes of m
};

// Samples in a 20³-cell domain, two near its low corner (cells cut off), two sharing cells, one with a
// singular F (its guesses fall back to x − x_s).
Samples make_samples() {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
  const std::vector<std::array<float, 3>> at = {
      {0.06f, 0.07f, 0.52f}, {0.51f, 0.50f, 0.49f}, {0.53f, 0.52f, 0.50f}, {0.80f, 0.31f, 0.66f}, {0.3f, 0.9f, 0.2f}};
  Samples s;
  s.m = Index(at.size());
  s.X.resize(3 * s.m);
  s.x.resize(3 * s.m);
  s.F.resize(9 * s.m);
  for (Index i = 0; i < s.m; ++i) {
    for (int a = 0; a < 3; ++a) {
      s.x[a * s.m + i] = at[i][a];
      s.X[a * s.m + i] = at[i][a] - 0.02f + jitter(random) * 0.1f;
    }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) s.F[(3 * r + c) * s.m + i] = (r == c ? 1.0f : 0.0f) + jitter(random);
  }
  for (int e = 0; e < 9; ++e) s.F[e * s.m + 3] = 0.0f;  // singular
  return s;
}

std::multiset<Point> host_reference(const Samples& s, int l, bool prune) {
  const int domain = 20;
  auto position = [&](const std::vector<float>& planes, Index i) {
    return Vec3<float>(planes[i], planes[s.m + i], planes[2 * s.m + i]);
  };
  std::set<std::array<int, 3>> near;
  std::map<std::array<int, 3>, Index> cell_sample;  // the first sample to find each cell
  for (Index i = 0; i < s.m; ++i) {
    const mpm::QuadraticStencil<float> stencil(position(s.x, i), 1.0f / kDx);
    const int* b = stencil.base;
    for (int u = -2; u <= 2; ++u)
      for (int v = -2; v <= 2; ++v)
        for (int w = -2; w <= 2; ++w) near.insert({b[0] + u, b[1] + v, b[2] + w});
    for (int u = -2; u <= 3; ++u)
      for (int v = -2; v <= 3; ++v)
        for (int w = -2; w <= 3; ++w) {
          const std::array<int, 3> c = {b[0] + u, b[1] + v, b[2] + w};
          if (std::all_of(c.begin(), c.end(), [&](int k) { return k >= 0 && k < domain; })) cell_sample.emplace(c, i);
        }
  }
  std::multiset<Point> points;
  for (const auto& [c, i] : cell_sample) {
    Mat3<double> F;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) F(r, k) = s.F[(3 * r + k) * s.m + i];
    const double det = determinant(F);
    for (int u = 0; u < l; ++u)
      for (int v = 0; v < l; ++v)
        for (int w = 0; w < l; ++w) {
          const int sub[3] = {u, v, w};
          Point p;
          Vec3<double> offset;
          Vec3<float> x;
          for (int a = 0; a < 3; ++a) {
            const double at = (c[a] + (sub[a] + 0.5) / l) * kDx;
            x[a] = float(at);
            offset[a] = at - s.x[a * s.m + i];
          }
          const mpm::QuadraticStencil<float> stencil(x, 1.0f / kDx);
          if (prune && !near.count({stencil.base[0], stencil.base[1], stencil.base[2]})) continue;
          const Vec3<double> step =
              det > 0.0 ? (offset[0] * cross(F.row(1), F.row(2)) + offset[1] * cross(F.row(2), F.row(0)) +
                           offset[2] * cross(F.row(0), F.row(1))) *
                              (1.0 / det)
                        : offset;
          for (int a = 0; a < 3; ++a) {
            p[a] = x[a];
            p[3 + a] = float(s.X[a * s.m + i] + step[a]);
          }
          for (int e = 0; e < 9; ++e) p[6 + e] = s.F[e * s.m + i];
          points.insert(p);
        }
  }
  return points;
}

// `counted`: the cells' count read back to size the candidates (many samples), else bounded by the cells the
// samples could find (few samples: no count read back).
std::multiset<Point> device_points(SampleNeighbourhood& neighbourhood, const Samples& s, int l, bool prune,
                                   bool counted) {
  const Exec& exec = test::exec();
  const auto X = DeviceBuffer<float>::from_host(exec.backend, s.X, exec.stream);
  const auto x = DeviceBuffer<float>::from_host(exec.backend, s.x, exec.stream);
  const auto F = DeviceBuffer<float>::from_host(exec.backend, s.F, exec.stream);
  EulerianLattice lattice;
  lattice.dx = kDx;
  lattice.points_per_cell = l;
  for (int& cells : lattice.domain_cells) cells = 20;
  lattice.prune = prune;
  if (counted) lattice.candidates_without_count = 0;
  const memory::Traffic before = memory::traffic();
  const SampleNeighbourhood::Points built = neighbourhood.build_eulerian_points(
      exec, Vec3Planes<const float>(X.data(), s.m), Vec3Planes<const float>(x.data(), s.m),
      Mat3Planes<const float>(F.data(), s.m), lattice);
  EXPECT_EQ(memory::traffic().downloads - before.downloads, counted ? 1 : 0);
  const Index bound = built.bound, n = download(exec.backend, built.count)[0];
  EXPECT_LE(n, bound);
  if (!counted) EXPECT_EQ(bound, 6 * 6 * 6 * Index(l) * l * l * s.m);
  DeviceBuffer<float> out(exec.backend, 15 * bound);
  DeviceBuffer<std::uint64_t> place_cell(exec.backend, bound);
  DeviceBuffer<std::int32_t> place_sub(exec.backend, bound);
  neighbourhood.write_eulerian_points(
      exec, Vec3Planes<float>(out.data(), bound), Vec3Planes<float>(out.data() + 3 * bound, bound),
      Mat3Planes<float>(out.data() + 6 * bound, bound), place_cell.span(), place_sub.span());
  const std::vector<float> host = out.to_host(exec.stream);
  const std::vector<std::uint64_t> cells = place_cell.to_host(exec.stream);
  const std::vector<std::int32_t> subs = place_sub.to_host(exec.stream);
  std::multiset<Point> points;
  for (Index q = 0; q < n; ++q) {
    Point p;
    for (int e = 0; e < 15; ++e) p[e] = host[e * bound + q];
    points.insert(p);
    // The place names the point: x = (cell + (sub's digit + ½) / ℓ) dx per axis, and places increase.
    const int cell[3] = {int(cells[q] >> 42), int((cells[q] >> 21) & 0x1fffff), int(cells[q] & 0x1fffff)};
    const int digit[3] = {subs[q] / (l * l), subs[q] / l % l, subs[q] % l};
    for (int a = 0; a < 3; ++a) EXPECT_FLOAT_EQ(p[a], float((cell[a] + (digit[a] + 0.5) / l) * kDx)) << q;
    if (q > 0) EXPECT_TRUE(cells[q - 1] < cells[q] || (cells[q - 1] == cells[q] && subs[q - 1] < subs[q])) << q;
  }
  return points;
}

TEST(SampleNeighbourhood, BuildsTheHostReferencesEulerianPoints) {
  const Samples samples = make_samples();
  SampleNeighbourhood neighbourhood;
  for (const int l : {1, 2, 3})
    for (const bool prune : {true, false})
      for (const bool counted : {false, true}) {
        const std::multiset<Point> expected = host_reference(samples, l, prune);
        ASSERT_GT(expected.size(), 100u);
        // Rebuilt with the same object: its kept buffers must not carry the last build's points over.
        EXPECT_TRUE(device_points(neighbourhood, samples, l, prune, counted) == expected)
            << "l = " << l << ", prune = " << prune << ", counted = " << counted;
      }
}

TEST(SampleNeighbourhood, NearBasesAreTheNodesWithinTwoOfEverySamplesBase) {
  const Samples samples = make_samples();
  const Exec& exec = test::exec();
  const auto x = DeviceBuffer<float>::from_host(exec.backend, samples.x, exec.stream);
  SampleNeighbourhood neighbourhood;
  const Span<const std::uint64_t> near =
      neighbourhood.near_bases(exec, Vec3Planes<const float>(x.data(), samples.m), 1.0f / kDx);
  const std::vector<std::uint64_t> keys = download(exec.backend, near, exec.stream);
  EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
  std::set<std::uint64_t> expected;
  for (Index i = 0; i < samples.m; ++i) {
    const mpm::QuadraticStencil<float> stencil(
        Vec3<float>(samples.x[i], samples.x[samples.m + i], samples.x[2 * samples.m + i]), 1.0f / kDx);
    for (int u = -2; u <= 2; ++u)
      for (int v = -2; v <= 2; ++v)
        for (int w = -2; w <= 2; ++w) {
          const int b[3] = {stencil.base[0] + u, stencil.base[1] + v, stencil.base[2] + w};
          if (b[0] >= 0 && b[1] >= 0 && b[2] >= 0) expected.insert(node_key(b[0], b[1], b[2]));
        }
  }
  std::set<std::uint64_t> found;
  for (const std::uint64_t key : keys)
    if (key != UINT64_MAX) found.insert(key);
  EXPECT_EQ(found, expected);
}

}  // namespace
}  // namespace romp::rom
